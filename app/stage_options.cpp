// The profiles' settings as the stages take them; see stage_options.h.
#include "app/stage_options.h"

#include <algorithm>

namespace app {

geometry::ToolpathOptions toolpath_options(const printer::PrinterProfile& machine) {
  geometry::ToolpathOptions options;
  options.extrusion_width = machine.extrusion_width;
  options.first_layer_width = machine.first_layer_width;
  options.perimeters = machine.print.perimeters;
  options.infill_density = machine.print.infill_density;
  // The profile's values were checked on load; the fallbacks are never taken.
  options.infill_pattern = geometry::parse_infill_pattern(machine.print.infill_pattern)
                               .value_or(geometry::InfillPattern::grid);
  options.top_layers = machine.print.top_layers;
  options.bottom_layers = machine.print.bottom_layers;
  options.top_thickness = machine.print.top_thickness;
  options.bottom_thickness = machine.print.bottom_thickness;
  options.skirt_loops = machine.print.skirt_loops;
  options.skirt_distance = machine.print.skirt_distance;
  options.retract_min_travel = machine.retraction.min_travel;
  options.seam = geometry::parse_seam_position(machine.print.seam)
                     .value_or(geometry::SeamPosition::aligned);
  options.support.pattern = geometry::parse_support_pattern(machine.support.pattern)
                                .value_or(geometry::SupportPattern::lines);
  options.support.spacing = machine.support.spacing;
  options.support.sheath = machine.support.sheath;
  options.support.angle = machine.support.angle;
  options.support.interface_density = machine.support.interface_density;
  options.support.raft_base_width = machine.raft.base_width;
  options.support.raft_base_spacing = machine.raft.base_spacing;
  options.support.raft_interface_spacing = machine.raft.interface_spacing;
  options.brim_width = machine.brim_width;
  return options;
}

// The profile's support settings in the part's frame: boxes are given on the bed (the
// G-code's X and Y), and the part is centred on the bed.
geometry::SupportOptions support_options(const printer::Profiles& profiles) {
  const printer::PrinterProfile& machine = profiles.printer;
  const printer::SupportSettings& s = machine.support;
  geometry::SupportOptions options;
  options.placement =
      geometry::parse_support_placement(s.type).value_or(geometry::SupportPlacement::none);
  options.overhang_angle = profiles.material.overhang_angle;
  options.bead_width = machine.extrusion_width;
  options.min_area = s.min_area;
  options.xy_gap = s.xy_gap;
  options.top_contact_distance = s.top_contact_distance;
  options.bottom_contact_distance = s.bottom_contact_distance;
  options.interface_thickness = s.interface_thickness;
  options.bridge_length = profiles.material.bridge_length;
  options.pattern = geometry::parse_support_pattern(s.pattern).value_or(geometry::SupportPattern::lines);
  options.line_spacing = s.spacing;
  options.line_angle = s.angle;
  const double cx = printer::bed_centre_x(machine), cy = printer::bed_centre_y(machine);
  auto part_box = [&](const printer::SupportBoxMm& b) {
    return geometry::SupportBox{{b[0] - cx, b[1] - cy, b[2]}, {b[3] - cx, b[4] - cy, b[5]}};
  };
  for (const auto& b : s.enforcers) options.enforcers.push_back(part_box(b));
  for (const auto& b : s.blockers) options.blockers.push_back(part_box(b));
  return options;
}

geometry::RaftOptions raft_options(const printer::PrinterProfile& machine) {
  const printer::RaftSettings& r = machine.raft;
  geometry::RaftOptions options;
  options.enabled = r.enabled;
  options.margin = r.margin;
  options.air_gap = r.air_gap;
  options.base_thickness = r.base_thickness;
  options.interface_layers = r.interface_layers;
  options.surface_layers = r.surface_layers;
  options.layer_thickness = r.layer_thickness;
  return options;
}

double raft_height(const printer::RaftSettings& r) {
  if (!r.enabled) return 0;
  return r.base_thickness + (r.interface_layers + r.surface_layers) * r.layer_thickness + r.air_gap;
}


geometry::SupportCost support_cost(const printer::PrinterProfile& machine) {
  const printer::SupportSettings& s = machine.support;
  geometry::SupportCost cost;
  const double sets = s.pattern == "grid" ? 2 : 1;
  cost.body_share = s.spacing > 0 ? std::min(1.0, sets * machine.extrusion_width / s.spacing) : 1;
  cost.interface_share = std::clamp(s.interface_density / 100, 0.0, 1.0);
  cost.interface_thickness = s.interface_thickness;
  cost.top_gap = s.top_contact_distance;
  cost.bottom_gap = s.bottom_contact_distance;
  return cost;
}

sim::SupportCheckOptions support_check_options(const printer::Profiles& profiles) {
  sim::SupportCheckOptions options;
  options.filament_diameter = profiles.printer.filament_diameter;
  options.bridge_length = profiles.material.bridge_length;
  options.contact_gap = std::max(profiles.printer.support.top_contact_distance,
                                 profiles.printer.support.bottom_contact_distance);
  return options;
}

}  // namespace app
