// Steps 4 and 5 of the medial-axis contour (paper §3.3, Fig. 17: "a simple fairing process is
// carried out by adding more sampling points locally"): where the contour crosses a Delaunay
// edge, and the contour between two such crossings.
//
// Unfaired, a crossing is the edge's midpoint: the sampled axis, aliased where the strip is
// thin next to the spacing. Faired, it is the point of the edge equidistant from the two
// boundary polygons (the loops, not their samples, so the sampling's aliasing is gone), and
// between two crossings new vertices go on that exact axis wherever the chord's middle is off
// it by more than kFairingTolerance, recursively; the faired loop is then simplified within
// a quarter of that. Distances are to the few loops round the edge (AxisQuery). All mm.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "geometry/contour/ma/samples.h"
#include "geometry/core/polygon.h"

namespace geometry::ma {

// How far off the medial axis the middle of a contour edge may be before fairing adds a
// vertex there, mm; and how deep it may split one edge.
inline constexpr double kFairingTolerance = 0.001;
inline constexpr int kFairingDepth = 6;
// How far, mm, simplifying the faired contour may move it: a quarter of the fairing tolerance.
inline constexpr double kSimplifyTolerance = 0.25 * kFairingTolerance;

// A boundary loop as fairing's distance walks read it: per edge j (vertex j to the next, the
// last back to the first) its start, b - a and squared length, computed once per island where
// a walk would recompute them at every edge it visits (each edge is visited a dozen times).
// An edge whose squared length is not positive (a repeated vertex) has ab = 0 and length 0.
struct LoopEdges {
  struct Edge {
    Vec2 a, ab;
    double length2;
  };
  const Loop* loop = nullptr;
  std::vector<Edge> edges;
  explicit LoopEdges(const Loop& loop);
};

// Where the medial axis is looked for: the loops of the samples round one Delaunay edge (its
// two ends and the two opposite corners), with each one's nearest edge so far. Where three
// loops meet (islands merging in the slab) the nearest solid loop need not be the edge's own.
struct AxisQuery {
  struct Near {
    const LoopEdges* loop;
    std::uint32_t segment;
  };
  std::array<Near, 3> solid_side{}, empty_side{};
  int solid_count = 0, empty_count = 0;

  void add(bool solid, const LoopEdges* loop, std::uint32_t segment) {
    auto& side = solid ? solid_side : empty_side;
    int& count = solid ? solid_count : empty_count;
    for (int k = 0; k < count; ++k) {
      if (side[k].loop == loop) return;
    }
    if (count < 3) side[count++] = {loop, segment};
  }
  // Positive when x is nearer the empty side than the solid one. (These three are defined
  // in fairing.cpp, inline: fairing is their only user.)
  double imbalance(Vec2 x);
  // The same at a sample on edge `segment` of the first solid loop, or of the first empty one.
  double imbalance_at_solid_sample(Vec2 x, std::uint32_t segment);
  double imbalance_at_empty_sample(Vec2 x, std::uint32_t segment);
};

// A vertex of the contour, with the loops its axis is measured from.
struct ContourVertex {
  Vec2 at;
  AxisQuery query;
};

// The point of the Delaunay edge [solid.at, empty.at] equidistant from both sides: `solid` a
// sample of the query's first solid loop, `empty` one of its first empty loop. Strictly inside
// the edge (1% to 99% along it), so two loops never share a point at a sample.
Vec2 equidistant_on(AxisQuery& query, const Sample& solid, const Sample& empty);

// Whether a comes before b by x, then y: where an axis loop starts and how loops are ordered.
inline bool before(Vec2 a, Vec2 b) { return a.x < b.x || (a.x == b.x && a.y < b.y); }

// One closed loop of the contour from its crossings, in order, the solid on the left of each
// step: with fairing, resampled on the axis between them and simplified; without, the
// crossings themselves. It starts at its least vertex (by x, then y), whichever crossing the
// chain starts at: the same loop from any rotation of the chain.
Loop axis_loop(const std::vector<ContourVertex>& chain, bool fairing);

}  // namespace geometry::ma
