// PrusaSlicer's names for what mahost knows of a slice; see prusa_variables.h.
#include "printer/prusa_variables.h"

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

}  // namespace

MacroVariables prusa_variables(const Profiles& profiles, const PlaceholderValues& values) {
  const PrinterProfile& p = profiles.printer;
  const MaterialProfile& m = profiles.material;
  const int n = p.extruders;
  MacroVariables v;
  auto material = [&](std::string_view name, MacroScalar value) {
    v[std::string(name)] = per_extruder(std::move(value), n, "material");
  };
  material("temperature", whole(m.nozzle_temperature));
  material("first_layer_temperature", whole(m.first_layer_nozzle_temperature));
  material("bed_temperature", whole(m.bed_temperature));
  material("first_layer_bed_temperature", whole(m.first_layer_bed_temperature));
  material("filament_type", m.type.empty() ? m.name : m.type);
  material("filament_settings_id", m.name);
  material("filament_diameter", p.filament_diameter);
  material("extrusion_multiplier", m.flow);
  material("filament_density", m.density);
  auto nozzle = [&](std::string_view name, MacroScalar value) {
    v[std::string(name)] = per_extruder(std::move(value), n, "nozzle and retraction");
  };
  nozzle("nozzle_diameter", p.nozzle_diameter);
  nozzle("retract_length", p.retraction.length);
  nozzle("retract_speed", p.retraction.speed);
  nozzle("deretract_speed", p.retraction.prime_speed);
  nozzle("retract_lift", p.retraction.z_hop);
  nozzle("retract_before_travel", p.retraction.min_travel);
  nozzle("min_layer_height", p.layer.allowed.empty() ? p.layer.min : p.layer.allowed.front());
  nozzle("max_layer_height", p.layer.allowed.empty() ? p.layer.max : p.layer.allowed.back());

  v["max_print_height"] = macro_scalar(p.bed_z);
  v["z_offset"] = macro_scalar(0.0);
  const FeatureSpeeds& s = p.speed;
  for (const auto& [name, speed] : {std::pair{"travel_speed", s.travel}, {"travel_speed_z", s.z},
                                    {"perimeter_speed", s.inner_wall}, {"external_perimeter_speed", s.outer_wall},
                                    {"infill_speed", s.sparse_infill}, {"solid_infill_speed", s.solid_infill},
                                    {"top_solid_infill_speed", s.top_skin}, {"support_material_speed", s.support},
                                    {"bridge_speed", s.bridge}, {"first_layer_speed", p.first_layer_speed}}) {
    v[name] = macro_scalar(speed);
  }
  v["extrusion_width"] = macro_scalar(p.extrusion_width);
  v["first_layer_extrusion_width"] = macro_scalar(p.first_layer_width);
  // PrusaSlicer keeps two values of each limit (normal and silent mode); mahost one.
  const MotionLimits& limits = p.motion;
  const char* axes = "xyze";
  for (int axis = 0; axis < 4; ++axis) {
    v[fmt::format("machine_max_feedrate_{}", axes[axis])] = macro_vector({limits.max_speed[axis]});
    v[fmt::format("machine_max_acceleration_{}", axes[axis])] = macro_vector({limits.max_acceleration[axis]});
  }
  v["machine_max_acceleration_extruding"] = macro_vector({limits.print_acceleration});
  v["machine_max_acceleration_travel"] = macro_vector({limits.travel_acceleration});
  v["machine_max_acceleration_retracting"] = macro_vector({limits.retract_acceleration});
  v["use_relative_e_distances"] = macro_scalar(p.relative_e);
  v["gcode_flavor"] = macro_scalar(std::string(dialect_of(p.firmware).name));
  v["printer_settings_id"] = macro_scalar(p.name);

  const double x0 = p.bed_origin_x, y0 = p.bed_origin_y;
  v["print_bed_min"] = macro_vector({x0, y0});
  v["print_bed_max"] = macro_vector({x0 + p.bed_x, y0 + p.bed_y});
  v["print_bed_size"] = macro_vector({p.bed_x, p.bed_y});

  v["layer_height"] = macro_scalar(values.layer_height);
  v["first_layer_height"] = macro_scalar(p.first_layer_height);
  v["layer_z"] = macro_scalar(values.max_layer_z);
  v["max_layer_z"] = macro_scalar(values.max_layer_z);
  v["layer_num"] = macro_scalar(static_cast<long long>(values.layer_count > 0 ? values.layer_count - 1 : 0));
  v["total_layer_count"] = macro_scalar(static_cast<long long>(values.layer_count));
  const bool first_known = values.first_layer_min_x <= values.first_layer_max_x;
  const double cx = bed_centre_x(p), cy = bed_centre_y(p);
  const double min_x = first_known ? values.first_layer_min_x : cx;
  const double min_y = first_known ? values.first_layer_min_y : cy;
  const double max_x = first_known ? values.first_layer_max_x : cx;
  const double max_y = first_known ? values.first_layer_max_y : cy;
  v["first_layer_print_min"] = macro_vector({min_x, min_y});
  v["first_layer_print_max"] = macro_vector({max_x, max_y});
  v["first_layer_print_size"] = macro_vector({max_x - min_x, max_y - min_y});
  v["input_filename_base"] = macro_scalar(values.input_filename_base);
  v["input_filename"] = macro_scalar(values.input_filename_base + ".gcode");

  for (const char* name : {"current_extruder", "initial_extruder", "initial_tool"}) {
    v[name] = macro_scalar(0LL);
  }
  for (const char* name : {"has_wipe_tower", "has_single_extruder_multi_material_priming",
                           "wipe_tower", "single_extruder_multi_material"}) {
    v[name] = macro_scalar(false);
  }
  for (const auto& [name, constant] : p.gcode_constants) v.emplace(name, constant);
  return v;
}

}  // namespace printer
