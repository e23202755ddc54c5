// The one layer between our millimetre Regions and Clipper 1 (libpolyclipping-dev): every 2D
// boolean, offset and conversion to Clipper's integer paths in geometry/ goes through here.
// Clipper's engines (ClipperLib::Clipper, ClipperLib::ClipperOffset) run in core/clipper*.cpp
// only; other files hold Clipper's path types and call its path helpers (Area, Orientation,
// ReversePath, CleanPolygons).
//
// Grids. Clipper works on 64-bit integers. Everything is on the nanometre grid,
// kClipperScale units per mm, which keeps a bed-sized part inside Clipper's fast low range
// (|coordinate| < 2^30 units, 1073 mm), except the volume integrals of slab_columns.h, on a
// picometre grid (kFineClipperScale; slab_columns.h says why) with the same operations.
//
// Fill rules. A Region has the non-zero rule (outer loops CCW, holes CW), and so have the
// operations here and their results, unless named `positive`: those fill where the loops' sum
// of windings is positive, for paths built as a sum of windings (a hole's loop reversed takes
// away what the loop round it adds), such as the medial-axis contour's islands and the grown
// footprint's raw offsets. Lengths are given in mm unless a name says units. Every function
// accepts empty input and returns empty output.
#pragma once

#include <polyclipping/clipper.hpp>

#include <vector>

#include "geometry/core/polygon.h"

namespace geometry {

inline constexpr double kClipperScale = 1e6;      // units per mm: 1 unit = 1 nm
inline constexpr double kFineClipperScale = 1e9;  // units per mm of the fine grid: 1 pm

// A length or coordinate already in units, rounded to the nearest unit, halves away from
// zero (std::llround's result) without the library call: v minus its truncation is exact
// for |v| < 2^53, so the comparisons with 0.5 decide as llround does. Inline: the offsets
// round every point they make.
inline ClipperLib::cInt rounded_units(double v) {
  const auto whole = static_cast<ClipperLib::cInt>(v);
  const double rest = v - static_cast<double>(whole);
  return rest >= 0.5 ? whole + 1 : (rest <= -0.5 ? whole - 1 : whole);
}

// Clipper's own rounding (ClipperLib's Round: v + 0.5 or v - 0.5, truncated), which differs
// from rounded_units where v + 0.5 itself rounds (v within an ulp below a half): for code that
// must make the very points ClipperOffset makes (the slab's grown footprint, slab.cpp).
inline ClipperLib::cInt clipper_rounded(double v) {
  return static_cast<ClipperLib::cInt>(v < 0 ? v - 0.5 : v + 0.5);
}

// Millimetres to the nanometre grid (rounded_units) and back.
ClipperLib::IntPoint to_clipper(Vec2 p);
Vec2 from_clipper(const ClipperLib::IntPoint& p);
ClipperLib::Path to_clipper(const Loop& loop);
ClipperLib::Paths to_clipper(const Region& region);
Loop from_clipper(const ClipperLib::Path& path);
Region from_clipper(const ClipperLib::Paths& paths);
// Outer loops CCW and holes CW, from any PolyTree Clipper produced.
Region from_clipper(const ClipperLib::PolyTree& tree);

// Millimetres to the picometre grid and back.
ClipperLib::Path to_fine_clipper(const Loop& loop);
ClipperLib::Paths to_fine_clipper(const Region& region);
Vec2 from_fine_clipper(const ClipperLib::IntPoint& p);

namespace clipper {

using ClipperLib::IntPoint;
using ClipperLib::Path;
using ClipperLib::Paths;
using ClipperLib::PolyTree;

// Booleans, non-zero.
Paths intersection(const Paths& a, const Paths& b);
Paths difference(const Paths& a, const Paths& b);
// What lies in exactly one of a and b (tests and benchmarks compare regions by its area).
Paths symmetric_difference(const Paths& a, const Paths& b);
// The union of a and b (each loop of either), normalised: simple loops, holes CW.
Paths union_nonzero(const Paths& a, const Paths& b = {});
// The same as Clipper's nesting (outer loops, their holes as children, islands in holes
// below them); the tree is the caller's (a PolyTree cannot be copied), returned for chaining.
PolyTree& union_nonzero_tree(const Paths& paths, PolyTree& tree);

// Booleans, positive: where a's windings sum to more than 0, or b's do (each set summed on its
// own, so a set may carry reversed loops that cancel its own parts, not the other's).
Paths union_positive(const Paths& a, const Paths& b = {});
PolyTree& union_positive_tree(const Paths& paths, PolyTree& tree);

// Open polylines clipped to the inside of a filled region. Clipper hands each piece back in
// either direction, and a closed line (last point = first) that the region's edge cuts comes
// back cut at its first point too.
Paths clip_open(const Paths& lines, const Paths& region);
// The same with pieces that meet end to end joined into one, whichever way round each came
// back: a closed line is cut only where it crosses the region's edge (and is whole, last
// point = first, where it does not).
Paths clip_open_joined(const Paths& lines, const Paths& region);

// Whether every point of `inner` lies inside `outer` (both non-zero) with their boundaries
// apart: no edge of one meets an edge of the other, each loop of inner lies inside outer and
// no loop of outer inside inner. Then difference(inner, outer) is nothing, up to the slivers
// of a unit or two Clipper's rounding may leave where edges pass within a unit of each other.
// A proof, not a test: false also where an edge crosses more than 64 cells of the grid the
// edges are compared on (about one edge per cell over the boxes' overlap). Empty inner: true.
// Cost: a pass over the edges of both, and of the loops of each for one point of the other's.
bool proven_inside(const Paths& inner, const Paths& outer);

// Whether every point of the polylines `lines` (each also closed from its last point back to
// its first) lies outside `region` (non-zero), on none of its edges: no edge of one meets an
// edge of the other, and the region winds 0 times round each line's first point. Then
// clip_open(lines, region) is nothing. A proof, not a test: false also where an edge crosses
// more than 64 cells of the grid the edges are compared on. Empty lines or region: true.
// Cost: a pass over the edges of both, and of the region's loops for each line's first point.
bool proven_outside(const Paths& lines, const Paths& region);

// Splits a region into islands: each outer loop with the holes directly inside it; an island
// inside a hole is an island of its own. In the order Clipper's tree lists them.
std::vector<Paths> islands(const Paths& region);
// The islands of a union's tree (union_nonzero_tree), in its order: what islands() gives
// where it sweeps.
std::vector<Paths> islands(const PolyTree& tree);

// Offset of a filled region by delta mm (negative shrinks). Sharp joins are mitred up to
// miter_limit times delta; round joins follow the arc within 5 um. The loops' orientation
// is taken as it is (outer loops CCW, holes CW; a stray speck of a hole outside the outer
// loop changes nothing). Loops of less than a square micrometre are dropped first, and so
// are those the offset closes, holes when growing and islands when shrinking, that are no
// more than 2 |delta| across. Its own implementation (clipper_offset.cpp), ClipperOffset's
// joins without most of the union it costs: where the raw loops are a region as they stand
// they are the offset, and a lone loop that goes back through vertices is Clipper's union
// of it where union_of_folded_loop finds that; otherwise Clipper's union.
Paths offset(const Paths& region, double delta, ClipperLib::JoinType join = ClipperLib::jtMiter,
             double miter_limit = 3.0);

// offset(region, delta, join, miter_limit).empty(), without the union where a point is found
// that the raw loops the offset is made of wind round once or more, clear of their edges (an
// outer loop's centroid, in a part wide enough): that point lies in the offset. Elsewhere the
// offset itself. Cost: the raw loops and a pass over their edges per point tried, a fraction
// of the offset's where that settles it.
bool offset_is_empty(const Paths& region, double delta, ClipperLib::JoinType join = ClipperLib::jtMiter,
                     double miter_limit = 3.0);

// Clipper's union with the positive rule of one loop that runs CCW and crosses itself in
// folds, such as an offset's raw loop where it went back through vertices (folds that may
// nest and share edges): into `out`, point for point and from the same start as
// union_positive({loop}) gives it, without the sweep where the union is one loop without
// holes and the crossings lie where the sweep finds them; returns false, and leaves `out`
// unspecified, where not (then union_positive is the answer). Cost: a grid of the edges to
// find the crossings, about a fifth of Clipper's union of the loop. Of the 3,687 single-loop
// offsets of the bunny's mid slice at 0.15 mm that the raw loops did not settle, the traced
// boundary alone takes 3,129, each the very loop Clipper makes (cutting folds alone: 1,833).
bool union_of_folded_loop(const Path& loop, Path& out);

// Clipper's islands (islands()) of loops that each run CCW and meet nowhere, without the
// sweep: no point repeated or in line with its neighbours, no edges crossing or touching, no
// loop inside another. Into `out`: each loop an island of its own, started where Clipper's
// union starts a loop (the point after its least y), in the order its tree lists them (the
// greatest y first). False, and `out` unspecified, where the loops are not such, two points of
// a loop share its least y or two loops their greatest y (then the union is the answer).
// Cost: a pass over the edges on a grid of about one edge per cell.
bool islands_of_loops_apart(const Paths& region, std::vector<Paths>& out);

// Shrink then grow by radius mm: removes every part narrower than 2 * radius.
Paths opening(const Paths& region, double radius);

// Clipper's own offset (ClipperOffset, its union included), for what `offset` does not take:
// open lines (end etOpenRound, etOpenSquare, etOpenButt), closed lines grown to both sides
// (etClosedLine), and closed polygons where ClipperOffset's very points matter. delta and
// arc_tolerance in mm (arc_tolerance: how far round joins and ends may be off the arc).
Paths library_offset(const Paths& paths, double delta, ClipperLib::JoinType join,
                     ClipperLib::EndType end, double arc_tolerance, double miter_limit = 2.0);

// Each loop with the vertices dropped that lie within `tolerance` mm of the simplified loop
// (Douglas-Peucker, a strict bound); loops left with fewer than 3 points are dropped. Not
// re-unioned: run union_nonzero after it if the loops may now touch.
Paths simplified(const Paths& region, double tolerance);

// The smallest box holding the points, as ClipperLib's IntRect: x in [left, right], y in
// [top, bottom] (top is the least y). No points: an empty box, left > right, which meets
// nothing and which add_to_box grows from.
ClipperLib::IntRect bounding_box(const Path& path);
ClipperLib::IntRect bounding_box(const Paths& paths);
void add_to_box(ClipperLib::IntRect& box, const ClipperLib::IntRect& other);
inline bool boxes_meet(const ClipperLib::IntRect& a, const ClipperLib::IntRect& b) {
  return a.left <= b.right && b.left <= a.right && a.top <= b.bottom && b.top <= a.bottom;
}

// Net area (outer loops minus holes, each loop's own sign), in units^2 of the paths' grid.
double area_units2(const Paths& paths);
// The same in mm^2, for paths on the nanometre grid.
double area_mm2(const Paths& region);

}  // namespace clipper

}  // namespace geometry
