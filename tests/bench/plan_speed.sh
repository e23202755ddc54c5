#!/usr/bin/env bash
# Adaptive slicing time: mahost's whole adaptive slice (planning the layers by the exact error,
# then slicing them with the default contour, best) against CuraEngine 4.13's adaptive slice
# of the same placed bunny (50 mm, --up y --units m), both without supports or raft, run by
# turns in the same run, REPEAT times each; the medians of wall and CPU time (user + system,
# all threads) and their ratio (mahost / CuraEngine: below 1, mahost is faster); and the median
# of mahost's planning alone (the wall time its plan line gives) against CuraEngine's whole wall.
#
# Usage: tests/bench/plan_speed.sh [BUILD_DIR]      (default build; absolute or in the repository)
#        PAIRS="0.4:0.3 0.3:0.2"  mahost --tolerance : CuraEngine adaptive_layer_height_threshold
#        REPEAT=7                 runs of each (default 7)
#        PRINTER=NAME             the printer profile both slice for (peer_slicers.sh; default
#                                 up-plus-2, 0.05 mm steps; generic-marlin's are 0.01 mm)
# Needs CuraEngine (scripts/setup) and Cura's definitions (tests/bench/cura_definitions.sh).
set -euo pipefail
cd "$(dirname "$0")/../.."
build=${1:-build}
[[ $build == /* ]] || build=$(pwd)/$build
mahost=$build/mahost
[[ -x $mahost ]] || { echo "plan_speed: $mahost not found; build first (scripts/build)" >&2; exit 2; }
command -v CuraEngine >/dev/null || { echo "plan_speed: CuraEngine not found; run scripts/setup" >&2; exit 2; }
pairs=${PAIRS:-0.4:0.3 0.3:0.2}
repeat=${REPEAT:-7}
[[ $repeat =~ ^[1-9][0-9]*$ ]] || { echo "plan_speed: REPEAT must be a whole number >= 1" >&2; exit 2; }

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
source tests/bench/peer_slicers.sh

placed=$work/bunny50.stl
"$mahost" info data/bunny.stl --up y --units m --height 50 --export "$placed" >/dev/null

# run FILE COMMAND...: appends "wall cpu" of one run to FILE.
run() {
  local file=$1
  shift
  local TIMEFORMAT="%R %U %S"
  { time "$@" >"$work/run.log" 2>&1; } 2>"$work/time" ||
    { echo "plan_speed: failed: $*" >&2; tail -3 "$work/run.log" >&2; exit 1; }
  awk '{ printf "%s %.3f\n", $1, $2 + $3 }' "$work/time" >>"$file"
}
median() { sort -n | awk '{ v[NR] = $1 } END { print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2 }'; }

printf '%-40s %10s %10s\n' run "wall, s" "CPU, s"
for pair in $pairs; do
  tolerance=${pair%%:*} threshold=${pair##*:}
  ours=$work/mahost-$tolerance theirs=$work/cura-$threshold
  : >"$ours"
  : >"$theirs"
  : >"$ours-plan"
  for ((k = 0; k < repeat; ++k)); do
    run "$ours" "$mahost" slice "$placed" --printer "$peer_printer" --adaptive --tolerance "$tolerance" --support none --no-raft \
      -o "$work/m.gcode"
    # The planning alone: the wall time the plan line gives ("planned in 2.3 s").
    sed -n 's/.*planned in \([0-9.]*\) s.*/\1/p' "$work/run.log" | head -1 >>"$ours-plan"
    run "$theirs" cura_adaptive "$work/c.gcode" "$placed" "$threshold"
  done
  plan_line=$("$mahost" slice "$placed" --printer "$peer_printer" --adaptive --tolerance "$tolerance" --support none --no-raft \
    -o "$work/m.gcode" 2>&1 | grep -m1 '^adaptive:' | cut -c1-60)
  mw=$(cut -d' ' -f1 "$ours" | median) mc=$(cut -d' ' -f2 "$ours" | median)
  cw=$(cut -d' ' -f1 "$theirs" | median) cc=$(cut -d' ' -f2 "$theirs" | median)
  printf '%-40s %10.2f %10.2f\n' "mahost --tolerance $tolerance" "$mw" "$mc" \
    "CuraEngine threshold $threshold" "$cw" "$cc"
  mp=$(median <"$ours-plan")
  printf '%-40s %10.2f %10s\n' "  of which mahost's planning" "$mp" "-"
  printf '%-40s %10.2f %10s\n' "  ratio planning / CuraEngine" "$(awk -v a="$mp" -v b="$cw" 'BEGIN { print a / b }')" "-"
  printf '%-40s %10.2f %10.2f\n' "  ratio mahost / CuraEngine" "$(awk -v a="$mw" -v b="$cw" 'BEGIN { print a / b }')" \
    "$(awk -v a="$mc" -v b="$cc" 'BEGIN { print a / b }')"
  echo "  ($plan_line...)"
done
echo "printer $peer_printer; medians of $repeat runs each, alternated; load at the end: $(cut -d' ' -f1-3 /proc/loadavg)"
