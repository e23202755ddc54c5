#!/usr/bin/env bash
# CPU time of `mahost slice` per contour strategy against CuraEngine 4.13's on the bunny, the
# paper's part placed 50 mm tall (--up y --units m --height 50), with compare_slicers.sh's
# settings (the UP Plus 2, no support, no raft, one skirt loop). CPU time is user + system
# over all threads, which a machine shared with other work inflates less than wall time; the
# runs alternate (best, ma, mid, CuraEngine, best, ...) so that a busy spell hits all alike,
# and each figure is the median of RUNS. Prints each median and its ratio to CuraEngine's, and
# the median wall time beside it (mahost slices its layers in parallel, CuraEngine 4.13 too).
#
# Usage: tests/bench/contour_cpu.sh [BUILD_DIR]   (default: build; mahost must be built)
#        RUNS=N       runs of each (default 7)
#        LAYER=T      layer thickness, mm (default 0.15)
#        CONTOURS=... mahost's strategies (default "best ma mid")
#        BASELINE=DIR another build whose mahost runs best too, in the same alternation (a
#                     change's effect against the machine's load of the moment)
#        CALLGRIND=1  also counts each strategy's instructions once (valgrind --tool=callgrind,
#                     about a minute each): the same figure on a busy machine as on a quiet one
set -euo pipefail
cd "$(dirname "$0")/../.."
build=${1:-build}
runs=${RUNS:-7}
layer=${LAYER:-0.15}
contours=${CONTOURS:-best ma mid}
[[ $runs =~ ^[1-9][0-9]*$ ]] || { echo "contour_cpu: RUNS must be a whole number >= 1" >&2; exit 2; }
mahost=$build/mahost
[[ -x $mahost ]] || { echo "contour_cpu: $mahost not found; build first (scripts/build)" >&2; exit 2; }
baseline=${BASELINE:-}
if [[ -n $baseline && ! -x $baseline/mahost ]]; then
  echo "contour_cpu: $baseline/mahost not found" >&2; exit 2
fi
for tool in CuraEngine /usr/bin/time; do
  command -v "$tool" >/dev/null || { echo "contour_cpu: $tool not found; run scripts/setup" >&2; exit 2; }
done
if [[ ${CALLGRIND:-0} == 1 ]] && ! command -v valgrind >/dev/null; then
  echo "contour_cpu: CALLGRIND=1 needs valgrind" >&2; exit 2
fi

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
source tests/bench/cura_definitions.sh

model=$work/bunny50.stl
"$mahost" info data/bunny.stl --up y --units m --height 50 --export "$model" >/dev/null 2>&1
mahost_args=(slice data/bunny.stl --up y --units m --height 50 --layer "$layer" --support none --no-raft)
cura_command "$layer" "$model" "$work/cura.gcode"

# run NAME COMMAND...: one run under /usr/bin/time, its CPU seconds appended to $work/NAME,
# its wall seconds to $work/NAME.wall.
run() {
  local name=$1
  shift
  /usr/bin/time -f "%U %S %e" -o "$work/time" "$@" >"$work/log" 2>&1 || {
    echo "contour_cpu: failed: $*" >&2; tail -5 "$work/log" >&2; exit 1; }
  awk '{ printf "%.3f\n", $1 + $2 }' "$work/time" >>"$work/$name"
  awk '{ printf "%.3f\n", $3 }' "$work/time" >>"$work/$name.wall"
}
for ((i = 0; i < runs; i++)); do
  for contour in $contours; do run "$contour" "$mahost" "${mahost_args[@]}" --contour "$contour" -o "$work/$contour.gcode"; done
  [[ -z $baseline ]] || run baseline "$baseline/mahost" "${mahost_args[@]}" --contour best -o "$work/baseline.gcode"
  run cura "${cura[@]}"
done

median() { sort -n "$work/$1" | awk '{ v[NR] = $1 } END { print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2 }'; }
cura_cpu=$(median cura)
# row LABEL NAME: the medians of run NAME, its CPU time against CuraEngine's, and its CPU runs.
row() {
  printf '%-22s %8.2f %14.2f %8.2f   %s\n' "$1" "$(median "$2")" \
    "$(awk -v m="$(median "$2")" -v c="$cura_cpu" 'BEGIN { print m / c }')" "$(median "$2.wall")" \
    "$(sort -n "$work/$2" | tr '\n' ' ')"
}
echo "bunny 50 mm at $layer mm, no support: CPU seconds (user + system) and wall seconds, medians of $runs alternated runs"
printf '%-22s %8s %14s %8s   %s\n' slicer cpu "/ CuraEngine" wall "cpu runs"
for contour in $contours; do row "mahost ($contour)" "$contour"; done
if [[ -n $baseline ]]; then
  row "baseline (best)" baseline
  echo "baseline: $baseline/mahost; best's G-code $(cmp -s "$work/best.gcode" "$work/baseline.gcode" && echo identical || echo differs) (last run of each)"
fi
row "CuraEngine 4.13" cura

if [[ ${CALLGRIND:-0} == 1 ]]; then
  echo "instructions (callgrind, one run each):"
  for contour in $contours; do
    valgrind --tool=callgrind --callgrind-out-file="$work/callgrind.out" \
      "$mahost" "${mahost_args[@]}" --contour "$contour" -o "$work/$contour.gcode" 2>"$work/valgrind.log" >/dev/null
    printf '%-22s %s\n' "mahost ($contour)" "$(sed -n 's/.*Collected : //p' "$work/valgrind.log")"
  done
fi
