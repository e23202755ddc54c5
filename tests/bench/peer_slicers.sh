# Sourced by the layer-plan benchmarks (adaptive_layers.sh, plan_vs_peers.sh): the peers'
# adaptive slicing, with the settings both compare under (the printer's layer range, step and
# first layer, no supports or raft). Needs $work (a scratch folder) and Cura's definitions
# (cura_definitions.sh, sourced here).
#
# The printer is PRINTER (a profile in configs/printers/, default up-plus-2: 0.15 to 0.4 mm in
# steps of 0.05 and a 0.3 mm first layer; generic-marlin: 0.05 to 0.3 mm in steps of 0.01 and a
# 0.2 mm first layer). Its layer range is read into layer_min, layer_max, layer_step and
# first_layer.
source "$(dirname "${BASH_SOURCE[0]}")/cura_definitions.sh"
peer_printer=${PRINTER:-up-plus-2}
peer_profile="$(dirname "${BASH_SOURCE[0]}")/../../configs/printers/$peer_printer.toml"
[[ -f $peer_profile ]] || { echo "no printer profile $peer_profile (PRINTER=$peer_printer)" >&2; exit 2; }
# The profile's range and first layer, and CuraEngine's base and variation for it. CuraEngine's
# adaptive heights are its base layer height plus or minus whole variation steps, so the base
# must be one of the printer's heights: the one a whole number of steps above the least that is
# nearest the middle of the range, rounded down, and the variation as many steps (UP Plus 2:
# 0.25 +- 0.1, 0.15 to 0.35 mm, as 0.275 +- 0.125 would print between the steps;
# generic-marlin: 0.17 +- 0.12, 0.05 to 0.29 mm).
read -r layer_min layer_max layer_step first_layer cura_base cura_variation < <(/usr/bin/python3 - "$peer_profile" <<'PY'
import math, sys, tomllib
profile = tomllib.load(open(sys.argv[1], "rb"))
layer = profile["layer"]
lo, hi, step = layer["min"], layer["max"], layer["step"]
k = math.floor((hi - lo) / 2 / step + 1e-9) if step > 0 else 0
print(lo, hi, step, profile["first_layer"]["height"], f"{lo + k * step:.4f} {k * step:.4f}")
PY
)
[[ -n $cura_variation && $layer_step != 0 ]] ||
  { echo "the peers' comparison needs a printer with a layer step (PRINTER=$peer_printer)" >&2; exit 2; }

# cura_adaptive OUT.gcode PLACED.stl THRESHOLD: CuraEngine 4.13's adaptive layers
# (adaptive_layer_height_enabled, base cura_base, variation cura_variation in the printer's
# steps) at adaptive_layer_height_threshold THRESHOLD.
cura_adaptive() {
  CuraEngine slice -j "$cura_resources/definitions/fdmprinter.def.json" \
    -s machine_width=140 -s machine_depth=140 -s machine_height=135 -s machine_center_is_zero=true \
    -s machine_gcode_flavor="RepRap (Marlin/Sprinter)" -s machine_start_gcode="G28" -s machine_end_gcode="M84" \
    -s layer_height="$cura_base" -s layer_height_0="$first_layer" \
    -s adaptive_layer_height_enabled=true -s adaptive_layer_height_threshold="$3" \
    -s adaptive_layer_height_variation="$cura_variation" -s adaptive_layer_height_variation_step="$layer_step" \
    -s wall_line_count=2 -s top_layers=3 -s bottom_layers=3 -s infill_sparse_density=20 \
    -s adhesion_type=skirt -s skirt_line_count=1 -s support_enable=false \
    -e0 -s machine_nozzle_size=0.4 -s material_diameter=1.75 \
    -o "$1" -l "$2"
}

# slic3r_adaptive OUT.gcode PLACED.stl QUALITY: Slic3r 1.3's adaptive slicing (the printer's
# range; Slic3r has no step) at adaptive_slicing_quality QUALITY percent.
slic3r_adaptive() {
  local cfg=$work/slic3r-$$.ini
  cat >"$cfg" <<INI
bed_shape = 0x0,140x0,140x140,0x140
nozzle_diameter = 0.4
filament_diameter = 1.75
first_layer_height = $first_layer
layer_height = $cura_base
adaptive_slicing = 1
adaptive_slicing_quality = $3%
min_layer_height = $layer_min
max_layer_height = $layer_max
perimeters = 2
top_solid_layers = 3
bottom_solid_layers = 3
fill_density = 20%
skirts = 1
INI
  slic3r --load "$cfg" --print-center 70,70 "$2" -o "$1"
}
