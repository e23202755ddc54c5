// Supports, bridges and the raft: what a part with overhangs needs beyond its own layers so
// that nothing is extruded into air (DESIGN.md §1, the stage after the contours).
//
// Inputs:  regions[i], the region layer i really prints (any contour strategy; outer loops
//          CCW, holes CW, mm), layers[i] its bounds (z_lo, z_hi, mm; thicknesses may differ
//          from layer to layer); the options below.
// Outputs: per layer, the support it prints beside the part (sparse body and dense
//          interface regions) and the pieces of its region laid as bridges; the raft's
//          area and layers; how much higher the part then sits. The steps:
//   1. overhangs:  layer k's pieces that layer k-1 does not carry, by the overhang angle
//                  (overhang.h), specks dropped; inside an enforcer box every piece not
//                  over layer k-1, inside a blocker box none;
//   2. bridges:    a piece held on two sides (or all round) whose lines span at most
//                  bridge_length is a bridge (bridge_detector.h), not supported;
//   3. contacts:   the other pieces are what the support's top
//                  carries: the highest layer whose top is at least top_contact_distance
//                  below the piece's layer. Each is widened across the body's lines to the
//                  nearest line on either side and half a bead past it, along them only
//                  to a loop's width if shorter (with a grid, across both), so that every
//                  interface line over the sparse body
//                  ends on a body line instead of in the air between two (PrusaSlicer's
//                  support areas are snapped to its support grid the same way). What it
//                  costs, on a sphere (r 15 mm, compare_supports.sh's settings): interface
//                  109 mm of filament against 56 mm unwidened, for 64.5 mm of unsupported
//                  extrusion against 149 mm (CuraEngine, unwidened: 57 mm, 146 mm). Leaving
//                  the top interface layer unwidened where a widened one lies under it saves
//                  only 6 mm there (each layer of a sphere's underside is also the lower
//                  interface layer of the contact above) and costs 11.5 mm unsupported;
//   4. columns:    from each contact down to the bed (buildplate: contacts over any part
//                  of the layers below are dropped) or onto the part (everywhere), layer by
//                  layer: never within xy_gap of the part's region in the same layer, never
//                  under the part closer than top_contact_distance, never over it closer
//                  than bottom_contact_distance (so supports come off);
//   5. interfaces: the top interface_thickness of each column under a contact is dense:
//                  whole layers from the column's top down until they are that thick
//                  at least (rounded up to the layers there, as the gaps are);
//   6. raft:       under the first layer (part and support) grown by the raft's margin,
//                  holes filled: base, interface and surface layers, then the air gap.
// A contact within top_contact_distance of the bed has no layer to rest on: the bed,
// across the gap, carries it. With placement none nothing of 1-5 happens (no bridges
// either), and without a raft the plan is empty: the G-code is what it was without this
// stage.
// Deterministic, parallel over layers where layers are independent (TBB).
#pragma once

#include <optional>
#include <string_view>
#include <vector>

#include "geometry/core/polygon.h"
#include "geometry/mesh/mesh.h"
#include "geometry/slicing/layer_stack.h"

namespace geometry {

enum class SupportPlacement {
  none,        // no support, no bridges
  buildplate,  // columns only from the bed
  everywhere,  // columns from the bed or from the part's top surfaces
};

inline constexpr SupportPlacement kSupportPlacements[] = {
    SupportPlacement::none, SupportPlacement::buildplate, SupportPlacement::everywhere};

std::string_view support_placement_name(SupportPlacement placement);  // "none", ...
std::optional<SupportPlacement> parse_support_placement(std::string_view name);

// The support's sparse body: lines at one angle, or a grid of lines at it and 90 degrees on.
enum class SupportPattern { lines, grid };

std::string_view support_pattern_name(SupportPattern pattern);  // "lines", "grid"
std::optional<SupportPattern> parse_support_pattern(std::string_view name);

// An axis-aligned box in the part's frame (the frame of `regions` and `layers`), mm.
struct SupportBox {
  Vec3 min, max;
};

struct SupportOptions {
  SupportPlacement placement = SupportPlacement::none;
  double overhang_angle = 50;       // degrees from vertical a wall may lean unsupported
  double bead_width = 0.45;         // mm; a layer reaches at most half of it past the one below
  double min_area = 0.2;            // mm^2: smaller overhang pieces are left alone
  double xy_gap = 0.2;              // mm between support and the part in the same layer
  double top_contact_distance = 0.2;     // mm of air between the support's top and the part
  double bottom_contact_distance = 0.2;  // mm of air between the part and support on it
  // mm of dense layers at the top of each column, at least: whole layers down from its top
  // until they are this thick; 0: none.
  double interface_thickness = 0.4;
  double bridge_length = 10;        // mm a bridge may span; 0: nothing is bridged
  // The body's lines (toolpaths/support_paths.h lays them): contacts are widened to them.
  SupportPattern pattern = SupportPattern::lines;
  double line_spacing = 2.5;        // mm
  double line_angle = 0;            // degrees from +X
  std::vector<SupportBox> enforcers;  // every overhang inside is supported
  std::vector<SupportBox> blockers;   // no overhang inside is supported
};

struct RaftOptions {
  bool enabled = false;
  double margin = 3;            // mm the raft reaches past the first layer
  double air_gap = 0.2;         // mm between the raft's top and the part
  double base_thickness = 0.3;  // mm, one base layer
  int interface_layers = 1;
  int surface_layers = 2;
  double layer_thickness = 0.2;  // mm, each interface and surface layer
};

// A piece of a layer's region laid as a bridge: lines at `angle` (degrees from +X), the
// longest `span` mm between its anchors.
struct Bridge {
  Region area;
  double angle = 0;
  double span = 0;
};

struct LayerSupport {
  Region body;       // sparse support
  Region interface;  // dense support right under the part
  std::vector<Bridge> bridges;
};

enum class RaftPart { base, interface, surface };

struct RaftLayer {
  Layer bounds;  // from the bed, mm
  RaftPart part = RaftPart::base;
};

struct SupportPlan {
  std::vector<LayerSupport> layers;  // one per part layer, or none at all
  Region raft_area;
  std::vector<RaftLayer> raft;       // bottom first
  double lift = 0;                   // the part's layers sit this much higher, mm
  bool empty() const { return layers.empty() && raft.empty(); }
};

SupportPlan plan_supports(const std::vector<Region>& regions, const std::vector<Layer>& layers,
                          const SupportOptions& options, const RaftOptions& raft = {});

// The volume the support regions and the raft enclose (area x thickness), mm^3: what a
// solid fill of them would take; lines take a fraction of it.
double support_volume(const SupportPlan& plan, const std::vector<Layer>& layers);

}  // namespace geometry
