// Clipper 1 operations the toolpath files share (perimeters, thin walls, skins, infill, skirt).
//
// All on Clipper paths in integer nanometres (clipper_bridge.h) with the non-zero fill rule:
// outer loops positive (CCW), holes negative (CW), as every Clipper result here is returned.
// Distances are given in mm. Every function accepts empty input and returns empty output.
#pragma once

#include <polyclipping/clipper.hpp>

#include <vector>

namespace geometry::toolpath_clipper {

using ClipperLib::Path;
using ClipperLib::Paths;

// Offset of a filled region by delta mm (negative shrinks). Sharp joins are mitred up to
// miter_limit times delta; round joins follow the arc within 5 um. The loops' orientation
// is taken as it is (outer loops CCW, holes CW; a stray speck of a hole outside the outer
// loop changes nothing). Loops of less than a square micrometre are dropped first, and so
// are those the offset closes, holes when growing and islands when shrinking, that are no
// more than 2 |delta| across.
Paths offset(const Paths& region, double delta, ClipperLib::JoinType join = ClipperLib::jtMiter,
             double miter_limit = 3.0);

// Shrink then grow by radius mm: removes every part narrower than 2 * radius.
Paths opening(const Paths& region, double radius);

Paths intersection(const Paths& a, const Paths& b);
Paths difference(const Paths& a, const Paths& b);
Paths union_of(const Paths& a, const Paths& b = {});

// Open polylines clipped to the inside of a filled region.
Paths clip_open(const Paths& lines, const Paths& region);

// Splits a region into islands: each outer loop with the holes directly inside it; an island
// inside a hole is an island of its own. In the order Clipper's tree lists them.
std::vector<Paths> islands(const Paths& region);

// Each loop with the vertices dropped that lie within `tolerance` mm of the simplified loop
// (Douglas-Peucker, a strict bound); loops left with fewer than 3 points are dropped. Not
// re-unioned: run union_of after it if the loops may now touch.
Paths simplified(const Paths& region, double tolerance);

// Net area in mm^2 (outer loops minus holes).
double area_mm2(const Paths& region);

}  // namespace geometry::toolpath_clipper
