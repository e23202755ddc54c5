# Sourced by the benchmarks that run CuraEngine: sets cura_resources to a folder holding
# Cura's JSON machine definitions, exports CURA_ENGINE_SEARCH_PATH and defines cura_command
# (below). Debian ships the definitions only in the GUI package `cura` (416 packages with
# Qt); instead of installing it, this fetches that one .deb with `apt-get download cura` and
# unpacks its definitions into
# ${XDG_CACHE_HOME:-~/.cache}/mahost/cura-4.13 (once). Needs $work, a scratch folder.
cura_resources=""
for dir in /usr/share/cura/resources "${XDG_CACHE_HOME:-$HOME/.cache}/mahost/cura-4.13/resources"; do
  [[ -f $dir/definitions/fdmprinter.def.json ]] && { cura_resources=$dir; break; }
done
if [[ -z $cura_resources ]]; then
  cache=${XDG_CACHE_HOME:-$HOME/.cache}/mahost/cura-4.13
  echo "fetching Cura's machine definitions (apt-get download cura, once)" >&2
  (cd "$work" && apt-get download cura >/dev/null 2>&1) ||
    { echo "apt-get download cura failed; install the package cura instead" >&2; exit 2; }
  dpkg-deb -x "$work"/cura_*.deb "$work/cura"
  mkdir -p "$cache/resources"
  cp -r "$work/cura/usr/share/cura/resources/definitions" "$work/cura/usr/share/cura/resources/extruders" \
    "$cache/resources/"
  cura_resources=$cache/resources
fi
export CURA_ENGINE_SEARCH_PATH=$cura_resources/definitions:$cura_resources/extruders

# cura_command LAYER MODEL OUT: sets the array `cura` to the CuraEngine command that slices
# MODEL at LAYER mm into OUT with compare_slicers.sh's settings (the UP Plus 2, no support,
# one skirt loop). CuraEngine does not evaluate the definitions' formulas (the Cura front end
# does), so every derived setting is passed explicitly.
cura_command() {
  cura=(CuraEngine slice -j "$cura_resources/definitions/fdmprinter.def.json" \
      -s machine_width=140 -s machine_depth=140 -s machine_height=135 -s machine_center_is_zero=true \
      -s machine_gcode_flavor="RepRap (Marlin/Sprinter)" -s machine_start_gcode="G28" -s machine_end_gcode="M84" \
      -s machine_max_feedrate_x=200 -s machine_max_feedrate_y=200 -s machine_max_feedrate_z=10 -s machine_max_feedrate_e=40 \
      -s machine_max_acceleration_x=1500 -s machine_max_acceleration_y=1500 -s machine_max_acceleration_z=100 \
      -s machine_max_acceleration_e=3000 -s machine_acceleration=800 \
      -s layer_height="$1" -s layer_height_0=0.3 \
      -s line_width=0.45 -s wall_line_width=0.45 -s wall_line_width_0=0.45 -s wall_line_width_x=0.45 \
      -s skin_line_width=0.45 -s infill_line_width=0.45 -s skirt_brim_line_width=0.45 \
      -s initial_layer_line_width_factor=111.1 \
      -s wall_line_count=2 -s top_layers=3 -s bottom_layers=3 \
      -s infill_sparse_density=20 -s infill_pattern=grid -s infill_line_distance=4.5 \
      -s adhesion_type=skirt -s skirt_line_count=1 -s skirt_gap=3 -s support_enable=false \
      -s speed_print=50 -s speed_infill=50 -s speed_wall=40 -s speed_wall_0=25 -s speed_wall_x=40 \
      -s speed_topbottom=30 -s speed_roofing=30 -s speed_travel=120 -s speed_layer_0=15 \
      -s speed_print_layer_0=15 -s speed_travel_layer_0=120 -s skirt_brim_speed=15 \
      -s acceleration_enabled=true -s acceleration_print=800 -s acceleration_infill=800 \
      -s acceleration_wall=800 -s acceleration_wall_0=800 -s acceleration_wall_x=800 \
      -s acceleration_topbottom=800 -s acceleration_roofing=800 -s acceleration_travel=1500 \
      -s acceleration_layer_0=800 -s acceleration_print_layer_0=800 -s acceleration_travel_layer_0=1500 \
      -s acceleration_skirt_brim=800 -s jerk_enabled=false \
      -s retraction_enable=true -s retraction_amount=1 -s retraction_speed=30 \
      -s retraction_retract_speed=30 -s retraction_prime_speed=25 -s retraction_min_travel=2 \
      -s material_print_temperature=245 -s material_print_temperature_layer_0=250 \
      -s material_bed_temperature=100 -s material_bed_temperature_layer_0=105 -s cool_fan_enabled=false \
      -e0 -s machine_nozzle_size=0.4 -s material_diameter=1.75 \
      -o "$3" -l "$2")
}
