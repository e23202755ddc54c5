#!/usr/bin/env bash
# How far the plan line's uniform estimates (app/uniform_estimate.h) stand from slicing
# uniformly: per model, `mahost slice --adaptive --tolerance T` says "estimated X
# against Y at uniform t mm (n layers) and ..."; each Y is set beside the estimate of the same
# part sliced uniformly at t with the same options and contour. Models: the bunny (50 mm,
# with and without supports and raft), a sphere (r 15 mm), a T (a 50 mm bar on a 10 mm stem,
# supports and raft), a frustum (r 20 to 2 mm, 30 mm), and tests/bench/models/{steps,dome,vase}.
#
# Usage: tests/bench/estimate_accuracy.sh [BUILD_DIR]     (default build; needs openscad)
set -euo pipefail
cd "$(dirname "$0")/../.."
build=${1:-build}
[[ $build = /* ]] || build=$(pwd)/$build
mahost=$build/mahost
[[ -x $mahost ]] || { echo "estimate_accuracy: $mahost not found; build first (scripts/build)" >&2; exit 2; }
command -v openscad >/dev/null || { echo "estimate_accuracy: openscad not found; run scripts/setup --bench" >&2; exit 2; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

echo 'sphere(r = 15, $fn = 96);' >"$work/sphere.scad"
echo 'union() { translate([-5, -5, 0]) cube([10, 10, 20]); translate([-25, -5, 20]) cube([50, 10, 5]); }' >"$work/tee.scad"
echo 'cylinder(r1 = 20, r2 = 2, h = 30, $fn = 96);' >"$work/frustum.scad"
for m in sphere tee frustum; do openscad -o "$work/$m.stl" "$work/$m.scad" >/dev/null 2>&1; done
for m in steps dome vase; do openscad -o "$work/$m.stl" "tests/bench/models/$m.scad" >/dev/null 2>&1; done

seconds() {  # "1 h 2 min 3 s" -> 3723
  local total=0 value unit
  set -- $1
  while (($# >= 2)); do
    value=$1 unit=$2; shift 2
    case $unit in h) total=$((total + 3600 * value)) ;; min) total=$((total + 60 * value)) ;; s) total=$((total + value)) ;; esac
  done
  echo "$total"
}

printf '%-34s %6s %6s %9s %9s %7s\n' "model, options, tolerance" "t mm" layers "plan line" "sliced" error
row() {  # name tolerance model-and-options...
  local name=$1 tolerance=$2
  shift 2
  local line
  line=$("$mahost" slice "$@" --adaptive --tolerance "$tolerance" -o "$work/a.gcode" 2>&1 | grep '^adaptive:')
  grep -oE '(against|and) ([0-9]+ (h|min|s) ?)+at uniform [0-9.]+ mm \([0-9]+ layers\)' <<<"$line" |
    while read -r _ rest; do
      local said=${rest%% at uniform*} t layers full
      t=$(sed -E 's/.*at uniform ([0-9.]+) mm.*/\1/' <<<"$rest")
      layers=$(sed -E 's/.*\(([0-9]+) layers\).*/\1/' <<<"$rest")
      full=$("$mahost" slice "$@" --layer "$t" -o "$work/u.gcode" 2>&1 |
        sed -nE 's/.*estimated print time (([0-9]+ (h|min|s) ?)+),.*/\1/p' | head -1)
      local a b
      a=$(seconds "$said") b=$(seconds "$full")
      printf '%-34s %6s %6s %8ss %8ss %+6.1f%%\n' "$name $tolerance" "$t" "$layers" "$a" "$b" \
        "$(echo "scale=4; 100 * ($a - $b) / $b" | bc)"
    done
}
bunny=(data/bunny.stl --up y --units m --height 50)
row "bunny, no supports" 0.3 "${bunny[@]}" --support none --no-raft
row "bunny, no supports" 0.4 "${bunny[@]}" --support none --no-raft
row "bunny, profile (supports, raft)" 0.3 "${bunny[@]}"
row "sphere, profile" 0.3 "$work/sphere.stl"
row "sphere, no supports" 0.2 "$work/sphere.stl" --support none --no-raft
row "T, profile" 0.2 "$work/tee.stl"
row "frustum" 0.2 "$work/frustum.stl" --no-raft
row "steps" 0.3 "$work/steps.stl" --no-raft
row "steps, profile" 0.15 "$work/steps.stl"
row "dome" 0.3 "$work/dome.stl" --no-raft
row "vase" 0.3 "$work/vase.stl" --no-raft
