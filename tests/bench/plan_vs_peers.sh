#!/usr/bin/env bash
# mahost's layer plan against each peer's at the peer's own layer count, judged by an
# independent judge (tests/bench/judge.py: numpy and shapely, no code of mahost's).
#
# For each model (the bunny, 50 mm, --up y --units m, its hole-filled base z < 2.25 mm left out
# of all four measures; and tests/bench/models/{pawn,star,tiers,gear,cap,bottle,knob}.scad, written
# for this comparison before any plan was judged on them) and each peer run:
#   - CuraEngine 4.13 adaptive layers at several thresholds (CURA_THRESHOLDS),
#   - Slic3r 1.3 adaptive slicing at several qualities (SLIC3R_QUALITIES),
#   - uniform layers of the mid section at several thicknesses (UNIFORM; mahost slice --contour
#     mid: the printer's first layer, flat tops landed),
# the peer's layers are read from its G-code and judged with the model's own mid section (what
# the peers print); then mahost plans at most as many layers (slice --max-layers N --contour
# best), its layered part is exported (analyze --boundaries its G-code --export-layers) and
# judged the same way. Each row: layers, mean D, P95h D (by height), max D, total ΔV of both,
# and whether mahost is no worse on all four and at least 10% better on one ("yes"), with the
# measures where it is worse otherwise. All slicing without supports or raft, on the printer
# PRINTER (peer_slicers.sh; default up-plus-2: 0.15-0.4 mm in 0.05 mm steps, 0.3 mm first
# layer; generic-marlin: 0.05-0.3 mm in 0.01 mm steps, 0.2 mm first layer).
#
# Usage: tests/bench/plan_vs_peers.sh [BUILD_DIR]          (default build; absolute or in the
#                                                          repository; mahost built)
#        MODELS="bunny pawn" tests/bench/plan_vs_peers.sh   a subset
#        CONTOURS="best mid": mahost's layers judged with each contour (analyze --boundaries
#                   its G-code --contour C), a row each; slice prints with the first (default
#                   best), the others say how much of a row is the plan's and the contour's
#        KEEP=DIR: keep every G-code, layered part and judge's JSON and CSV there
#        PEERS=DIR: take the peers' G-code and judged JSON and CSV from an earlier run's KEEP
#                   folder where it has them for the same placed model (byte for byte) and
#                   printer, instead of slicing and judging them again (they do not depend on
#                   mahost's plan)
#        PRINTER=NAME: the printer profile all slice for (default up-plus-2)
# Needs CuraEngine, slic3r, openscad, python3-numpy, python3-shapely (scripts/setup --bench).
set -euo pipefail
cd "$(dirname "$0")/../.."
build=${1:-build}
[[ $build == /* ]] || build=$(pwd)/$build
mahost=$build/mahost
judge=(/usr/bin/python3 "$(pwd)/tests/bench/judge.py")
[[ -x $mahost ]] || { echo "plan_vs_peers: $mahost not found; build first (scripts/build)" >&2; exit 2; }
for tool in CuraEngine slic3r openscad; do
  command -v "$tool" >/dev/null || { echo "plan_vs_peers: $tool not found; run scripts/setup --bench" >&2; exit 2; }
done
/usr/bin/python3 -c "import numpy, shapely" 2>/dev/null ||
  { echo "plan_vs_peers: python3-numpy and python3-shapely needed; run scripts/setup --bench" >&2; exit 2; }
models=${MODELS:-bunny pawn star tiers gear cap bottle knob}
cura_thresholds=${CURA_THRESHOLDS:-0.05 0.1 0.2 0.3}
slic3r_qualities=${SLIC3R_QUALITIES:-25 50 75 90}
uniform=${UNIFORM:-0.15 0.2 0.25 0.3}
judged_contours=${CONTOURS:-best}

work=${KEEP:-$(mktemp -d)}
mkdir -p "$work"
[[ -n ${KEEP:-} ]] || trap 'rm -rf "$work"' EXIT
source tests/bench/peer_slicers.sh
echo "$peer_printer" >"$work/printer"  # whose range the peers' runs there were sliced in

rows=()
# reused TAG: whether PEERS holds the peer run TAG for this placed model.
reused() {
  [[ -n ${PEERS:-} && -f $PEERS/$1.gcode && -f $PEERS/$1-peer.json && -f $PEERS/$1-peer.csv ]] &&
    [[ $(cat "$PEERS/printer" 2>/dev/null || echo up-plus-2) == "$peer_printer" ]] &&
    cmp -s "$placed" "$PEERS/$model_name-placed.stl"
}
# compare NAME PEER.gcode: the peer's plan and mahost's at its layer count, one row.
compare() {
  local name=$1 peer=$2 tag=$3
  local n ours=$work/$tag-mahost.gcode part=$work/$tag-mahost-layers.stl
  n=$("${judge[@]}" "$placed" --layers "$peer" --count)
  if reused "$tag"; then
    [[ $PEERS -ef $work ]] || cp "$PEERS/$tag-peer.json" "$PEERS/$tag-peer.csv" "$work/"
  else
    "${judge[@]}" "$placed" --layers "$peer" --mid ${excl:+--exclude-z $excl} \
      --json "$work/$tag-peer.json" --csv "$work/$tag-peer.csv" >/dev/null
  fi
  "$mahost" slice "$placed" --printer "$peer_printer" --max-layers "$n" --contour "${judged_contours%% *}" --support none --no-raft \
    -o "$ours" >"$work/$tag-mahost.log" 2>&1 ||
    { echo "plan_vs_peers: mahost slice failed for $name:" >&2; tail -3 "$work/$tag-mahost.log" >&2; exit 1; }
  local contour label json
  for contour in $judged_contours; do
    # The first contour is the one slice printed; the others judge the same layers.
    label=$name json=$work/$tag-mahost.json part=$work/$tag-mahost-layers.stl
    if [[ $contour != "${judged_contours%% *}" ]]; then
      label="  same layers, $contour" json=$work/$tag-mahost-$contour.json
      part=$work/$tag-mahost-$contour-layers.stl
    fi
    "$mahost" analyze "$placed" --printer "$peer_printer" --boundaries "$ours" --contours "$contour" --contour "$contour" \
      --export-layers "$part" >"$work/$tag-analyze.log" 2>&1 ||
      { echo "plan_vs_peers: mahost analyze failed for $name:" >&2; tail -3 "$work/$tag-analyze.log" >&2; exit 1; }
    "${judge[@]}" "$placed" --layers "$ours" --part "$part" ${excl:+--exclude-z $excl} \
      --json "$json" --csv "${json%.json}.csv" >/dev/null
    row "$work/$tag-peer.json" "$json" "$label" "$work/$tag-peer.csv"
  done
}

# row PEER.json OURS.json NAME PEER.csv: one row of the table.
row() {
  rows+=("$(/usr/bin/python3 - "$@" "$layer_min" "$layer_max" "$layer_step" <<'PY'
import csv, json, sys
peer, ours, name = json.load(open(sys.argv[1])), json.load(open(sys.argv[2])), sys.argv[3]
lo, hi, step = map(float, sys.argv[5:8])
# The peer's layers above the first that the printer cannot print: under its least or over its
# greatest thickness, or between its steps, each to 1.5 um (a G-code file's Z is written to 1
# um, so a thickness from two of them is off by up to 1 um). The peers were given the range,
# and Slic3r knows no step. Said beside the verdict, which still counts them as printed.
slack = 1.5e-3
def printable(t):
    return lo - slack <= t <= hi + slack and abs(t / step - round(t / step)) * step <= slack
layers = list(csv.DictReader(open(sys.argv[4])))[1:peer["layers"]]
thicknesses = [float(r["z_hi"]) - float(r["z_lo"]) for r in layers]
thin = [t for t in thicknesses if t < lo - slack]
off_step = [t for t in thicknesses if t >= lo - slack and not printable(t)]
keys = [("mean_D", "mean D"), ("p95h_D", "P95h D"), ("max_D", "max D"), ("total_dV", "dV")]
# D equal to a nanometre is a tie (a binary STL's 32-bit coordinates move a point by more:
# the first layer, one slab for both, is judged 0.1256574 against 0.1256581 mm on the star).
worse = [label for k, label in keys if ours[k] > peer[k] * (1 + 1e-9) + (1e-6 if k != "total_dV" else 1e-9)]
better = [k for k, _ in keys if ours[k] <= 0.9 * peer[k]]
verdict = "yes" if not worse and better else "no: " + (", ".join(worse) + " worse" if worse else "none 10% better")
cells = "  ".join(f"{peer[k]:7.4f} {ours[k]:7.4f}" if k != "total_dV" else f"{peer[k]:8.2f} {ours[k]:8.2f}"
                  for k, _ in keys)
# A peer ending below the model's top (CuraEngine on the star and the cap) is judged with one
# more slab printing nothing, counted in the mean D as a layer would be (judge.py).
uncovered = peer.get("uncovered", 0) > 1e-6
notes = ([f"{len(thin)} layer(s) under the printer's {lo:g} mm, down to {min(thin):.3f}"] if thin else []) + \
        ([f"{len(off_step)} between its {step:g} mm steps"] if off_step else []) + \
        ([f"ends {peer['uncovered']:.3f} mm below the top"] if uncovered else [])
if notes:
    verdict += " (peer: " + "; ".join(notes) + ")"
print(f"{name:<22} {peer['layers']:4d} {ours['layers']:4d}  {cells}  {verdict}")
PY
)")
}

for model_name in $models; do
  case $model_name in
    bunny) model=data/bunny.stl; place=(--up y --units m --height 50); excl="0:2.25" ;;
    pawn | star | tiers | gear | cap | bottle | knob)
      model=$work/$model_name.stl; place=(); excl=""
      openscad -o "$model" "tests/bench/models/$model_name.scad" >"$work/openscad.log" 2>&1 ||
        { echo "plan_vs_peers: openscad failed on $model_name.scad" >&2; tail -3 "$work/openscad.log" >&2; exit 1; } ;;
    *) echo "plan_vs_peers: unknown model $model_name (bunny pawn star tiers gear cap bottle knob)" >&2; exit 2 ;;
  esac
  # The placed, repaired mesh (centred, on the bed, mm): what every slicer slices and the
  # judge judges against.
  placed=$work/$model_name-placed.stl
  "$mahost" info "$model" "${place[@]}" --export "$placed" >/dev/null
  rows+=("--- $model_name")
  for threshold in $cura_thresholds; do
    out=$work/$model_name-cura-$threshold.gcode
    if reused "$model_name-cura-$threshold"; then
      [[ $PEERS -ef $work ]] || cp "$PEERS/$model_name-cura-$threshold.gcode" "$out"
    else cura_adaptive "$out" "$placed" "$threshold" >"$work/peer.log" 2>&1 ||
      { echo "plan_vs_peers: CuraEngine failed on $model_name" >&2; tail -3 "$work/peer.log" >&2; exit 1; }
    fi
    compare "Cura adaptive $threshold" "$out" "$model_name-cura-$threshold"
  done
  for quality in $slic3r_qualities; do
    out=$work/$model_name-slic3r-$quality.gcode
    if reused "$model_name-slic3r-$quality"; then
      [[ $PEERS -ef $work ]] || cp "$PEERS/$model_name-slic3r-$quality.gcode" "$out"
    else slic3r_adaptive "$out" "$placed" "$quality" >"$work/peer.log" 2>&1 ||
      { echo "plan_vs_peers: slic3r failed on $model_name" >&2; tail -3 "$work/peer.log" >&2; exit 1; }
    fi
    compare "Slic3r adaptive $quality%" "$out" "$model_name-slic3r-$quality"
  done
  for t in $uniform; do
    out=$work/$model_name-uniform-$t.gcode
    if reused "$model_name-uniform-$t"; then
      [[ $PEERS -ef $work ]] || cp "$PEERS/$model_name-uniform-$t.gcode" "$out"
    else
      "$mahost" slice "$placed" --printer "$peer_printer" --layer "$t" --contour mid --support none --no-raft -o "$out" >"$work/peer.log" 2>&1
    fi
    compare "uniform mid $t" "$out" "$model_name-uniform-$t"
  done
done

echo "each peer run against mahost's plan of at most as many layers (slice --max-layers N --contour best),"
echo "judged by tests/bench/judge.py (D and ΔV of the model against the layers printed: the peers' the"
echo "model's mid sections, mahost's its exported layered part); bunny: z < 2.25 mm left out;"
echo "per measure the peer's figure, then mahost's; D in mm, ΔV in mm³"
printf '%-22s %4s %4s  %-15s  %-15s  %-15s  %-17s  %s\n' run peer ours "mean D" "P95h D" "max D" "total ΔV" "mahost no worse, 10% better on one"
printf '%s\n' "${rows[@]}"
