// The values PrusaSlicer's placeholders name (its settings' names), as mahost knows them for a
// slice: the start and end G-code of a printer imported from PrusaSlicer are evaluated over
// these (profile.h's expand_placeholders, prusa_macro.h).
//
// Known: the material's temperature, first_layer_temperature, bed_temperature,
// first_layer_bed_temperature, filament_type, filament_settings_id, filament_diameter,
// extrusion_multiplier, filament_density; the printer's nozzle_diameter, retract_length,
// retract_speed, deretract_speed, retract_lift, retract_before_travel, min_layer_height,
// max_layer_height (each a vector with one element per extruder: mahost knows the first
// extruder's, and naming another's is an error that says so), max_print_height, z_offset (0:
// mahost moves Z as planned), the speeds (travel_speed, travel_speed_z, perimeter_speed,
// external_perimeter_speed, infill_speed, solid_infill_speed, top_solid_infill_speed,
// support_material_speed, bridge_speed, first_layer_speed), extrusion_width,
// first_layer_extrusion_width, machine_max_feedrate_x/y/z/e and machine_max_acceleration_x/y/z/
// e/extruding/travel/retracting, use_relative_e_distances, gcode_flavor, printer_settings_id;
// the bed (print_bed_min, print_bed_max, print_bed_size: X and Y, mm, in G-code coordinates);
// the slice: layer_height, first_layer_height, layer_z and max_layer_z (the top of the last
// layer; 0 before it), layer_num, total_layer_count, first_layer_print_min, _max, _size,
// input_filename (the model's name with .gcode), input_filename_base; and what mahost never
// does: current_extruder, initial_extruder, initial_tool (0), has_wipe_tower,
// has_single_extruder_multi_material_priming, wipe_tower, single_extruder_multi_material
// (false). Then the printer's gcode_constants (printer_model, printer_notes,
// print_settings_id, ...), for names not above.
#pragma once

#include "printer/profile.h"
#include "printer/prusa_macro.h"

namespace printer {

MacroVariables prusa_variables(const Profiles& profiles, const PlaceholderValues& values);

}  // namespace printer
