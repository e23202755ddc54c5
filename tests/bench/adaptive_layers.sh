#!/usr/bin/env bash
# Layer plans judged by our exact metrics: the peers' adaptive layer heights beside uniform
# layers. For the bunny (50 mm, --up y --units m; its hole-filled base, z < 2.25 mm,
# left out of the percentile) and three OpenSCAD models (tests/bench/models/*.scad: a dome on
# a plinth, stepped tiers with off-grid flat tops, a twisted vase), each run is one layer plan:
#   (mahost slices without supports or raft here, as the peers do: --support none --no-raft)
#   - mahost uniform, mid and ma contours, at 0.15, 0.2, 0.25 and 0.3 mm (0.3 mm first layer);
#   - CuraEngine 4.13 adaptive layers (adaptive_layer_height_enabled, base 0.25 mm, variation
#     0.1 mm in steps of 0.05: 0.15 to 0.35 mm, the UP Plus 2's grid) at several
#     adaptive_layer_height_threshold values;
#   - Slic3r 1.3 adaptive slicing (adaptive_slicing, 0.15 to 0.4 mm) at several
#     adaptive_slicing_quality values;
#   - PrusaSlicer 2.5 has no command-line switch for its adaptive heights (a GUI tool that
#     stores a layer height profile in a 3MF), so it has no row;
#   - mahost's adaptive plans (slice --adaptive --tolerance T --contour best), at several T
#     (ADAPTIVE_TOLERANCES), printed and judged with best;
# Every plan is read back from its G-code (mahost analyze --boundaries FILE) and judged with
# the contour the slicer prints at those boundaries (mid for the peers), exactly as analyze
# does: layers, mean D and max D over layers, the 95th percentile of D by height (P95h),
# total ΔV. The print time is mahost's estimate (the UP Plus 2's motion model, our toolpaths)
# of the same plan sliced with that contour (mahost slice --boundaries), so every row is timed
# alike; for the peers' continuous heights (Slic3r's reach 0.406 mm) the UP Plus 2's step is
# lifted and its range widened to 0.05-0.45 mm (--set layer.step=0 ...) for timing only.
#
# Usage: tests/bench/adaptive_layers.sh [BUILD_DIR]     (default build; mahost built)
#        MODELS="bunny dome" tests/bench/adaptive_layers.sh   a subset of bunny dome steps vase
#          (MODELS=none: only EXTRA)
#        EXTRA="my.stl part.scad" tests/bench/adaptive_layers.sh   one's own STL or OpenSCAD
#          files too, each sliced as it stands (no z range left out of P95h D)
# It ends with the slicing time of every adaptive run (wall and CPU), mahost's planning
# included, beside the peers' in the same run.
# Needs CuraEngine, slic3r, openscad (scripts/setup --bench installs them).
set -euo pipefail
cd "$(dirname "$0")/../.."
build=${1:-build}
mahost=$(pwd)/$build/mahost
[[ -x $mahost ]] || { echo "adaptive_layers: $mahost not found; build first (scripts/build)" >&2; exit 2; }
for tool in CuraEngine slic3r openscad; do
  command -v "$tool" >/dev/null || { echo "adaptive_layers: $tool not found; run scripts/setup --bench" >&2; exit 2; }
done
models=${MODELS:-bunny dome steps vase}
[[ $models == none ]] && models=""
extra=()
for file in ${EXTRA:-}; do
  [[ -f $file ]] || { echo "adaptive_layers: $file not found" >&2; exit 2; }
  extra+=("$(cd "$(dirname "$file")" && pwd)/$(basename "$file")")
  models+=" extra:$((${#extra[@]} - 1))"
done
cura_thresholds=${CURA_THRESHOLDS:-0.05 0.1 0.2 0.3}
slic3r_qualities=${SLIC3R_QUALITIES:-25 50 75 90}
uniform=${UNIFORM:-0.15 0.2 0.25 0.3}
adaptive_tolerances=${ADAPTIVE_TOLERANCES:-0.1 0.2 0.3 0.4 0.5}

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
source tests/bench/peer_slicers.sh

# The printer every plan is sliced for (estimates) and judged on.
timing_printer=(--printer up-plus-2 --set layer.step=0 --set layer.min=0.05 --set layer.max=0.45)

rows=()
notes=()
speed=()
# timed NAME MODEL COMMAND...: runs a slicer, keeps its wall and CPU time (user + system, all
# threads) for the speed table; a failure stops the run with the slicer's last lines.
timed() {
  local name=$1 model=$2
  shift 2
  local TIMEFORMAT="%R %U %S"  # bash's own time: the peers' runs are shell functions
  { time "$@" >"$work/run.log" 2>&1; } 2>"$work/time" ||
    { echo "adaptive_layers: failed: $name" >&2; tail -3 "$work/run.log" >&2; exit 1; }
  local wall user sys
  read -r wall user sys <"$work/time"
  speed+=("$(printf '%-8s %-34s %8.2f s %8.2f s' "$model" "$name" "$wall" "$(awk -v u="$user" -v s="$sys" 'BEGIN { print u + s }')")")
}
# judge NAME MODEL_ARGS... -- GCODE CONTOUR: one row from a plan's G-code.
judge() {
  local name=$1 model=$2 place=$3 excl=$4 gcode=$5 contour=$6
  local json=$work/judge.json timed=$work/timed.gcode
  # shellcheck disable=SC2086
  "$mahost" analyze "$model" $place --boundaries "$gcode" --contours "$contour" \
    ${excl:+--exclude-z $excl} --json "$json" >"$work/analyze.log" 2>&1 ||
    { echo "adaptive_layers: analyze failed for $name:" >&2; tail -3 "$work/analyze.log" >&2; return 1; }
  # A plan ending more than a layer below the part's top (CuraEngine leaves out a tip too
  # small to print) is not sliced: no time, and the reason under the table.
  local seconds=-1
  # shellcheck disable=SC2086
  if "$mahost" slice "$model" $place --boundaries "$gcode" --contour "$contour" --support none --no-raft "${timing_printer[@]}" \
    -o "$timed" >"$work/slice.log" 2>&1; then
    seconds=$(grep -m1 '^;PRINT_TIME_S:' "$timed" | cut -d: -f2)
  else
    notes+=("$name: not timed: $(tail -1 "$work/slice.log" | sed 's/^mahost: --boundaries [^:]*: //')")
  fi
  rows+=("$(python3 - "$json" "$name" "$seconds" <<'PY'
import json, sys
j = json.load(open(sys.argv[1]))
s = j["strategies"][0]
t = float(sys.argv[3])
p95 = s["p95_distance_by_height"]
print(f'{sys.argv[2]:<34} {j["layers"]:6d} {j["layer_thickness_min"]:5.3f}-{j["layer_thickness_max"]:5.3f} '
      f'{j["layers_top"]:6.2f} '
      f'{s["mean_distance"]:7.4f} {s["max_distance"]:7.4f} {p95:7.4f} {s["total_volume_deviation"]:9.2f} '
      + (f'{int(t // 3600)}:{int(t % 3600 // 60):02d}:{int(t % 60):02d}' if t >= 0 else '       -'))
PY
)")
}

for model_name in $models; do
  file=""
  case $model_name in
    bunny) model=data/bunny.stl; place="--up y --units m --height 50"; excl="0:2.25" ;;
    dome | steps | vase) file=tests/bench/models/$model_name.scad ;;
    extra:*) file=${extra[${model_name#extra:}]}; model_name=$(basename "${file%.*}") ;;
    *) echo "adaptive_layers: unknown model $model_name (bunny, dome, steps, vase; own files by EXTRA)" >&2; exit 2 ;;
  esac
  if [[ -n $file ]]; then  # as it stands, made by OpenSCAD from a .scad
    model=$work/$model_name.stl; place=""; excl=""
    case $file in
      *.scad) openscad -o "$model" "$file" >"$work/openscad.log" 2>&1 ||
                { echo "adaptive_layers: openscad failed on $file" >&2; tail -3 "$work/openscad.log" >&2; exit 1; } ;;
      *) cp "$file" "$model" ;;
    esac
  fi
  # The placed, repaired mesh (centred, on the bed, mm): what every slicer slices.
  placed=$work/$model_name-placed.stl
  # shellcheck disable=SC2086
  "$mahost" info "$model" $place --export "$placed" >/dev/null
  rows+=("--- $model_name")

  # mahost, uniform layers.
  for t in $uniform; do
    for contour in mid ma; do
      out=$work/mahost-$contour-$t.gcode
      # shellcheck disable=SC2086
      "$mahost" slice "$model" $place --layer "$t" --contour "$contour" --support none --no-raft -o "$out" >/dev/null 2>&1
      judge "mahost uniform $t $contour" "$model" "$place" "$excl" "$out" "$contour"
    done
  done

  # mahost, adaptive layers by the exact error: the plan made for best (planned by mid's D,
  # which bounds best's from above), printed and judged with best.
  for tolerance in $adaptive_tolerances; do
    out=$work/mahost-adaptive-$tolerance.gcode
    # shellcheck disable=SC2086
    timed "mahost adaptive $tolerance best" "$model_name" "$mahost" slice "$model" $place \
      --adaptive --tolerance "$tolerance" --contour best --support none --no-raft -o "$out"
    judge "mahost adaptive $tolerance best" "$model" "$place" "$excl" "$out" best
  done

  # CuraEngine 4.13, adaptive layers.
  for threshold in $cura_thresholds; do
    out=$work/cura-$threshold.gcode
    timed "CuraEngine adaptive thr $threshold" "$model_name" cura_adaptive "$out" "$placed" "$threshold"
    judge "CuraEngine adaptive thr $threshold" "$model" "$place" "$excl" "$out" mid
  done

  # Slic3r 1.3, adaptive slicing.
  for quality in $slic3r_qualities; do
    out=$work/slic3r-$quality.gcode
    timed "Slic3r adaptive quality $quality%" "$model_name" slic3r_adaptive "$out" "$placed" "$quality"
    judge "Slic3r adaptive quality $quality%" "$model" "$place" "$excl" "$out" mid
  done
done

echo "layer plans judged by mahost analyze --boundaries (exact D and ΔV of the contour printed);"
echo "P95h D: the D within which layers covering 95% of the height stay (bunny: z < 2.25 mm left out);"
echo "top: where the plan's last layer ends (the part above it is not printed, nor judged);"
echo "time: mahost's estimate of the plan sliced with that contour on the UP Plus 2 (step lifted for timing)"
printf '%-34s %6s %11s %6s %7s %7s %7s %9s %8s\n' run layers "t, mm" top "mean D" "max D" "P95h D" "ΔV, mm³" time
printf '%s\n' "${rows[@]}"
((${#notes[@]})) && printf '%s\n' "${notes[@]}"
echo
echo "slicing time (mahost: planning and slicing; the peers: their whole slice), load $(cut -d' ' -f1-3 /proc/loadavg):"
printf '%-8s %-34s %10s %10s\n' model run wall CPU
printf '%s\n' "${speed[@]}"
