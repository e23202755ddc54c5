// The medial-axis contour (paper §3.2-3.3). The only file that includes CGAL's Delaunay.
//
// Per layer: slab -> footprint -> boundary pairs (slab.h, boundary_pair.h); for each pair the
// free faces beside its loops are labelled solid or empty from the mid cross-section; then
//   1. sampling: every loop vertex, plus points on longer edges every `spacing` mm (capped
//      at max_points per island);
//   2. CGAL's Delaunay triangulation (Epick) of the island's samples, inserted in Hilbert
//      order, with the loops' edges as constraints (Constrained_Delaunay_triangulation_2:
//      where a strip is wider than the spacing it is the plain Delaunay triangulation; where
//      it is thinner the constraints keep its edges from jumping across the other loop);
//   3. Observation 3.3.1: the Voronoi edges whose dual Delaunay edge joins a sample of a solid
//      loop to one of an empty loop. With two labels every Delaunay triangle has 0 or 2 such
//      edges, so the kept edges chain into closed loops, one per triangle strip, never
//      branching, even where three or more loops meet (islands that merge inside the slab):
//      the loop goes round the union of the solid loops' territories;
//   4. each kept Voronoi edge gives one contour vertex where it crosses its dual Delaunay edge,
//      which keeps the contour inside the triangles, hence inside the strip ("clipped to the
//      strip"), simple, and disjoint from other loops. Unfaired, that is the edge's midpoint.
//      Fairing (§3.3, Fig. 17) moves it along the dual edge to the point equidistant from the
//      two boundary polygons (not their samples, so sampling aliasing is gone), then resamples
//      locally: where the middle of a contour edge is off the medial axis by more than
//      kFairingTolerance, a new vertex is put on the axis there, recursively;
//   5. the loops are the layer's Region as they stand, rounded to Clipper's nanometre grid
//      (simple, disjoint, solid on their left); with a cap or a wall in the layer, Clipper
//      unions all islands' paths (positive winding) into a valid Region.
// A vertical wall's strip (lower contour = upper contour: a ring a few margins wide) gives the
// mid section inside it, that very contour, without a triangulation.
// Caps (a feature beginning or ending inside the slab: an island whose free faces are all
// solid or all empty) have a medial-axis tree, not a loop. Their contour is the cross-section
// at the layer's middle inside the island, which for a cap is the least volume deviation
// possible (a column is filled iff the model fills at least half of it); if the feature does
// not reach the middle, the cross-section half-way through the feature's own height inside the
// slab, so the feature is kept. Walls midway between a cap's outline and its apex would halve
// the distance error of a symmetric dome, but on the bunny's 33 caps they made 6 layers' D
// worse (up to 0.7 mm: tilted features whose apex sits at their edge) and 1 better.
//
// Where the strip is not a strip. The axis is right where the surface inside the slab is a
// flank running from the island's solid loops to its empty loops; the boundary pair shows
// nothing else. Two rules take the mid section (the least-ΔV choice, as for caps) where the
// surface does something else:
//   6. floating features: a face of the mid section inside a strip (a solid part, or an empty
//      part of a hole) that holds none of the island's loops, that is, the surface crosses the
//      middle there on a closed curve the boundary pair cannot show: a bump or tail tip that
//      begins inside the slab, a dip, the patches of a nearly flat surface whose height wobbles
//      round the middle (the bunny's hole-filled base). The face itself becomes part of the
//      contour (solid) or a hole in it (empty); the rest of the island keeps its axis.
//   7. pockets (paper §3.4, non-contributing points): the same-side triangles of the
//      triangulation, joined across their shared edges, with the mixed triangles at their
//      mouths. A pocket holds samples with no Delaunay neighbour on the other side: the bottom
//      of a groove, a neck or septum where two parts of one side merge inside the slab (a
//      saddle), the lobe of a bump, a sharp corner. The axis does not come near them (on a
//      saddle it fills the neck; the surface may cut it). Let Θ be the largest distance from a
//      contributing sample of the island to the walls (the paper's Θ): a pocket with a sample
//      farther than Θ takes the mid section inside its triangles, if that brings its samples
//      nearer to the walls. The paper's own refinement (moving Voronoi vertices towards
//      those samples) is not implemented here either.
// Both replacements are one Clipper operation each, (region \ zone) ∪ (mid ∩ zone), so the
// parts meet exactly on the zone's edges (a short wall there joins the axis to the section).
#include "geometry/contour/ma_contour.h"

#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Spatial_sort_traits_adapter_2.h>
#include <CGAL/Triangulation_face_base_with_info_2.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>
#include <CGAL/property_map.h>
#include <CGAL/spatial_sort.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <utility>

#include "geometry/contour/contour_strategy.h"
#include "geometry/core/boundary_grid.h"
#include "geometry/core/douglas_peucker.h"
#include "geometry/core/clipper_bridge.h"

namespace geometry {

namespace {

// Which sample a vertex is (a vertex CGAL made where two constraints cross has none), and its
// label, set once the triangulation is complete: 1 where the free face beside it is solid.
struct SampleRef {
  static constexpr std::uint32_t kNone = 0xffffffffu;
  std::uint32_t index = kNone;
  char solid = 0;
};

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using VertexBase = CGAL::Triangulation_vertex_base_with_info_2<SampleRef, Kernel>;
// Per face: visited by the chain walk, and how many loops a walk from the infinite face
// crosses to reach it (odd: inside the footprint).
struct FaceInfo {
  std::uint8_t visited = 0;
  std::int8_t nesting = -1;
};
using FaceBase = CGAL::Constrained_triangulation_face_base_2<
    Kernel, CGAL::Triangulation_face_base_with_info_2<FaceInfo, Kernel>>;
using Tds = CGAL::Triangulation_data_structure_2<VertexBase, FaceBase>;
using Delaunay = CGAL::Constrained_Delaunay_triangulation_2<Kernel, Tds, CGAL::Exact_predicates_tag>;
// The same triangulation without constraints: points go in here (a third faster than into
// Delaunay, whose flips keep constraint flags up to date), then its faces are handed over.
using PlainDelaunay = CGAL::Delaunay_triangulation_2<Kernel, Tds>;
using Face = Delaunay::Face_handle;
using Vertex = Delaunay::Vertex_handle;

// Default spacing when MaOptions::spacing is 0, mm (every loop vertex is a sample anyway).
// With fairing the contour's vertices sit on the exact axis of the boundary polygons and its
// edges are split until they follow it to 1 um, so spacing only shapes the triangulation:
// the bunny's distance errors are the same (mean 0.301 mm) at 0.1, 0.2, 0.5 mm and with loop
// vertices alone, while CPU time falls from 1.9 s to 1.2 s. 0.25 mm still gives a long edge
// (a cube's 10 mm side) forty samples, so the triangles across a strip stay short.
constexpr double kDefaultSpacing = 0.25;

// How far off the medial axis the middle of a contour edge may be before fairing adds a
// vertex there, mm; and how deep it may split one edge.
constexpr double kFairingTolerance = 0.001;
constexpr int kFairingDepth = 6;
// How far, mm, simplifying the faired contour may move it: a quarter of the fairing tolerance.
constexpr double kSimplifyTolerance = 0.25 * kFairingTolerance;

struct Sample {
  Vec2 at;
  std::uint32_t loop = 0;     // index into loops_of(pair)
  std::uint32_t segment = 0;  // the loop's edge from vertex `segment` to the next
};

double length(Vec2 v) { return std::sqrt(v.x * v.x + v.y * v.y); }  // mm: no overflow to guard

// At least the loop's perimeter, mm: the sum of |dx| + |dy|, without a square root.
double perimeter_bound(const Loop& loop) {
  double bound = 0;
  for (std::size_t i = 0, n = loop.size(); i < n; ++i) {
    const Vec2 d = loop[i + 1 == n ? 0 : i + 1] - loop[i];
    bound += std::abs(d.x) + std::abs(d.y);
  }
  return bound;
}

std::vector<Sample> sample_loops(const std::vector<const Loop*>& loops, const MaOptions& options) {
  std::size_t vertices = 0;
  double total = 0;  // the loops' length, or a bound on it while that keeps under the cap
  for (const Loop* loop : loops) {
    vertices += loop->size();
    total += perimeter_bound(*loop);
  }
  const std::size_t cap = std::max<std::size_t>(options.max_points, 16);
  // Over the cap even with vertices alone: keep every stride-th vertex.
  const std::size_t stride = vertices > cap ? (vertices + cap - 1) / cap : 1;
  double spacing = options.spacing > 0 ? options.spacing : kDefaultSpacing;
  if (stride == 1 && vertices + total / spacing > cap) {
    total = 0;
    for (const Loop* loop : loops) total += perimeter(*loop);
  }
  if (stride == 1 && vertices + total / spacing > cap) {
    spacing = total / static_cast<double>(cap - vertices + 1);
  }
  std::vector<Sample> samples;
  samples.reserve(std::min(cap + loops.size(), vertices + static_cast<std::size_t>(total / spacing) + 1));
  for (std::uint32_t l = 0; l < loops.size(); ++l) {
    const Loop& loop = *loops[l];
    const std::size_t n = loop.size();
    for (std::size_t j = 0; j < n; j += stride) {
      const Vec2 a = loop[j], b = loop[(j + 1) % n];
      samples.push_back({a, l, static_cast<std::uint32_t>(j)});
      if (stride > 1) continue;
      const int pieces = static_cast<int>(std::ceil(length(b - a) / spacing));
      for (int k = 1; k < pieces; ++k) {
        samples.push_back({a + (static_cast<double>(k) / pieces) * (b - a), l,
                           static_cast<std::uint32_t>(j)});
      }
    }
  }
  return samples;
}

double squared_distance_to_segment(Vec2 p, Vec2 a, Vec2 b) {
  const Vec2 ab = b - a, ap = p - a;
  const double length2 = dot(ab, ab);
  const double t = length2 > 0 ? std::clamp(dot(ap, ab) / length2, 0.0, 1.0) : 0.0;
  const Vec2 d = ap - t * ab;
  return dot(d, d);
}

// Distance from x to the loop, searched from edge `segment` along the loop while it gets no
// worse; `segment` is updated to the nearest edge found, as the hint for the next query.
// (Called a few million times per model: the walk wraps round without a division.)
double distance_near(const Loop& loop, std::uint32_t& segment, Vec2 x) {
  const std::size_t n = loop.size();
  if (n == 0) return std::numeric_limits<double>::infinity();
  const auto at = [&](std::size_t j) {
    return squared_distance_to_segment(x, loop[j], loop[j + 1 == n ? 0 : j + 1]);
  };
  double best = at(segment);
  std::size_t j = segment;
  for (std::size_t step = 1; step < n; ++step) {  // forwards
    j = j + 1 == n ? 0 : j + 1;
    const double d = at(j);
    if (d > best) break;
    if (d < best) {
      best = d;
      segment = static_cast<std::uint32_t>(j);
    }
  }
  j = segment;
  for (std::size_t step = 1; step < n; ++step) {  // backwards
    j = j == 0 ? n - 1 : j - 1;
    const double d = at(j);
    if (d > best) break;
    if (d < best) {
      best = d;
      segment = static_cast<std::uint32_t>(j);
    }
  }
  return std::sqrt(best);
}

// Where the medial axis is looked for: the loops of the samples round one Delaunay edge (its
// two ends and the two opposite corners), with each one's nearest edge so far. Where three
// loops meet (islands merging in the slab) the nearest solid loop need not be the edge's own.
struct AxisQuery {
  struct Near {
    const Loop* loop;
    std::uint32_t segment;
  };
  std::array<Near, 3> solid_side{}, empty_side{};
  int solid_count = 0, empty_count = 0;

  void add(bool solid, const Loop* loop, std::uint32_t segment) {
    auto& side = solid ? solid_side : empty_side;
    int& count = solid ? solid_count : empty_count;
    for (int k = 0; k < count; ++k) {
      if (side[k].loop == loop) return;
    }
    if (count < 3) side[count++] = {loop, segment};
  }
  // From x to the side's loops. With `on` set, x is a sample on edge *on of the side's first
  // loop, which is then its nearest edge: that edge's distance (0 or a rounding error), and
  // the hint moved there, without a walk. The other loops are walked as always.
  // Always inlined (GCC kept it a call): fairing asks it about three million times per model,
  // and inlined into each caller the walks cost a tenth fewer instructions.
  [[gnu::always_inline]] static double nearest(std::array<Near, 3>& side, int count, Vec2 x,
                                               const std::uint32_t* on = nullptr) {
    double best = std::numeric_limits<double>::infinity();
    if (on) {
      const Loop& loop = *side[0].loop;
      const std::size_t j = side[0].segment = *on;
      best = std::sqrt(squared_distance_to_segment(x, loop[j], loop[j + 1 == loop.size() ? 0 : j + 1]));
    }
    for (int k = on ? 1 : 0; k < count; ++k) {
      best = std::min(best, distance_near(*side[k].loop, side[k].segment, x));
    }
    return best;
  }
  // Positive when x is nearer the empty side than the solid one.
  double imbalance(Vec2 x) {
    return nearest(solid_side, solid_count, x) - nearest(empty_side, empty_count, x);
  }
  // The same at a sample on edge `segment` of the first solid loop, or of the first empty one.
  double imbalance_at_solid_sample(Vec2 x, std::uint32_t segment) {
    return nearest(solid_side, solid_count, x, &segment) - nearest(empty_side, empty_count, x);
  }
  double imbalance_at_empty_sample(Vec2 x, std::uint32_t segment) {
    return nearest(solid_side, solid_count, x) - nearest(empty_side, empty_count, x, &segment);
  }
};

// How exactly fairing places a point on the axis, mm: far below kFairingTolerance, and each
// step of the solver costs a walk along up to six loops. A point is on the axis when it is
// within this of it along the line searched, or when its distances to the two sides agree to
// within this (f is such an imbalance: the first step of regula falsi nearly always lands
// there, where the bracket alone would take two or three more walks to close).
constexpr double kAxisSolveTolerance = 1e-5;

// The root of f between lo and hi, where f(lo) = f_lo and f(hi) = f_hi have opposite signs, to
// within `tolerance` in the argument or kAxisSolveTolerance in the value. f is close to linear
// where fairing asks (an imbalance of distances along a short segment), so regula falsi with
// the Illinois step converges in a few evaluations where bisection would take twenty.
template <class F>
double regula_falsi(F&& f, double lo, double hi, double f_lo, double f_hi, double tolerance) {
  double t = 0.5 * (lo + hi);
  int kept_side = 0;
  for (int it = 0; it < 60 && std::abs(hi - lo) > tolerance; ++it) {
    t = (lo * f_hi - hi * f_lo) / (f_hi - f_lo);
    const double value = f(t);
    if (std::abs(value) <= kAxisSolveTolerance) break;
    if ((value > 0) == (f_hi > 0)) {
      hi = t;
      f_hi = value;
      if (kept_side == -1) f_lo *= 0.5;
      kept_side = -1;
    } else {
      lo = t;
      f_lo = value;
      if (kept_side == 1) f_hi *= 0.5;
      kept_side = 1;
    }
  }
  return t;
}

// The point of [s, e] equidistant from both loops: s a sample of the query's first solid loop,
// e one of its first empty loop.
Vec2 equidistant_on(AxisQuery& query, const Sample& solid, const Sample& empty) {
  const Vec2 s = solid.at, e = empty.at;
  const double f_lo = query.imbalance_at_solid_sample(s, solid.segment);
  const double f_hi = query.imbalance_at_empty_sample(e, empty.segment);
  double t = 0.5;
  if (f_lo < 0 && f_hi > 0) {
    t = regula_falsi([&](double u) { return query.imbalance(s + u * (e - s)); }, 0, 1, f_lo, f_hi,
                     kAxisSolveTolerance / std::max(length(e - s), 1e-12));
  }
  // Strictly inside the edge, so two loops can never share a point at a sample.
  t = std::clamp(t, 0.01, 0.99);
  return s + t * (e - s);
}

// The loop straightened within `tolerance` (douglas_peucker.h). A faired contour has a
// vertex wherever the triangulation crosses the axis, two or three per sample, most of them
// on straight stretches.
Loop simplified(const Loop& loop, double tolerance) {
  const std::size_t n = loop.size();
  if (n <= 4) return loop;
  const std::vector<char> keep =
      douglas_peucker_keep(n, tolerance * tolerance, [&](std::size_t i, std::size_t a, std::size_t b) {
        return squared_distance_to_segment(loop[i], loop[a], loop[b]);
      });
  Loop out;
  out.reserve(static_cast<std::size_t>(std::count(keep.begin(), keep.end(), 1)));
  for (std::size_t i = 0; i < n; ++i) {
    if (keep[i]) out.push_back(loop[i]);
  }
  return out;
}

struct ContourVertex {
  Vec2 at;
  AxisQuery query;
};

// Fairing by local resampling: put vertices on the axis between a and b where the chord
// strays from it. The solid side is left of a->b.
void fair_between(const ContourVertex& a, const ContourVertex& b, int depth,
                  std::vector<Vec2>& out) {
  const Vec2 chord = b.at - a.at;
  const double chord_length = length(chord);
  if (depth <= 0 || chord_length < 4 * kFairingTolerance) return;
  const Vec2 middle = 0.5 * (a.at + b.at);
  AxisQuery query = a.query;
  const double off = query.imbalance(middle);
  if (std::abs(off) <= 2 * kFairingTolerance) return;
  const Vec2 towards_solid = (1.0 / chord_length) * Vec2{-chord.y, chord.x};
  // imbalance falls by at most 2 per unit moved towards the solid side, so the axis is at
  // least |off| / 2 away: bracket from there, then solve.
  const double sign = off > 0 ? 1.0 : -1.0;
  const auto along = [&](double d) { return sign * query.imbalance(middle + (sign * d) * towards_solid); };
  double near = 0.5 * std::abs(off), far = std::abs(off);
  double f_near = along(near), f_far = along(far);
  if (!(f_near > 0)) {
    far = near;  // at exactly the bound (a wall of slope 2): the axis is there
    f_far = f_near;
  }
  const double limit = chord_length;
  while (f_far > 0 && far <= limit) {
    near = far;
    f_near = f_far;
    far *= 2;
    f_far = along(far);
  }
  if (far > limit) return;  // no crossing near the chord: leave the edge as it is
  const double d = f_far == 0 || far == near
                       ? far
                       : regula_falsi(along, near, far, f_near, f_far, kAxisSolveTolerance);
  const ContourVertex added{middle + (sign * d) * towards_solid, query};
  fair_between(a, added, depth - 1, out);
  out.push_back(added.at);
  fair_between(added, b, depth - 1, out);
}

}  // namespace

namespace {

// A pocket (see the top of the file): a connected set of same-side triangles inside the
// footprint with at least one non-contributing sample, together with the mixed triangles at
// its mouths, and the corners of all of them.
struct Pocket {
  ClipperLib::Paths triangles;
  std::vector<Vec2> corners;
  std::vector<Vec2> non_contributing;
};

struct IslandAxis {
  std::vector<Loop> loops;
  std::vector<Vec2> contributing;  // samples with a Delaunay neighbour on the other side
  std::vector<Pocket> pockets;
};

IslandAxis island_axis(const BoundaryPair& pair, std::span<const char> solid,
                       const MaOptions& options, MaStats* stats, bool want_pockets) {
  IslandAxis axis;
  const std::vector<const Loop*> loops = loops_of(pair);
  std::vector<Loop>& contour = axis.loops;
  if (solid.size() != loops.size()) return axis;
  if (std::all_of(solid.begin(), solid.end(), [&](char s) { return (s != 0) == (solid[0] != 0); })) {
    return axis;  // a cap: no loop separates solid from empty
  }
  const std::vector<Sample> samples = sample_loops(loops, options);
  if (stats) stats->samples += samples.size();
  std::vector<std::uint32_t> first_of_loop(loops.size(), 0);
  for (std::uint32_t i = samples.size(); i-- > 0;) first_of_loop[samples[i].loop] = i;

  std::vector<Kernel::Point_2> points;
  points.reserve(samples.size());
  for (std::uint32_t i = 0; i < samples.size(); ++i) {
    const Vec2 p = samples[i].at;
    points.emplace_back(p.x, p.y);
  }
  // Inserted in spatial (Hilbert) order, each located from the previous one. In loop order
  // every new sample on a circle conflicts with much of what is built (measured: 40 000
  // points on two circles 6.9 s in loop order, 0.03 s in Hilbert order; with constraints
  // and fairing 0.06 s, 200 000 points 0.3 s).
  std::vector<std::size_t> order(samples.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  using SortTraits = CGAL::Spatial_sort_traits_adapter_2<
      Kernel, CGAL::Pointer_property_map<Kernel::Point_2>::const_type>;
  const std::vector<Kernel::Point_2>& sorted_points = points;
  CGAL::spatial_sort(order.begin(), order.end(), SortTraits(CGAL::make_property_map(sorted_points)));
  // With no constraint yet, the constrained triangulation of the points is their Delaunay
  // triangulation (both break ties by the same symbolic perturbation): it is built as a plain
  // one and its data structure moved into the constrained one (handles stay valid).
  Delaunay triangulation;
  std::vector<Vertex> vertex_of(samples.size());
  {
    PlainDelaunay plain;
    Face hint;
    for (std::size_t i : order) {
      const Vertex v = plain.insert(points[i], hint);
      if (v->info().index == SampleRef::kNone) v->info().index = static_cast<std::uint32_t>(i);
      vertex_of[i] = v;
      hint = v->face();
    }
    static_cast<PlainDelaunay::Triangulation&>(plain).swap(triangulation);
  }
  // The loops' edges as constraints: where the strip is thinner than the sample spacing (a
  // vertical wall's strip is 4 um wide) a plain Delaunay edge may jump from one side of the
  // strip across the other loop and split that loop's territory; constrained, every
  // triangle with corners on two loops lies inside the strip. Where the strip is wider than
  // the spacing the boundary edges are Delaunay edges anyway and nothing changes.
  for (std::uint32_t i = 0; i < samples.size(); ++i) {
    const std::uint32_t next =
        i + 1 < samples.size() && samples[i + 1].loop == samples[i].loop ? i + 1 : first_of_loop[samples[i].loop];
    const Vertex a = vertex_of[i], b = vertex_of[next];
    if (a == b) continue;
    // Nearly always the edge is there already: mark it (what insert_constraint does then,
    // after a search for vertices on the segment and a std::stack per call).
    Face f;
    int k = 0;
    if (triangulation.dimension() == 2 && triangulation.is_edge(a, b, f, k)) {
      f->set_constraint(k, true);
      f->neighbor(k)->set_constraint(triangulation.mirror_index(f, k), true);
    } else {
      triangulation.insert_constraint(a, b);
    }
  }
  for (Face f : triangulation.all_face_handles()) f->info() = FaceInfo{};

  // The infinite vertex is no sample either.
  const auto known = [](Vertex v) { return v->info().index != SampleRef::kNone; };
  // A crossing vertex (two loops touching) takes the outside's label: any labelling closes.
  const char outside = solid[0] != 0;
  for (Vertex v : triangulation.all_vertex_handles()) {
    v->info().solid = known(v) ? solid[samples[v->info().index].loop] != 0 : outside;
  }
  const auto label = [](Vertex v) { return v->info().solid; };
  const auto mixed = [&](Face f) {
    const char l0 = label(f->vertex(0));
    return label(f->vertex(1)) != l0 || label(f->vertex(2)) != l0;
  };
  // In a face with mixed labels, the edge the contour leaves by: with vertices v0 v1 v2
  // counter-clockwise and v_i the odd one out, the solid stays on the left if the contour
  // enters by (v_i, v_i+1) and leaves by (v_i+2, v_i) when v_i is solid, the reverse if not.
  const auto exit_edge = [&](Face f) -> int {
    const char l0 = label(f->vertex(0)), l1 = label(f->vertex(1)), l2 = label(f->vertex(2));
    if (l0 == l1 && l1 == l2) return -1;
    const int odd = l1 == l2 ? 0 : (l0 == l2 ? 1 : 2);
    return label(f->vertex(odd)) ? (odd + 1) % 3 : (odd + 2) % 3;
  };

  std::vector<ContourVertex> chain;  // one loop's, before fairing
  for (Face start : triangulation.all_face_handles()) {
    if (start->info().visited || exit_edge(start) < 0) continue;
    chain.clear();
    Face f = start;
    do {
      f->info().visited = 1;
      const int out = exit_edge(f);
      const Vertex u = f->vertex(Delaunay::cw(out)), v = f->vertex(Delaunay::ccw(out));
      if (known(u) && known(v)) {
        const Sample& su = samples[u->info().index];
        const Sample& sv = samples[v->info().index];
        const bool u_solid = label(u);
        const Sample& s = u_solid ? su : sv;
        const Sample& e = u_solid ? sv : su;
        AxisQuery query;
        query.add(true, loops[s.loop], s.segment);
        query.add(false, loops[e.loop], e.segment);
        const Face across = f->neighbor(out);
        for (Vertex w : {f->vertex(out), across->vertex(across->index(f))}) {
          if (!known(w)) continue;
          const Sample& sw = samples[w->info().index];
          query.add(label(w), loops[sw.loop], sw.segment);
        }
        const Vec2 at = options.fairing ? equidistant_on(query, s, e) : 0.5 * (s.at + e.at);
        chain.push_back({at, query});
      }
      f = f->neighbor(out);
    } while (f != start && exit_edge(f) >= 0 && !f->info().visited);
    if (chain.size() < 3) continue;
    Loop loop;
    loop.reserve(chain.size());
    for (std::size_t i = 0; i < chain.size(); ++i) {
      loop.push_back(chain[i].at);
      if (options.fairing) fair_between(chain[i], chain[(i + 1) % chain.size()], kFairingDepth, loop);
    }
    if (options.fairing) loop = simplified(loop, kSimplifyTolerance);
    if (loop.size() >= 3) contour.push_back(std::move(loop));
  }
  if (stats) stats->loops += contour.size();
  if (!want_pockets) return axis;

  // Which faces lie inside the footprint: flood from the infinite face, one more loop
  // crossed at every constrained edge (CGAL's polygon-with-holes triangulation example).
  {
    std::vector<std::pair<Face, int>> border{{triangulation.infinite_face(), 0}};
    std::vector<Face> queue;
    while (!border.empty()) {
      const auto [seed, nesting] = border.back();
      border.pop_back();
      if (seed->info().nesting != -1) continue;
      queue.assign(1, seed);
      while (!queue.empty()) {
        const Face f = queue.back();
        queue.pop_back();
        if (f->info().nesting != -1) continue;
        f->info().nesting = static_cast<std::int8_t>(std::min(nesting, 100));
        for (int i = 0; i < 3; ++i) {
          const Face n = f->neighbor(i);
          if (n->info().nesting != -1) continue;
          if (triangulation.is_constrained({f, i})) {
            border.push_back({n, nesting + 1});
          } else {
            queue.push_back(n);
          }
        }
      }
    }
  }
  const auto inside = [&](Face f) {
    return !triangulation.is_infinite(f) && (f->info().nesting & 1) != 0;
  };
  const auto corner = [&](Face f, int i) {
    const auto& p = f->vertex(i)->point();
    return Vec2{p.x(), p.y()};
  };
  const auto triangle = [&](Face f) {
    ClipperLib::Path path;
    for (int i = 0; i < 3; ++i) path.push_back(to_clipper(corner(f, i)));
    return path;  // CCW, as CGAL keeps its faces
  };
  // Contributing samples: corners of a mixed face inside the footprint.
  std::vector<char> contributing(samples.size(), 0);
  for (Face f : triangulation.finite_face_handles()) {
    if (!inside(f) || !mixed(f)) continue;
    for (int i = 0; i < 3; ++i) {
      const Vertex v = f->vertex(i);
      if (known(v)) contributing[v->info().index] = 1;
    }
  }
  for (std::uint32_t i = 0; i < samples.size(); ++i) {
    if (contributing[i]) axis.contributing.push_back(samples[i].at);
  }
  // Pockets: components of same-side faces inside the footprint, joined across their shared
  // (unconstrained) edges; visited is reused as "already in a component".
  for (Face f : triangulation.all_face_handles()) f->info().visited = 0;
  std::vector<Face> component, queue;
  for (Face seed : triangulation.finite_face_handles()) {
    if (seed->info().visited || !inside(seed) || mixed(seed)) continue;
    component.clear();
    queue.assign(1, seed);
    seed->info().visited = 1;
    while (!queue.empty()) {
      const Face f = queue.back();
      queue.pop_back();
      component.push_back(f);
      for (int i = 0; i < 3; ++i) {
        const Face n = f->neighbor(i);
        if (n->info().visited || !inside(n) || triangulation.is_constrained({f, i})) continue;
        if (mixed(n)) continue;
        n->info().visited = 1;
        queue.push_back(n);
      }
    }
    Pocket pocket;
    for (Face f : component) {
      for (int i = 0; i < 3; ++i) {
        const Vertex v = f->vertex(i);
        if (known(v) && !contributing[v->info().index]) {
          contributing[v->info().index] = 2;  // listed once
          pocket.non_contributing.push_back(samples[v->info().index].at);
        }
      }
    }
    if (pocket.non_contributing.empty()) continue;
    // A mixed face has one same-side edge, so it is the mouth of one pocket at most, once.
    for (Face f : component) {
      pocket.triangles.push_back(triangle(f));
      for (int i = 0; i < 3; ++i) {
        const Face n = f->neighbor(i);
        if (inside(n) && mixed(n) && !triangulation.is_constrained({f, i})) {
          pocket.triangles.push_back(triangle(n));
        }
      }
    }
    for (const ClipperLib::Path& t : pocket.triangles) {
      for (const auto& p : t) pocket.corners.push_back(from_clipper(p));
    }
    axis.pockets.push_back(std::move(pocket));
  }
  return axis;
}

}  // namespace

std::vector<Loop> medial_axis_loops(const BoundaryPair& pair, std::span<const char> solid,
                                    const MaOptions& options, MaStats* stats) {
  return island_axis(pair, solid, options, stats, false).loops;
}

Region ma_contour(const Slab& slab, const std::function<Region(double z)>& cross_section,
                  const MaOptions& options, MaStats* stats) {
  if (slab.facets.empty() || !(slab.z_lo < slab.z_hi)) return {};
  return ma_contour(slab, slab_islands(slab), cross_section, options, stats);
}

namespace {

constexpr double kSquareMicrometre = 1e6;  // Clipper areas are in nm^2

double clipper_area(const ClipperLib::Paths& paths) {
  double a = 0;
  for (const auto& p : paths) a += ClipperLib::Area(p);
  return a;
}

ClipperLib::Paths clip(const ClipperLib::Paths& subject, const ClipperLib::Paths& by,
                       ClipperLib::ClipType operation) {
  ClipperLib::Clipper clipper;
  clipper.AddPaths(subject, ClipperLib::ptSubject, true);
  clipper.AddPaths(by, ClipperLib::ptClip, true);
  ClipperLib::Paths result;
  clipper.Execute(operation, result, ClipperLib::pftNonZero, ClipperLib::pftNonZero);
  return result;
}

ClipperLib::Paths grown(const ClipperLib::Path& filled, double delta) {
  ClipperLib::ClipperOffset offset(2.0, std::abs(delta) / 8);
  offset.AddPath(filled, ClipperLib::jtRound, ClipperLib::etClosedPolygon);
  ClipperLib::Paths result;
  offset.Execute(result, delta);
  return result;
}

// A vertical wall's strip: one outer loop, one hole, and every point of the ring within four
// margins of both (a wall's ring is two margins wide). Checked as: the outline lies inside
// the hole grown by that much, and the outline shrunk by it inside the hole.
bool is_wall(const BoundaryPair& pair) {
  if (pair.inner.size() != 1) return false;
  // First the cheap test that rejects nearly every real strip: a wall's ring is on average
  // two margins wide (its area over its mean perimeter), and most rings are so much wider
  // that a bound on the perimeter tells.
  const double ring_area = signed_area(pair.outer) + signed_area(pair.inner[0]);
  const double length_bound = 0.5 * (perimeter_bound(pair.outer) + perimeter_bound(pair.inner[0]));
  if (ring_area > 3 * kFootprintMargin * length_bound) return false;
  const double mean_length = 0.5 * (perimeter(pair.outer) + perimeter(pair.inner[0]));
  if (!(mean_length > 0) || ring_area > 3 * kFootprintMargin * mean_length) return false;
  const double reach = 4 * kFootprintMargin * kClipperScale;
  const ClipperLib::Path outline = to_clipper(pair.outer);
  ClipperLib::Path hole = to_clipper(pair.inner[0]);
  ClipperLib::ReversePath(hole);  // as a filled polygon
  if (clipper_area(clip({outline}, grown(hole, reach), ClipperLib::ctDifference)) > kSquareMicrometre) {
    return false;
  }
  return clipper_area(clip(grown(outline, -reach), {hole}, ClipperLib::ctDifference)) <= kSquareMicrometre;
}

// A section's part inside the island's outline (`paths`, clipped to `outline`) as paths to add
// with positive winding: where the island is solid all round, the outline reversed takes that
// solid away first.
ClipperLib::Paths section_in_island(ClipperLib::Paths paths, const ClipperLib::Path& outline,
                                    bool solid_outside) {
  if (solid_outside) {
    ClipperLib::Path reversed = outline;
    ClipperLib::ReversePath(reversed);
    paths.push_back(std::move(reversed));
  }
  return paths;
}

// The same from the whole section.
ClipperLib::Paths section_in_island(const Region& section, const BoundaryPair& pair,
                                    bool solid_outside) {
  const ClipperLib::Path outline = to_clipper(pair.outer);
  return section_in_island(clip(to_clipper(section), {outline}, ClipperLib::ctIntersection),
                           outline, solid_outside);
}

// A cap: the mid section inside it; if the feature does not reach the middle (nothing of an
// empty-beside cap there, all of a solid-beside one, a cavity), the section half-way through
// the feature's own height range inside the slab.
ClipperLib::Paths cap_contour(const Slab& slab, const BoundaryPair& pair, bool solid_outside,
                              const Region& middle,
                              const std::function<Region(double z)>& cross_section) {
  const ClipperLib::Path outline = to_clipper(pair.outer);
  const double island = ClipperLib::Area(outline);
  ClipperLib::Paths middle_inside = clip(to_clipper(middle), {outline}, ClipperLib::ctIntersection);
  const double inside = clipper_area(middle_inside);
  const bool reaches_middle = solid_outside ? std::abs(inside - island) > kSquareMicrometre
                                            : inside > kSquareMicrometre;
  if (reaches_middle) return section_in_island(std::move(middle_inside), outline, solid_outside);
  Region ring{{pair.outer}};
  ring.loops.insert(ring.loops.end(), pair.inner.begin(), pair.inner.end());
  double lo = slab.z_hi, hi = slab.z_lo;
  for (const auto& facet : slab.facets) {
    if (!point_in_region(ring, {facet[0].x, facet[0].y})) continue;
    for (const Vec3& v : facet) {
      lo = std::min(lo, v.z);
      hi = std::max(hi, v.z);
    }
  }
  const Region section = lo < hi ? cross_section(0.5 * (lo + hi)) : middle;
  return section_in_island(section, pair, solid_outside);
}

}  // namespace

namespace {

// Below this, mm, two distances are the same for the refinement's decisions: the distance
// metric's own tolerance (distance_error.h).
constexpr double kRefineTolerance = 0.001;

// 10 nm, in Clipper units (clipper_bridge.h).
constexpr double kCleanDistance = 10;

ClipperLib::PolyTree& united_tree(const ClipperLib::Paths& paths, ClipperLib::PolyTree& tree) {
  ClipperLib::Clipper clipper;
  clipper.AddPaths(paths, ClipperLib::ptSubject, true);
  clipper.Execute(ClipperLib::ctUnion, tree, ClipperLib::pftNonZero, ClipperLib::pftNonZero);
  return tree;
}

ClipperLib::Paths united(const ClipperLib::Paths& paths) {
  ClipperLib::Clipper clipper;
  clipper.AddPaths(paths, ClipperLib::ptSubject, true);
  ClipperLib::Paths result;
  clipper.Execute(ClipperLib::ctUnion, result, ClipperLib::pftNonZero, ClipperLib::pftNonZero);
  return result;
}

// The union of paths of positive winding, as a Region (outer loops CCW, holes CW).
Region united_region(const ClipperLib::Paths& paths) {
  ClipperLib::Clipper clipper;
  clipper.AddPaths(paths, ClipperLib::ptSubject, true);
  ClipperLib::PolyTree tree;
  clipper.Execute(ClipperLib::ctUnion, tree, ClipperLib::pftPositive, ClipperLib::pftPositive);
  return from_clipper(tree);
}

// Whether axis loops on Clipper's grid are a Region as they stand: loops that are simple,
// pairwise disjoint and have the solid on their left (medial_axis_loops), from disjoint
// islands, which their union would only renumber. The rounding must not have merged two
// vertices (a union would drop one). On the bunny the union gave back the very same vertices
// on each of the 325 layers whose islands all have their axis.
bool on_grid_as_they_are(const ClipperLib::Paths& loops) {
  for (const ClipperLib::Path& loop : loops) {
    if (loop.size() < 3) return false;
    for (std::size_t i = 0, n = loop.size(); i < n; ++i) {
      if (loop[i] == loop[i + 1 == n ? 0 : i + 1]) return false;
    }
  }
  return true;
}

// `region` with the mid section taking its place inside `zone`: (region \ zone) ∪ (mid ∩ zone),
// in one Clipper operation, so that the two parts meet exactly along the zone's edges (two
// operations round their crossings apart and leave nanometre cracks there). Each input has
// winding 1 inside and 0 outside. Subject: region - zone > 0; clip: mid + zone - box > 0,
// the box reversed round everything.
Region mid_inside(const ClipperLib::Paths& region, const ClipperLib::Paths& all_middle,
                  const ClipperLib::Paths& zone) {
  struct Box {
    ClipperLib::cInt lo_x, lo_y, hi_x, hi_y;
    void add(const ClipperLib::Path& path) {
      for (const auto& p : path) {
        lo_x = std::min(lo_x, p.X);
        lo_y = std::min(lo_y, p.Y);
        hi_x = std::max(hi_x, p.X);
        hi_y = std::max(hi_y, p.Y);
      }
    }
    bool meets(const Box& other) const {
      return lo_x <= other.hi_x && other.lo_x <= hi_x && lo_y <= other.hi_y && other.lo_y <= hi_y;
    }
  };
  constexpr auto kMax = std::numeric_limits<ClipperLib::cInt>::max();
  constexpr Box kEmpty{kMax, kMax, -kMax, -kMax};
  Box bounds = kEmpty;
  for (const auto& path : zone) bounds.add(path);
  // Only the section's loops whose box meets the zone's: the others add no winding inside it.
  ClipperLib::Paths middle;
  for (const auto& path : all_middle) {
    Box own = kEmpty;
    own.add(path);
    if (own.meets(bounds)) middle.push_back(path);
  }
  for (const auto& path : middle) bounds.add(path);
  const ClipperLib::cInt lo_x = bounds.lo_x, lo_y = bounds.lo_y, hi_x = bounds.hi_x, hi_y = bounds.hi_y;
  ClipperLib::Clipper clipper;
  clipper.AddPaths(region, ClipperLib::ptSubject, true);
  for (ClipperLib::Path path : zone) {
    ClipperLib::ReversePath(path);
    clipper.AddPath(path, ClipperLib::ptSubject, true);
  }
  clipper.AddPaths(middle, ClipperLib::ptClip, true);
  clipper.AddPaths(zone, ClipperLib::ptClip, true);
  const ClipperLib::Path box{{lo_x - 1, lo_y - 1}, {lo_x - 1, hi_y + 1}, {hi_x + 1, hi_y + 1},
                             {hi_x + 1, lo_y - 1}};  // clockwise
  clipper.AddPath(box, ClipperLib::ptClip, true);
  ClipperLib::Paths joined;
  clipper.Execute(ClipperLib::ctUnion, joined, ClipperLib::pftPositive, ClipperLib::pftPositive);
  // Where the mid section's walls meet the zone's edges a few nanometres from another vertex,
  // the crossing leaves edges of a nanometre or two: nothing a printer or a metric sees, but
  // slivers for a mesh made from the region (extruded_layers.h, CGAL's corefinement).
  ClipperLib::CleanPolygons(joined, kCleanDistance);
  ClipperLib::PolyTree tree;
  return from_clipper(united_tree(joined, tree));
}

// Whether add_floating_features can find a feature in the island, read off the mid section's
// loops as they are, without the union that nests them: a loop inside the island's ring whose
// face (inside it, outside the loops nested in it) holds none of the island's boundary points.
// The section's loops lie on the surface inside the slab, so each lies inside one island's
// ring, at least the footprint margin from its edge; they are nested, never crossing, and
// the innermost holding a point is the one of least area that holds it. (One case reads
// differently: a section loop touching itself at a vertex exactly at mid height, which the
// union could split in two. That is answered as the loop, not as its two halves.)
bool may_float(const BoundaryPair& pair, const Region& middle) {
  const std::vector<const Loop*> boundaries = loops_of(pair);
  const std::size_t n = middle.loops.size();
  std::vector<char> anchored(n, 0);
  for (const Loop* boundary : boundaries) {
    const Vec2 p = (*boundary)[0];
    std::size_t innermost = n;
    double least = std::numeric_limits<double>::infinity();
    for (std::size_t k = 0; k < n; ++k) {
      if (winding_number(middle.loops[k], p) == 0) continue;
      const double a = std::abs(signed_area(middle.loops[k]));
      if (a < least) {
        least = a;
        innermost = k;
      }
    }
    if (innermost < n) anchored[innermost] = 1;
  }
  for (std::size_t k = 0; k < n; ++k) {
    if (anchored[k] || middle.loops[k].size() < 3) continue;
    int in_ring = 0;
    for (const Loop* boundary : boundaries) in_ring += winding_number(*boundary, middle.loops[k][0]);
    if (in_ring != 0) return true;
  }
  return false;
}

// Floating features of an island (see the top of the file): the faces of the mid section
// (solid: an outer loop less its holes; empty: a hole less the outer loops inside it) that are
// bounded by a loop inside the island's footprint and hold none of the island's loops (a loop
// is held where its free face is: a point of it lies in the face). `middle` is the section's
// nesting (Clipper's PolyTree); the faces go to `zones`, as paths with winding 1 inside.
void add_floating_features(const BoundaryPair& pair, const ClipperLib::PolyTree& middle,
                           ClipperLib::Paths& zones, MaStats* stats) {
  Region ring{{pair.outer}};
  ring.loops.insert(ring.loops.end(), pair.inner.begin(), pair.inner.end());
  const std::vector<const Loop*> boundaries = loops_of(pair);
  for (const ClipperLib::PolyNode* node = middle.GetFirst(); node; node = node->GetNext()) {
    if (node->Contour.size() < 3 || !point_in_region(ring, from_clipper(node->Contour[0]))) continue;
    // The face: inside the node's loop, outside its children's.
    const Region outline{{from_clipper(node->Contour)}};
    std::vector<Region> children;
    for (const ClipperLib::PolyNode* child : node->Childs) children.push_back({{from_clipper(child->Contour)}});
    bool anchored = false;
    for (const Loop* boundary : boundaries) {
      const Vec2 p = (*boundary)[0];
      if (!point_in_region(outline, p)) continue;
      bool in_child = false;
      for (const Region& child : children) in_child = in_child || point_in_region(child, p);
      anchored = anchored || !in_child;
    }
    if (anchored) continue;
    // Winding 1 inside the face: the node's loop counter-clockwise, its children clockwise.
    ClipperLib::Path outer = node->Contour;
    if (!ClipperLib::Orientation(outer)) ClipperLib::ReversePath(outer);
    zones.push_back(std::move(outer));
    for (const ClipperLib::PolyNode* child : node->Childs) {
      ClipperLib::Path hole = child->Contour;
      if (ClipperLib::Orientation(hole)) ClipperLib::ReversePath(hole);
      zones.push_back(std::move(hole));
    }
    if (stats) ++stats->features;
  }
}

}  // namespace

Region ma_contour(const Slab& slab, const Region& footprint,
                  const std::function<Region(double z)>& cross_section, const MaOptions& options,
                  MaStats* stats) {
  if (slab.facets.empty() || !(slab.z_lo < slab.z_hi)) return {};
  return ma_contour(slab, boundary_pairs(footprint), cross_section, options, stats);
}

Region ma_contour(const Slab& slab, std::span<const BoundaryPair> pairs,
                  const std::function<Region(double z)>& cross_section, const MaOptions& options,
                  MaStats* stats) {
  if (slab.facets.empty() || !(slab.z_lo < slab.z_hi)) return {};
  if (pairs.empty()) return {};
  const Region middle = cross_section(0.5 * (slab.z_lo + slab.z_hi));
  if (stats) stats->islands += pairs.size();

  // Every loop has the solid on its left, so summing winding numbers over all islands gives
  // 1 exactly on the layer's region, also for islands nested in another's holes.
  ClipperLib::Paths paths, features;
  ClipperLib::PolyTree middle_nesting;  // built for the first island that may have a feature
  bool nested = false;
  bool only_axes = true;  // no cap, no wall
  std::vector<IslandAxis> axes;
  for (const BoundaryPair& pair : pairs) {
    const std::vector<char> solid = solid_beside(pair, middle);
    const bool cap = std::all_of(solid.begin(), solid.end(), [&](char s) { return s == solid[0]; });
    ClipperLib::Paths island;
    if (cap) {
      only_axes = false;
      if (stats) ++stats->caps;
      island = cap_contour(slab, pair, solid[0] != 0, middle, cross_section);
    } else if (is_wall(pair)) {
      // Lower contour = upper contour: the contour is that section, exactly (the axis of the
      // ring would be it to a fraction of the margin), without a triangulation.
      only_axes = false;
      if (stats) ++stats->walls;
      island = section_in_island(middle, pair, solid[0] != 0);
    } else {
      axes.push_back(island_axis(pair, solid, options, stats, options.pockets));
      for (const Loop& loop : axes.back().loops) island.push_back(to_clipper(loop));
      if (options.floating_features && may_float(pair, middle)) {
        if (!nested) united_tree(to_clipper(middle), middle_nesting);
        nested = true;
        add_floating_features(pair, middle_nesting, features, stats);
      }
    }
    paths.insert(paths.end(), island.begin(), island.end());
  }
  Region basic = only_axes && on_grid_as_they_are(paths) ? from_clipper(paths) : united_region(paths);
  bool any_pocket = false;
  for (const IslandAxis& axis : axes) any_pocket = any_pocket || !axis.pockets.empty();
  if (features.empty() && !any_pocket) return basic;

  const ClipperLib::Paths basic_paths = to_clipper(basic);
  const ClipperLib::Paths middle_paths = to_clipper(middle);
  const ClipperLib::Paths feature_zone = united(features);
  const Region with_features =
      feature_zone.empty() ? std::move(basic) : mid_inside(basic_paths, middle_paths, feature_zone);
  if (!any_pocket) return with_features;
  // Pockets (paper §3.4's non-contributing points): where a pocket's samples are farther from
  // the walls than every contributing sample of the island, and the mid section's walls are
  // nearer to them, the pocket takes the mid section.
  // The mid section's grid only if some pocket gets as far as asking it (two layers in five).
  const BoundaryGrid walls(with_features);
  std::optional<BoundaryGrid> middle_walls;
  ClipperLib::Paths zone = feature_zone;
  std::vector<double> worst;
  for (const IslandAxis& axis : axes) {
    if (axis.pockets.empty()) continue;
    worst.assign(axis.pockets.size(), 0);
    double farthest = 0;
    for (std::size_t k = 0; k < axis.pockets.size(); ++k) {
      for (Vec2 p : axis.pockets[k].non_contributing) worst[k] = std::max(worst[k], walls.nearest_distance(p));
      farthest = std::max(farthest, worst[k]);
    }
    // Θ of §3.4, the largest distance of a contributing sample to the walls; only needed up
    // to the farthest pocket sample (most pockets are a sharp corner's few samples).
    // Visited a sixteenth at a time, spread along the loops, so that where some sample is
    // farther than every pocket sample it is found early (the decisions come out the same in
    // any order: all pockets pass when one is, else level is the maximum).
    double level = 0;
    const std::size_t count = axis.contributing.size();
    constexpr std::size_t kStride = 16;
    for (std::size_t first = 0; first < kStride && level <= farthest; ++first) {
      for (std::size_t i = first; i < count && level <= farthest; i += kStride) {
        level = std::max(level, walls.nearest_distance(axis.contributing[i]));
      }
    }
    for (std::size_t k = 0; k < axis.pockets.size(); ++k) {
      const Pocket& pocket = axis.pockets[k];
      if (worst[k] <= level + kRefineTolerance) continue;
      if (!middle_walls) middle_walls.emplace(middle);
      double now = 0, with_middle = 0;
      for (Vec2 p : pocket.corners) {
        now = std::max(now, walls.nearest_distance(p));
        with_middle = std::max(with_middle, middle_walls->nearest_distance(p));
      }
      if (with_middle >= now - kRefineTolerance) continue;
      zone.insert(zone.end(), pocket.triangles.begin(), pocket.triangles.end());
      if (stats) ++stats->pockets;
    }
  }
  if (zone.size() == feature_zone.size()) return with_features;
  return mid_inside(basic_paths, middle_paths, united(zone));
}

Region ma_contour(const LayerStack& stack, std::size_t layer, const MaOptions& options,
                  MaStats& stats) {
  if (layer >= stack.size()) return {};
  return ma_contour(
      slab_of(stack, layer), [&stack](double z) { return stack.cross_section(z); }, options,
      &stats);
}

Region ma_contour(const LayerStack& stack, std::size_t layer, const MaOptions& options) {
  MaStats stats;
  return ma_contour(stack, layer, options, stats);
}

ContourResult ma_strategy(const ContourInput& input) {
  const LayerStack& stack = input.stack;
  const double middle = stack.layers()[input.layer].z_mid();
  const MaOptions& options = input.options.ma;
  if (!input.reference) return {ma_contour(stack, input.layer, options), middle};
  // The slab is clipped and its islands found already: hand them over.
  return {ma_contour(
              input.reference->slab, input.reference->islands,
              [&stack](double z) { return stack.cross_section(z); }, options),
          middle};
}

}  // namespace geometry
