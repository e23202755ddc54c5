# Sourced by the layer-plan benchmarks (adaptive_layers.sh, plan_vs_peers.sh): the peers'
# adaptive slicing, with the settings both compare under (the UP Plus 2's 0.15 to 0.4 mm range
# and 0.3 mm first layer, no supports or raft). Needs $work (a scratch folder) and Cura's
# definitions (cura_definitions.sh, sourced here).
source "$(dirname "${BASH_SOURCE[0]}")/cura_definitions.sh"

# cura_adaptive OUT.gcode PLACED.stl THRESHOLD: CuraEngine 4.13's adaptive layers
# (adaptive_layer_height_enabled, base 0.25 mm, variation 0.1 mm in steps of 0.05: 0.15 to
# 0.35 mm, the UP Plus 2's grid) at adaptive_layer_height_threshold THRESHOLD.
cura_adaptive() {
  CuraEngine slice -j "$cura_resources/definitions/fdmprinter.def.json" \
    -s machine_width=140 -s machine_depth=140 -s machine_height=135 -s machine_center_is_zero=true \
    -s machine_gcode_flavor="RepRap (Marlin/Sprinter)" -s machine_start_gcode="G28" -s machine_end_gcode="M84" \
    -s layer_height=0.25 -s layer_height_0=0.3 \
    -s adaptive_layer_height_enabled=true -s adaptive_layer_height_threshold="$3" \
    -s adaptive_layer_height_variation=0.1 -s adaptive_layer_height_variation_step=0.05 \
    -s wall_line_count=2 -s top_layers=3 -s bottom_layers=3 -s infill_sparse_density=20 \
    -s adhesion_type=skirt -s skirt_line_count=1 -s support_enable=false \
    -e0 -s machine_nozzle_size=0.4 -s material_diameter=1.75 \
    -o "$1" -l "$2"
}

# slic3r_adaptive OUT.gcode PLACED.stl QUALITY: Slic3r 1.3's adaptive slicing (0.15 to 0.4 mm)
# at adaptive_slicing_quality QUALITY percent.
slic3r_adaptive() {
  local cfg=$work/slic3r-$$.ini
  cat >"$cfg" <<INI
bed_shape = 0x0,140x0,140x140,0x140
nozzle_diameter = 0.4
filament_diameter = 1.75
first_layer_height = 0.3
layer_height = 0.25
adaptive_slicing = 1
adaptive_slicing_quality = $3%
min_layer_height = 0.15
max_layer_height = 0.4
perimeters = 2
top_solid_layers = 3
bottom_solid_layers = 3
fill_density = 20%
skirts = 1
INI
  slic3r --load "$cfg" --print-center 70,70 "$2" -o "$1"
}
