// The unsupported-extrusion check: how much of what the printer laid has nothing under it.
// Independent of the slicer: it reads only the deposition record, the moves the
// (simulated) firmware executed, so it judges the toolpaths, the supports and the G-code
// writer together, and G-code from any slicer.
//
// Rule. Every extruding move of layer k > 0 must rest on the layer below over at least half
// its width, or be part of a bridge: a stretch of an extrusion over air whose two ends are on
// the layer below and which is at most bridge_length long. In detail, per layer k:
//   - the beads below: each move widened to its bead width (the bead model inverted, at the
//     layer's height; consecutive moves of an extrusion joined round), of layer k-1 and, across
//     an air gap, of the layers further down that a bead may sag onto: layer j counts while
//     the layer above j reaches higher than layer k's bottom minus contact_gap (the support's
//     top contact distance, which a slicer rounds up to whole layers). The bed is a layer
//     below layer 0 (with a gap, layer 1 may sag onto it);
//   - "half its width": the centre line over the beads below, after closing them by a
//     quarter of layer k's median bead width (a gap up to half a bead between two beads
//     below still carries the bead over it, as it does half its width on either side), and
//     within `tolerance` of them (the G-code's resolution and rounding);
//   - each piece of a centre line off them is unsupported unless both its ends lie on them
//     and it is at most bridge_length long;
//   - an unsupported piece whose middle lies among the beads below (inside them closed by
//     `sparse_reach`: between the lines of a sparse infill or support body) is counted as
//     between sparse lines, the rest as in the open (beyond everything below: into air).
// Layer 0 rests on the bed. Layers are the record's Z levels (sim/deposition.h), so a print
// resumed mid-layer folds into the layer it left.
// Output: extruded length (all layers), unsupported length, per layer, and the first
// stretches found (for messages and tests). Units mm.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "geometry/core/polygon.h"
#include "sim/deposition.h"

namespace sim {

struct SupportCheckOptions {
  double filament_diameter = 1.75;  // mm, for the bead widths
  double bridge_length = 10;        // mm an unsupported stretch held at both ends may span
  double contact_gap = 0;           // mm of air a bead may sag across onto the beads below
  double tolerance = 0.025;         // mm
  double sparse_reach = 3;          // mm: beads up to twice this apart enclose what is between
  std::size_t stretches_kept = 20;  // how many stretches to list
};

struct UnsupportedStretch {
  int layer = 0;
  double z = 0;
  geometry::Vec2 from, to;
  double length = 0;     // mm along the extrusion
  bool anchored = false;  // both ends rest on the layer below (too long a bridge)
  bool between = false;   // among the beads below, between sparse lines
};

struct SupportCheck {
  double extruded_mm = 0;     // length of every extruding move, all layers
  double unsupported_mm = 0;
  double between_mm = 0;      // of it, between sparse lines below
  std::vector<double> unsupported_per_layer;  // mm, per Z level
  std::vector<UnsupportedStretch> stretches;  // the first ones, in layer order
};

SupportCheck check_unsupported_extrusion(const DepositionRecord& record,
                                         const SupportCheckOptions& options = {});

// "unsupported extrusion: 0.0 mm of 148.2 m (0.00%; ...)" and, when some is, how much of it
// is in the open and how much between sparse lines below.
std::string unsupported_summary(const SupportCheck& check, const SupportCheckOptions& options);

}  // namespace sim
