#!/usr/bin/env bash
# Supports beside CuraEngine 4.13 and PrusaSlicer 2.5: the same placed meshes, the
# same overhang angle (50 degrees from vertical; PrusaSlicer's threshold is the slope from
# horizontal, 40), support everywhere, no raft, the same support pattern and density (lines
# 2.5 mm apart, 0.4 mm of interface at 80% of solid: Cura's roof height, PrusaSlicer's 2
# layers), 0.2 mm of air above and below the support, 0.2 mm beside it, 0.2 mm layers on the
# UP Plus 2 settings of compare_slicers.sh.
# Per model and slicer: support filament (support and interface, from the ;TYPE: comments),
# all filament, the slicer's own print-time estimate, the unsupported extrusion by mahost's
# independent check (bridges up to 10 mm, contact gap 0.2 mm; bench_unsupported), wall and
# CPU time of the slicing run (median of REPEAT, default 3). Read PrusaSlicer's unsupported
# figure with care: it prints support layers at heights of their own (the top contact at the
# part's bottom less the contact distance, the body in thicker layers), and the check reads
# one layer per Z level, each as tall as the distance to the level below, so its support
# beads look like beads hanging over the air between them.
#
# Usage: [CONTOURS=ma,best] [NO_SHEATH=1] [MODELS_ONLY="bunny sphere"] [EXTRA="my.stl part.scad"]
#        tests/bench/compare_supports.sh [BUILD_DIR]   (default: build)
# CONTOURS: mahost's --contour strategies to slice with, one row each (default: ma, best).
# NO_SHEATH=1: one more mahost row, "-sheath" (the last of CONTOURS), without the loop round the support
# body (--set support.sheath=false), as the peers are set here (PrusaSlicer's
# support_material_with_sheath = 0, Cura's support_wall_count = 0).
# Models: the bunny (50 mm), a T (a 10 x 10 x 20 mm stem under a 50 x 10 x 5 mm bar), a
# sphere (30 mm), an arch (40 x 10 x 25 mm, a 24 mm semicircular opening); openscad makes
# the closed forms, mahost info --export places and repairs every model once, and all three
# slicers read that file. CuraEngine's definitions as in compare_slicers.sh.
set -euo pipefail
cd "$(dirname "$0")/../.."
build=${1:-build}
repeat=${REPEAT:-3}
contours=${CONTOURS:-ma,best}
mahost=$build/mahost
check=$build/tests/bench/bench_unsupported
for tool in "$mahost" "$check"; do
  [[ -x $tool ]] || { echo "compare_supports: $tool not found; build first (scripts/build)" >&2; exit 2; }
done
for tool in CuraEngine prusa-slicer openscad /usr/bin/time; do
  command -v "$tool" >/dev/null || { echo "compare_supports: $tool not found; run scripts/setup" >&2; exit 2; }
done
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
source "$(dirname "$0")/cura_definitions.sh"

# --- the models ------------------------------------------------------------------------------
"$mahost" info data/bunny.stl --up y --units m --height 50 --export "$work/bunny.stl" >/dev/null 2>&1
cat >"$work/tee.scad" <<'EOF'
union() { translate([-5, -5, 0]) cube([10, 10, 20]); translate([-25, -5, 20]) cube([50, 10, 5]); }
EOF
cat >"$work/sphere.scad" <<'EOF'
sphere(r = 15, $fn = 96);
EOF
cat >"$work/arch.scad" <<'EOF'
difference() { translate([-20, -5, 0]) cube([40, 10, 25]);
               rotate([90, 0, 0]) cylinder(r = 12, h = 12, center = true, $fn = 96); }
EOF
models=(bunny)
for m in tee sphere arch; do
  openscad -o "$work/$m-raw.stl" "$work/$m.scad" >/dev/null 2>&1
  "$mahost" info "$work/$m-raw.stl" --export "$work/$m.stl" >/dev/null 2>&1
  models+=("$m")
done
# MODELS_ONLY: a subset of the four above (none: only EXTRA); EXTRA: STL or OpenSCAD files of
# one's own, each placed as it stands (mahost info --export) and compared after them.
if [[ ${MODELS_ONLY:-} == none ]]; then models=(); elif [[ -n ${MODELS_ONLY:-} ]]; then read -r -a models <<<"$MODELS_ONLY"; fi
for file in ${EXTRA:-}; do
  m=$(basename "${file%.*}")
  case $file in
    *.scad) openscad -o "$work/$m-raw.stl" "$file" >/dev/null 2>&1 || { echo "compare_supports: openscad failed on $file" >&2; exit 2; } ;;
    *) cp "$file" "$work/$m-raw.stl" ;;
  esac
  "$mahost" info "$work/$m-raw.stl" --export "$work/$m.stl" >/dev/null 2>&1 ||
    { echo "compare_supports: mahost could not read $file" >&2; exit 2; }
  models+=("$m")
done

source tests/bench/timed.sh

rows=()
row() {  # model slicer seconds gcode
  local wall user sys peak report support all unsupported
  read -r wall user sys peak <"$work/time"
  report=$("$check" "$4" --bridge 10 --gap 0.2)
  unsupported=$(sed -n 's/.*unsupported extrusion: \([0-9.]*\) mm of \([0-9.]*\) m.*/\1/p' <<<"$report" | head -1)
  support=$(awk '/filament/ { s = 0; for (i = 1; i <= NF; i++) { if ($i == "support") s += $(i + 1);
              if ($i == "interface") s += $(i + 1) } print s }' <<<"$report")
  all=$(awk '/filament/ { sub(/:/, "", $2); print $2 }' <<<"$report")
  rows+=("$(printf '%-7s %-16s %9.2f m %9.2f m %10s %10.1f mm %7.2f s %7.2f s' "$1" "$2" \
    "$(awk -v f="$support" 'BEGIN { print f / 1000 }')" "$(awk -v f="$all" 'BEGIN { print f / 1000 }')" \
    "$(awk -v s="$3" 'BEGIN { printf "%dh%02dm%02ds", s / 3600, (s % 3600) / 60, s % 60 }')" \
    "$unsupported" "$wall" "$(awk -v u="$user" -v s="$sys" 'BEGIN { print u + s }')")")
}

cat >"$work/prusa.ini" <<'EOF'
layer_height = 0.2
bridge_speed = 20
raft_layers = 0
support_material = 1
support_material_auto = 1
support_material_threshold = 40
support_material_buildplate_only = 0
support_material_contact_distance = 0.2
support_material_bottom_contact_distance = 0.2
support_material_xy_spacing = 0.2
support_material_pattern = rectilinear
support_material_with_sheath = 0
support_material_spacing = 2.093
support_material_angle = 0
support_material_interface_layers = 2
support_material_bottom_interface_layers = 0
support_material_interface_spacing = 0.102
support_material_extrusion_width = 0.45
support_material_speed = 50
support_material_interface_speed = 40
EOF

for m in "${models[@]}"; do
  model=$work/$m.stl
  out=$work/mahost-$m.gcode
  for contour in ${contours//,/ }; do
    timed "$mahost" slice "$model" --contour "$contour" --layer 0.2 --support everywhere --no-raft \
      --overhang-angle 50 --support-spacing 2.5 --support-interface-thickness 0.4 \
      --support-top-distance 0.2 --support-bottom-distance 0.2 --support-xy-gap 0.2 \
      --bridge-length 10 -o "$out"
    row "$m" "mahost ($contour)" "$(grep -m1 '^;PRINT_TIME_S:' "$out" | cut -d: -f2)" "$out"
  done
  if [[ -n ${NO_SHEATH:-} ]]; then  # as the peers lay it: no loop round the body
    timed "$mahost" slice "$model" --contour "${contours##*,}" --layer 0.2 --support everywhere --no-raft \
      --overhang-angle 50 --support-spacing 2.5 --support-interface-thickness 0.4 \
      --support-top-distance 0.2 --support-bottom-distance 0.2 --support-xy-gap 0.2 \
      --bridge-length 10 --set support.sheath=false -o "$out"
    row "$m" "mahost -sheath" "$(grep -m1 '^;PRINT_TIME_S:' "$out" | cut -d: -f2)" "$out"
  fi

  out=$work/cura-$m.gcode
  timed CuraEngine slice -j "$cura_resources/definitions/fdmprinter.def.json" \
    -s machine_width=140 -s machine_depth=140 -s machine_height=135 -s machine_center_is_zero=true \
    -s machine_gcode_flavor="RepRap (Marlin/Sprinter)" -s machine_start_gcode="G28" -s machine_end_gcode="M84" \
    -s machine_max_feedrate_x=200 -s machine_max_feedrate_y=200 -s machine_max_feedrate_z=10 -s machine_max_feedrate_e=40 \
    -s machine_max_acceleration_x=1500 -s machine_max_acceleration_y=1500 -s machine_max_acceleration_z=100 \
    -s machine_max_acceleration_e=3000 -s machine_acceleration=800 \
    -s layer_height=0.2 -s layer_height_0=0.3 \
    -s line_width=0.45 -s wall_line_width=0.45 -s wall_line_width_0=0.45 -s wall_line_width_x=0.45 \
    -s skin_line_width=0.45 -s infill_line_width=0.45 -s skirt_brim_line_width=0.45 \
    -s initial_layer_line_width_factor=111.1 \
    -s wall_line_count=2 -s top_layers=3 -s bottom_layers=3 \
    -s infill_sparse_density=20 -s infill_pattern=grid -s infill_line_distance=4.5 \
    -s adhesion_type=skirt -s skirt_line_count=1 -s skirt_gap=3 \
    -s support_enable=true -s support_type=everywhere -s support_angle=50 -s support_pattern=zigzag \
    -s support_line_width=0.45 -s support_line_distance=2.5 -s support_initial_layer_line_distance=2.5 \
    -s support_z_distance=0.2 -s support_top_distance=0.2 -s support_bottom_distance=0.2 \
    -s support_xy_distance=0.2 -s support_xy_distance_overhang=0.2 -s support_wall_count=0 \
    -s support_interface_enable=true -s support_roof_enable=true -s support_bottom_enable=false \
    -s support_roof_height=0.4 -s support_interface_height=0.4 -s support_roof_density=80 \
    -s support_roof_line_distance=0.509 -s support_roof_pattern=lines -s support_roof_line_width=0.45 \
    -s support_interface_line_width=0.45 -s support_offset=0 -s support_tree_enable=false \
    -s speed_support=50 -s speed_support_infill=50 -s speed_support_interface=40 -s speed_support_roof=40 \
    -s speed_print=50 -s speed_infill=50 -s speed_wall=40 -s speed_wall_0=25 -s speed_wall_x=40 \
    -s speed_topbottom=30 -s speed_roofing=30 -s speed_travel=120 -s speed_layer_0=15 \
    -s speed_print_layer_0=15 -s speed_travel_layer_0=120 -s skirt_brim_speed=15 \
    -s acceleration_enabled=true -s acceleration_print=800 -s acceleration_infill=800 \
    -s acceleration_wall=800 -s acceleration_wall_0=800 -s acceleration_wall_x=800 \
    -s acceleration_topbottom=800 -s acceleration_roofing=800 -s acceleration_travel=1500 \
    -s acceleration_layer_0=800 -s acceleration_print_layer_0=800 -s acceleration_travel_layer_0=1500 \
    -s acceleration_skirt_brim=800 -s acceleration_support=800 -s acceleration_support_infill=800 \
    -s acceleration_support_interface=800 -s acceleration_support_roof=800 -s jerk_enabled=false \
    -s retraction_enable=true -s retraction_amount=1 -s retraction_speed=30 \
    -s retraction_retract_speed=30 -s retraction_prime_speed=25 -s retraction_min_travel=2 \
    -s material_print_temperature=245 -s material_print_temperature_layer_0=250 \
    -s material_bed_temperature=100 -s material_bed_temperature_layer_0=105 -s cool_fan_enabled=false \
    -e0 -s machine_nozzle_size=0.4 -s material_diameter=1.75 \
    -o "$out" -l "$model"
  row "$m" "CuraEngine 4.13" "$(grep '^;TIME_ELAPSED:' "$out" | tail -1 | cut -d: -f2)" "$out"

  out=$work/prusa-$m.gcode
  timed prusa-slicer --export-gcode --load tests/bench/prusa_up_plus_2.ini --load "$work/prusa.ini" --center 70,70 -o "$out" "$model"
  prusa_time=$(grep -m1 '^; estimated printing time (normal mode)' "$out" | sed 's/.*= //' |
    awk '{ s = 0; for (i = 1; i <= NF; i++) { v = $i + 0; u = substr($i, length($i));
           s += (u == "d") ? v * 86400 : (u == "h") ? v * 3600 : (u == "m") ? v * 60 : v } print s }')
  row "$m" "PrusaSlicer 2.5" "$prusa_time" "$out"
  [[ -n ${KEEP:-} ]] && cp "$work"/*-"$m".gcode "$KEEP"/ 2>/dev/null || true
done

echo "supports everywhere, 50 deg from vertical, lines 2.5 mm, 0.4 mm interface at 80%, 0.2 mm gaps; 0.2 mm layers"
echo "unsupported: mahost's check (bench_unsupported, bridges up to 10 mm, contact gap 0.2 mm); wall, cpu: median of $repeat"
printf '%-7s %-16s %11s %11s %10s %13s %9s %9s\n' model slicer support filament "est. time" unsupported wall cpu
printf '%s\n' "${rows[@]}"
