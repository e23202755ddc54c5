// Toolpath plan: every layer's toolpaths, in print order, from the layers' regions
// (DESIGN.md §1).
//
// Inputs:  regions[i], the planar region layer i extrudes (any contour strategy: outer loops
//          CCW, holes CW, mm), and layers[i], its bounds (z_lo, z_hi in mm); options below.
// Outputs: one LayerToolpaths per layer (same count and order as `layers`; a layer without a
//          region or with an empty one gets no paths): on the first layer the skirt, then per
//          island, nearest first: inner walls, outer wall, thin walls (and gap fill),
//          skins, infill. An island's solid pieces (bottom and top skins, solid infill, and
//          sparse infill at 100%) share one set of lines; infill lines are joined into
//          zig-zags unless infill_lines says separate (infill.h, zigzag.h).
// Layer i uses regions[i] when i < regions.size(), else the empty region. Each region's edges
// are first straightened within 5 um (Douglas-Peucker), far below a printer's step.
// Seams (aligned): each closed path's seam stays near the seam of the same loop on the layer
// below, so that seams line up (travel_order.h: remembered_seam).
// Travel: the first path of every layer has retract_before set (the layer change); after
// that, a travel retracts when it leaves the region (crosses a wall, a hole or open air) and
// is longer than retract_min_travel; a travel inside the region never does (travel_order.h).
// The nozzle starts each layer where the previous one ended (layer 0: the region's
// front-left corner), and islands are visited nearest first.
//
// Total: empty regions, zero-thickness layers and regions thinner than a bead all give a
// defined plan (a region too thin for a loop gets a centre line). Options out of range are
// clamped to the nearest sane value (density to [0, 100], counts to >= 0, widths to > 0);
// validating what the user typed is the caller's job.
// Deterministic: the same input gives the same plan, whatever the number of threads.
//
// See also: perimeters.h, thin_walls.h, skins.h, infill.h, zigzag.h, skirt.h,
// travel_order.h, toolpaths.h.
#pragma once

#include <cstddef>
#include <functional>
#include <vector>

#include "geometry/toolpaths/infill.h"        // InfillPattern, infill_pattern_name, parse_infill_pattern
#include "geometry/slicing/layer_stack.h"
#include "geometry/core/polygon.h"
#include "geometry/support/support_plan.h"
#include "geometry/toolpaths/support_paths.h"  // SupportPattern, SupportPathOptions
#include "geometry/toolpaths/toolpaths.h"
#include "geometry/toolpaths/travel_order.h"  // SeamPosition, seam_position_name, parse_seam_position

namespace geometry {

// Defaults suit a 0.4 mm nozzle (PrusaSlicer's and Cura's usual settings).
struct ToolpathOptions {
  double extrusion_width = 0.45;    // bead width of walls, skins and infill, mm
  double first_layer_width = 0.5;   // bead width on layer 0 (better adhesion), mm
  int perimeters = 2;               // wall loops per island
  double infill_density = 20;       // sparse infill, percent of the area (0..100)
  InfillPattern infill_pattern = InfillPattern::grid;
  double infill_angle = 45;         // degrees from +X of the first layer's lines
  double infill_overlap = 0.15;     // infill reaches into the innermost wall, fraction of width
  int top_layers = 3;               // solid layers under every top surface
  int bottom_layers = 3;            // solid layers over every bottom surface
  double top_thickness = 0;         // ... and at least this thick, mm (skins.h; 0: no minimum)
  double bottom_thickness = 0;      // ... and at least this thick, mm
  int skirt_loops = 1;              // loops around the first layer; 0 for none
  double skirt_distance = 3.0;      // gap between the part and the skirt, mm
  double retract_min_travel = 2.0;  // a travel leaving the region retracts if longer, mm
  SeamPosition seam = SeamPosition::aligned;
  InfillLines infill_lines = InfillLines::connected;  // zig-zags along the edge, or separate
  // With a support plan only: the support's and the raft's lines, and the brim.
  SupportPathOptions support;
  double brim_width = 0;            // mm of brim round the first layer; 0 for none
  // Only the part's layers marked here get paths (empty: every layer); the rest are left
  // empty, for a print-time estimate from a sample of the layers (host's plan line).
  std::vector<char> planned;
};

// Called once per finished layer with the count of layers done so far, possibly from several
// threads at once (host::Progress::update is safe for that).
using LayerDone = std::function<void(std::size_t done)>;

std::vector<LayerToolpaths> plan_toolpaths(const std::vector<Region>& regions,
                                           const std::vector<Layer>& layers,
                                           const ToolpathOptions& options,
                                           const LayerDone& on_layer_done = {});

// The same with supports, bridges and a raft (geometry/support/support_plan.h):
//   raft layers first, each its own LayerToolpaths (support_paths.h), then the part's layers
//   `support.lift` higher; each part layer's support body and interface paths are islands
//   of their own in the nearest-first order, the body's lines joined by connectors only
//   where the layer above has interface or a wider body (what stands on the edge); bottom
//   skin over a bridge, reaching two beads into its anchors, is laid as bridge lines at the
//   bridge's angle (role bridge, solid spacing); the brim (brim.h) goes round the first
//   printed layer (the raft, or the part and its support), the skirt round that and the
//   brim; a travel that stays inside the part, its support or the raft does not retract.
// With an empty plan and no brim this is plan_toolpaths above, path for path.
std::vector<LayerToolpaths> plan_toolpaths(const std::vector<Region>& regions,
                                           const std::vector<Layer>& layers,
                                           const ToolpathOptions& options,
                                           const SupportPlan& support,
                                           const LayerDone& on_layer_done = {});

}  // namespace geometry
