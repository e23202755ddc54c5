# Sourced by the benchmarks that time slicers (compare_slicers.sh, compare_supports.sh); needs
# $work (a scratch folder) and $repeat (runs per command).
# Runs a command $repeat times under /usr/bin/time; leaves the figures "wall_s user_s sys_s
# peak_kib" of the run with the median wall time in $work/time (CPU time, user + system over
# all threads, is what a busy machine does not inflate).
timed() {
  : >"$work/times"
  for ((run = 0; run < repeat; run++)); do
    /usr/bin/time -f "%e %U %S %M" -o "$work/time" "$@" >"$work/log" 2>&1 || {
      echo "${0##*/}: failed: $*" >&2; tail -5 "$work/log" >&2; exit 1; }
    cat "$work/time" >>"$work/times"
  done
  sort -n "$work/times" | sed -n "$(((repeat + 1) / 2))p" >"$work/time"
}
