// Toolpaths: what the nozzle traces on each layer, in print order (DESIGN.md §1).
//
// Pure geometry: the G-code writer (printer/) turns these into moves, speeds and extrusion.
// Coordinates in mm, in the part's frame (the writer adds the bed offset).
#pragma once

#include <string_view>
#include <vector>

#include "geometry/core/polygon.h"

namespace geometry {

enum class PathRole { skirt, outer_wall, inner_wall, thin_wall, bottom_skin, top_skin,
                      solid_infill, sparse_infill, support, support_interface, bridge, brim,
                      raft };

// "SKIRT", "WALL-OUTER", ..., "SUPPORT", "SUPPORT-INTERFACE", "BRIDGE", "BRIM", "RAFT" for
// ;TYPE: comments.
std::string_view role_name(PathRole role);

// Support, support interface and raft: what is printed only to carry the part.
bool is_support_role(PathRole role);

struct ExtrusionPath {
  PathRole role = PathRole::outer_wall;
  std::vector<Vec2> points;  // a closed path ends where it began: the last point repeats the first
  double width = 0;          // bead width, mm
  bool retract_before = false;  // the travel to this path's first point needs a retraction
};

struct LayerToolpaths {
  double z_lo = 0, z_hi = 0;  // the nozzle prints at z_hi; the bead is z_hi - z_lo tall
  std::vector<ExtrusionPath> paths;  // in print order
};

}  // namespace geometry
