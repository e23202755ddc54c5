// Zig-zag: parallel lines across an area, joined end to end along the area's edge, so that
// the nozzle lays many lines in one path instead of travelling (and retracting) between them
// (CuraEngine's "connect infill lines", PrusaSlicer's connected rectilinear infill).
//
// Inputs:  centre_area: where the beads' centre lines may run (mm, outer loops CCW, holes CW):
//            the area to fill shrunk by half a bead, so that a bead along its edge reaches
//            the edge of the area to fill.
//          lines: their direction (degrees from +X), spacing (mm, > 0) and offset: line k lies
//            at signed distance offset + k * spacing from the origin, measured along the
//            direction turned 90 degrees left.
//          max_connector: the longest stretch of the edge that may join two lines (mm); 0
//            joins none (separate lines).
//          fill_area: the area to fill (centre_area grown back by half a bead, or more): a
//            line end joined to nothing is carried on along its line to its edge, as a
//            separate line would be; nullptr leaves such ends on centre_area's edge.
// Output:  open paths of the given role and width. Each is line, connector, line, ...,
//          line: a connector follows centre_area's edge from the end of one line to the end
//          of the line next to it along the edge (on the same or the neighbouring scan
//          line). Lines shorter than a micrometre are dropped. Deterministic.
// Total: empty area, spacing <= 0 or more than a million lines give no paths.
#pragma once

#include <cmath>
#include <numbers>
#include <vector>

#include "geometry/core/polygon.h"
#include "geometry/toolpaths/toolpaths.h"

namespace geometry {

struct ScanLines {
  double angle = 0;    // direction, degrees from +X
  double spacing = 1;  // mm between neighbouring lines
  double offset = 0;   // mm: where line 0 lies across the direction
};

// The frame of lines at `angle_degrees`: into() turns a point by -angle, so that the lines
// run along +X at heights offset + k * spacing; out() turns it back. Shared by zig-zags and
// the separate lines of infill.cpp.
struct ScanFrame {
  double c, s;
  explicit ScanFrame(double angle_degrees)
      : c(std::cos(angle_degrees * std::numbers::pi / 180)),
        s(std::sin(angle_degrees * std::numbers::pi / 180)) {}
  Vec2 into(Vec2 p) const { return {p.x * c + p.y * s, -p.x * s + p.y * c}; }
  Vec2 out(Vec2 p) const { return {p.x * c - p.y * s, p.x * s + p.y * c}; }
};

std::vector<ExtrusionPath> zigzag(const Region& centre_area, const ScanLines& lines,
                                  double max_connector, const Region* fill_area, PathRole role,
                                  double width);

}  // namespace geometry
