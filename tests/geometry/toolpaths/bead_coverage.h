// What a set of toolpaths deposits, rebuilt as polygons, for the toolpath tests.
//
// Each path becomes its bead: the path offset by width/2 on both sides, with round ends and
// joins (the nozzle leaves a round blob where a bead starts and stops). The coverage of a
// region compares the union of the beads with the region (areas in mm^2). Ends::cut takes
// open paths' ends as cut square at their end points instead ("segment x width", as
// tests/support/gcode_beads reads a printed program): no bead reaches past its end.
#pragma once

#include <cmath>
#include <vector>

#include "geometry/core/clipper.h"
#include "geometry/core/polygon.h"
#include "geometry/toolpaths/toolpaths.h"

namespace bead_coverage {

enum class Ends { round, cut };

using geometry::clipper::area_mm2;

inline ClipperLib::Paths bead(const geometry::ExtrusionPath& path, Ends ends = Ends::round) {
  ClipperLib::Path line = geometry::to_clipper(path.points);
  const bool closed = path.points.size() > 2 && path.points.front() == path.points.back();
  if (closed) line.pop_back();
  const ClipperLib::EndType end = closed                ? ClipperLib::etClosedLine
                                  : ends == Ends::round ? ClipperLib::etOpenRound
                                                        : ClipperLib::etOpenButt;
  return geometry::clipper::library_offset({line}, path.width / 2, ClipperLib::jtRound, end,
                                           0.002);
}

inline ClipperLib::Paths beads(const std::vector<geometry::ExtrusionPath>& paths,
                               Ends ends = Ends::round) {
  ClipperLib::Paths all;
  for (const auto& path : paths) {
    const ClipperLib::Paths one = bead(path, ends);
    all.insert(all.end(), one.begin(), one.end());
  }
  return geometry::clipper::union_nonzero(all);
}

struct Coverage {
  double inside = 0;   // fraction of the region's area under some bead
  double outside = 0;  // bead area outside the region, as a fraction of the region's area
  // Material laid (length x width of every path) beyond the area the beads cover: where
  // beads lie on top of each other, as a fraction of the region's area.
  double double_coverage = 0;
};

inline double laid_area(const std::vector<geometry::ExtrusionPath>& paths) {
  double total = 0;
  for (const auto& path : paths) {
    for (std::size_t i = 0; i + 1 < path.points.size(); ++i) {
      const geometry::Vec2 d = path.points[i + 1] - path.points[i];
      total += std::hypot(d.x, d.y) * path.width;
    }
  }
  return total;
}

inline Coverage coverage(const geometry::Region& region,
                         const std::vector<geometry::ExtrusionPath>& paths,
                         Ends ends = Ends::round) {
  const ClipperLib::Paths target = geometry::to_clipper(region);
  const ClipperLib::Paths laid = beads(paths, ends);
  const double whole = area_mm2(target);
  Coverage c;
  if (whole <= 0) return c;
  c.inside = area_mm2(geometry::clipper::intersection(target, laid)) / whole;
  c.outside = area_mm2(geometry::clipper::difference(laid, target)) / whole;
  c.double_coverage = (laid_area(paths) - area_mm2(laid)) / whole;
  return c;
}

}  // namespace bead_coverage
