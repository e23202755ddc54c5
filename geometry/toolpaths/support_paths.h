// Support and raft toolpaths: the lines that fill a layer's support regions and the raft's
// layers (the regions come from geometry/support/support_plan.h).
//
// Support body: with `sheath`, of a loop round each island (PrusaSlicer's support sheath)
//   the stretches that carry the edges of what stands on the body where the part cut its
//   island along the lines, off them (support_sheath below); inside it lines `spacing` apart at `angle` (lines) or at angle and angle + 90
//   (grid), on a grid fixed in the part's frame, so that the lines of every layer stack on
//   those of the layer below; joined into zig-zags along the edge (connectors up to two
//   spacings; with options.connectors), role support.
// Support interface: per island a loop round its edge, half a bead in (an island narrower
//   than a bead gets nothing), so that the beads reach the edge whatever its shape, and
//   inside it separate lines at angle + 90, across the body's lines below them, at `density`
//   percent of solid (spacing = bead share * 100 / density), each from the loop's centre
//   line to its centre line, so that both its ends rest where the loop does; role
//   support_interface.
// Raft: base lines (`base_width` wide, `base_spacing` apart, at 0 degrees), interface lines
//   across them (the bead width, `interface_spacing` apart, at 90 degrees), each in a loop
//   round the raft's edge, lines and loop as the interface's (so the interface's line ends
//   and loop rest on the base's loop), surface layers solid (at 45 and 135 degrees,
//   alternating), all role raft.
// Beads are `width` wide on a layer `height` thick; lines lie inside the region, each bead's
// side on its edge at most. Empty regions, width <= 0 or spacing <= 0 give no paths.
#pragma once

#include <polyclipping/clipper.hpp>

#include <cstddef>
#include <optional>
#include <string_view>
#include <vector>

#include "geometry/core/polygon.h"
#include "geometry/support/support_plan.h"
#include "geometry/toolpaths/toolpaths.h"

namespace geometry {

struct SupportPathOptions {
  SupportPattern pattern = SupportPattern::lines;
  bool sheath = true;              // a loop round the body's islands
  // The body's lines joined into zig-zags along the edge (plan_toolpaths keeps them only
  // under an edge that carries something: toolpath_plan.cpp).
  bool connectors = true;
  double spacing = 2.5;            // mm between the body's lines
  double angle = 0;                // degrees from +X, the body's lines
  double interface_density = 80;   // percent of solid
  double raft_base_width = 0.8;    // mm
  double raft_base_spacing = 2.0;  // mm
  double raft_interface_spacing = 1.0;  // mm
};

// The sheath: of a loop half a bead inside the edge of each island of `support` (a layer's
// body and interface), what lies in `body` and its lines do not stand in for: with lines,
// the loop's stretches that run along them (within 45 degrees) farther than a quarter bead
// from the nearest line on the body's side (across the lines, what stands on the edge
// bridges from line to line; on a line, the line carries it); with a grid, all of it.
// `paths`: open stretches, or a closed loop where all of one is kept; role support.
// `beads`: their beads (open ends cut square), mm. None without options.sheath.
struct SupportSheath {
  std::vector<ExtrusionPath> paths;
  ClipperLib::Paths beads;
};
SupportSheath support_sheath(const ClipperLib::Paths& support, const Region& body, double width,
                             const SupportPathOptions& options);

// `sheath`: support_sheath's of the body; `carried`: where the layer below carries a sheath
// (its own sheath's bead, and the part); only the sheath's pieces over it are laid (a part
// receding under a steep overhang moves the body's edge, and its sheath, out by more than
// half a bead each layer: a sheath there would hang between the lines below). nullptr: all
// of it (on the bed). The lines run half a bead in from the body's edge and a bead off the
// sheath's centre line.
std::vector<ExtrusionPath> support_body_paths(const Region& body, double width,
                                              const SupportPathOptions& options,
                                              const SupportSheath& sheath, const Region* carried);
// The same with the body's own support_sheath.
std::vector<ExtrusionPath> support_body_paths(const Region& body, double width,
                                              const SupportPathOptions& options,
                                              const Region* carried = nullptr);
std::vector<ExtrusionPath> support_interface_paths(const Region& interface, double width,
                                                   double height,
                                                   const SupportPathOptions& options);

// The paths of raft layer `index` (0 = the base), of kind `part`, over `area`.
std::vector<ExtrusionPath> raft_paths(const Region& area, RaftPart part, std::size_t index,
                                      double width, double height,
                                      const SupportPathOptions& options);

}  // namespace geometry
