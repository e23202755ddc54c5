// Bridges: which way to lay lines across an unsupported area so that both their ends rest on
// the layer below, and how far they span. PrusaSlicer's BridgeDetector
// tries directions the same way; CuraEngine's bridgeAngle joins the two largest islands the
// skin rests on, which is one of the directions tried here.
//
// Input:  area, the unsupported piece of a layer (mm, outer loops CCW, holes CW); anchors,
//         what it may rest on at its edges (the layer below near it); spacing, how far apart
//         the trial lines lie (mm, > 0).
// Output: for the best direction (degrees from +X, in [0, 180)): the share of the lines'
//         length inside `area` whose both ends land on an anchor, and the longest such line
//         (the span); the best direction has the largest share, then, among directions
//         within half a percent of it, the shortest span. Trial directions: every 10 degrees,
//         the direction between the centroids of the two largest anchors, then every 2.5
//         degrees within 10 of the best. A first look along 0, 45, 90, 135 degrees and that
//         centroid direction, with at most 8 lines across, turns away pieces held on one
//         side (under half their lines held at both ends): most overhangs are such bands.
// `anchored` is true when that share is at least 98%: the area is held on two (or more)
// sides, or all round (a hole covered over), and lines across it bridge.
// Total: empty area, empty anchors or spacing <= 0 give anchored = false, span 0.
#pragma once

#include <polyclipping/clipper.hpp>

#include "geometry/core/polygon.h"

namespace geometry {

struct BridgeDirection {
  bool anchored = false;
  double angle = 0;           // degrees from +X
  double span = 0;            // mm, the longest line anchored at both ends
  double anchored_share = 0;  // 0..1
};

BridgeDirection bridge_direction(const Region& area, const Region& anchors, double spacing);
BridgeDirection bridge_direction(const ClipperLib::Paths& area, const ClipperLib::Paths& anchors,
                                 double spacing);

}  // namespace geometry
