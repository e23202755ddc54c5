#include "geometry/toolpaths/toolpaths.h"

namespace geometry {

// Cura's ;TYPE: words where one exists (viewers colour by them); one distinct word per role
// so a G-code reader can map the comment back to the role.
std::string_view role_name(PathRole role) {
  switch (role) {
    case PathRole::skirt: return "SKIRT";
    case PathRole::outer_wall: return "WALL-OUTER";
    case PathRole::inner_wall: return "WALL-INNER";
    case PathRole::thin_wall: return "WALL-THIN";
    case PathRole::bottom_skin: return "SKIN-BOTTOM";
    case PathRole::top_skin: return "SKIN-TOP";
    case PathRole::solid_infill: return "FILL-SOLID";
    case PathRole::sparse_infill: return "FILL";
    // Cura's words for support; Cura prints bridges as SKIN and the brim as SKIRT, but each
    // role needs a word of its own (PrusaSlicer's: "Bridge infill", "Skirt/Brim").
    case PathRole::support: return "SUPPORT";
    case PathRole::support_interface: return "SUPPORT-INTERFACE";
    case PathRole::bridge: return "BRIDGE";
    case PathRole::brim: return "BRIM";
    case PathRole::raft: return "RAFT";
  }
  return "UNKNOWN";
}

bool is_support_role(PathRole role) {
  return role == PathRole::support || role == PathRole::support_interface ||
         role == PathRole::raft;
}

}  // namespace geometry
