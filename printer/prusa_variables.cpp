// PrusaSlicer's names for what mahost knows of a slice; see prusa_variables.h.
#include "printer/prusa_variables.h"

#include <array>
#include <cmath>
#include <string>

#include <fmt/core.h>

namespace printer {
namespace {

// A per-extruder setting: the first extruder's value, and the others' as unknown.
MacroVariable per_extruder(MacroScalar first, int extruders, std::string_view whose) {
  MacroVariable v = macro_vector(std::vector<MacroScalar>(static_cast<std::size_t>(std::max(extruders, 1)), first));
  v.known = 1;
  v.unknown_why = fmt::format("mahost prints with the first extruder and knows only its {}", whose);
  return v;
}

long long whole(double celsius) { return std::llround(celsius); }

// What the names read: the profiles and the slice.
struct Known {
  const PrinterProfile& p;
  const MaterialProfile& m;
  const PlaceholderValues& slice;
};

MacroVariable material(const Known& k, MacroScalar value) {
  return per_extruder(std::move(value), k.p.extruders, "material");
}
MacroVariable nozzle(const Known& k, MacroScalar value) {
  return per_extruder(std::move(value), k.p.extruders, "nozzle and retraction");
}

// The layer thicknesses the printer takes, mm: its list's ends, else its range.
double thinnest_layer(const PrinterProfile& p) { return p.layer.allowed.empty() ? p.layer.min : p.layer.allowed.front(); }
double thickest_layer(const PrinterProfile& p) { return p.layer.allowed.empty() ? p.layer.max : p.layer.allowed.back(); }

// The first layer's extrusions in X and Y, [min_x, min_y, max_x, max_y]; the bed's centre
// while they are not known.
std::array<double, 4> first_layer_box(const Known& k) {
  const PlaceholderValues& s = k.slice;
  if (s.first_layer_min_x <= s.first_layer_max_x) {
    return {s.first_layer_min_x, s.first_layer_min_y, s.first_layer_max_x, s.first_layer_max_y};
  }
  const double cx = bed_centre_x(k.p), cy = bed_centre_y(k.p);
  return {cx, cy, cx, cy};
}

// One of PrusaSlicer's names and mahost's value for it. PrusaSlicer keeps two values of each
// machine limit (normal and silent mode); mahost one.
struct Placeholder {
  const char* name;
  MacroVariable (*value)(const Known&);
};

const Placeholder kPlaceholders[] = {
    {"temperature", [](const Known& k) { return material(k, whole(k.m.nozzle_temperature)); }},
    {"first_layer_temperature",
     [](const Known& k) { return material(k, whole(k.m.first_layer_nozzle_temperature)); }},
    {"bed_temperature", [](const Known& k) { return material(k, whole(k.m.bed_temperature)); }},
    {"first_layer_bed_temperature",
     [](const Known& k) { return material(k, whole(k.m.first_layer_bed_temperature)); }},
    {"filament_type", [](const Known& k) { return material(k, k.m.type.empty() ? k.m.name : k.m.type); }},
    {"filament_settings_id", [](const Known& k) { return material(k, k.m.name); }},
    {"filament_diameter", [](const Known& k) { return material(k, k.p.filament_diameter); }},
    {"extrusion_multiplier", [](const Known& k) { return material(k, k.m.flow); }},
    {"filament_density", [](const Known& k) { return material(k, k.m.density); }},

    {"nozzle_diameter", [](const Known& k) { return nozzle(k, k.p.nozzle_diameter); }},
    {"retract_length", [](const Known& k) { return nozzle(k, k.p.retraction.length); }},
    {"retract_speed", [](const Known& k) { return nozzle(k, k.p.retraction.speed); }},
    {"deretract_speed", [](const Known& k) { return nozzle(k, k.p.retraction.prime_speed); }},
    {"retract_lift", [](const Known& k) { return nozzle(k, k.p.retraction.z_hop); }},
    {"retract_before_travel", [](const Known& k) { return nozzle(k, k.p.retraction.min_travel); }},
    {"min_layer_height", [](const Known& k) { return nozzle(k, thinnest_layer(k.p)); }},
    {"max_layer_height", [](const Known& k) { return nozzle(k, thickest_layer(k.p)); }},

    {"max_print_height", [](const Known& k) { return macro_scalar(k.p.bed_z); }},
    {"z_offset", [](const Known&) { return macro_scalar(0.0); }},
    {"travel_speed", [](const Known& k) { return macro_scalar(k.p.speed.travel); }},
    {"travel_speed_z", [](const Known& k) { return macro_scalar(k.p.speed.z); }},
    {"perimeter_speed", [](const Known& k) { return macro_scalar(k.p.speed.inner_wall); }},
    {"external_perimeter_speed", [](const Known& k) { return macro_scalar(k.p.speed.outer_wall); }},
    {"infill_speed", [](const Known& k) { return macro_scalar(k.p.speed.sparse_infill); }},
    {"solid_infill_speed", [](const Known& k) { return macro_scalar(k.p.speed.solid_infill); }},
    {"top_solid_infill_speed", [](const Known& k) { return macro_scalar(k.p.speed.top_skin); }},
    {"support_material_speed", [](const Known& k) { return macro_scalar(k.p.speed.support); }},
    {"bridge_speed", [](const Known& k) { return macro_scalar(k.p.speed.bridge); }},
    {"first_layer_speed", [](const Known& k) { return macro_scalar(k.p.first_layer_speed); }},
    {"extrusion_width", [](const Known& k) { return macro_scalar(k.p.extrusion_width); }},
    {"first_layer_extrusion_width", [](const Known& k) { return macro_scalar(k.p.first_layer_width); }},
    {"machine_max_feedrate_x", [](const Known& k) { return macro_vector({k.p.motion.max_speed[0]}); }},
    {"machine_max_feedrate_y", [](const Known& k) { return macro_vector({k.p.motion.max_speed[1]}); }},
    {"machine_max_feedrate_z", [](const Known& k) { return macro_vector({k.p.motion.max_speed[2]}); }},
    {"machine_max_feedrate_e", [](const Known& k) { return macro_vector({k.p.motion.max_speed[3]}); }},
    {"machine_max_acceleration_x",
     [](const Known& k) { return macro_vector({k.p.motion.max_acceleration[0]}); }},
    {"machine_max_acceleration_y",
     [](const Known& k) { return macro_vector({k.p.motion.max_acceleration[1]}); }},
    {"machine_max_acceleration_z",
     [](const Known& k) { return macro_vector({k.p.motion.max_acceleration[2]}); }},
    {"machine_max_acceleration_e",
     [](const Known& k) { return macro_vector({k.p.motion.max_acceleration[3]}); }},
    {"machine_max_acceleration_extruding",
     [](const Known& k) { return macro_vector({k.p.motion.print_acceleration}); }},
    {"machine_max_acceleration_travel",
     [](const Known& k) { return macro_vector({k.p.motion.travel_acceleration}); }},
    {"machine_max_acceleration_retracting",
     [](const Known& k) { return macro_vector({k.p.motion.retract_acceleration}); }},
    {"use_relative_e_distances", [](const Known& k) { return macro_scalar(k.p.relative_e); }},
    {"gcode_flavor", [](const Known& k) { return macro_scalar(std::string(dialect_of(k.p.firmware).name)); }},
    {"printer_settings_id", [](const Known& k) { return macro_scalar(k.p.name); }},

    // The bed in G-code coordinates.
    {"print_bed_min", [](const Known& k) { return macro_vector({k.p.bed_origin_x, k.p.bed_origin_y}); }},
    {"print_bed_max",
     [](const Known& k) { return macro_vector({k.p.bed_origin_x + k.p.bed_x, k.p.bed_origin_y + k.p.bed_y}); }},
    {"print_bed_size", [](const Known& k) { return macro_vector({k.p.bed_x, k.p.bed_y}); }},

    {"layer_height", [](const Known& k) { return macro_scalar(k.slice.layer_height); }},
    {"first_layer_height", [](const Known& k) { return macro_scalar(k.p.first_layer_height); }},
    {"layer_z", [](const Known& k) { return macro_scalar(k.slice.max_layer_z); }},
    {"max_layer_z", [](const Known& k) { return macro_scalar(k.slice.max_layer_z); }},
    {"layer_num",
     [](const Known& k) {
       return macro_scalar(static_cast<long long>(k.slice.layer_count > 0 ? k.slice.layer_count - 1 : 0));
     }},
    {"total_layer_count",
     [](const Known& k) { return macro_scalar(static_cast<long long>(k.slice.layer_count)); }},
    {"first_layer_print_min",
     [](const Known& k) {
       const std::array<double, 4> b = first_layer_box(k);
       return macro_vector({b[0], b[1]});
     }},
    {"first_layer_print_max",
     [](const Known& k) {
       const std::array<double, 4> b = first_layer_box(k);
       return macro_vector({b[2], b[3]});
     }},
    {"first_layer_print_size",
     [](const Known& k) {
       const std::array<double, 4> b = first_layer_box(k);
       return macro_vector({b[2] - b[0], b[3] - b[1]});
     }},
    {"input_filename_base", [](const Known& k) { return macro_scalar(k.slice.input_filename_base); }},
    {"input_filename", [](const Known& k) { return macro_scalar(k.slice.input_filename_base + ".gcode"); }},

    // What mahost never does: one extruder, no wipe tower.
    {"current_extruder", [](const Known&) { return macro_scalar(0LL); }},
    {"initial_extruder", [](const Known&) { return macro_scalar(0LL); }},
    {"initial_tool", [](const Known&) { return macro_scalar(0LL); }},
    {"has_wipe_tower", [](const Known&) { return macro_scalar(false); }},
    {"has_single_extruder_multi_material_priming", [](const Known&) { return macro_scalar(false); }},
    {"wipe_tower", [](const Known&) { return macro_scalar(false); }},
    {"single_extruder_multi_material", [](const Known&) { return macro_scalar(false); }},
};

}  // namespace

MacroVariables prusa_variables(const Profiles& profiles, const PlaceholderValues& values) {
  const Known known{profiles.printer, profiles.material, values};
  MacroVariables v;
  for (const Placeholder& placeholder : kPlaceholders) v[placeholder.name] = placeholder.value(known);
  // The printer's gcode_constants, for names not above.
  for (const auto& [name, constant] : profiles.printer.gcode_constants) v.emplace(name, constant);
  return v;
}

}  // namespace printer
