#include "geometry/contour/ma/fairing.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "geometry/core/douglas_peucker.h"

namespace geometry::ma {

namespace {

// squared_distance_to_segment(x, a, b) bit for bit for finite x (edge: a, b - a and its squared
// length as that computes them), without its division where the foot of the perpendicular
// falls beyond an end (t clamped to 0 or 1): most edges a walk looks at. An edge of no length
// has ab = 0 (LoopEdges), so `along` is 0 and x's distance is to a, as
// squared_distance_to_segment's t = 0 gives, without a test of its own.
inline double clamped_distance2(Vec2 x, const LoopEdges::Edge& edge) {
  const Vec2 ap = x - edge.a;
  const double along = dot(ap, edge.ab);
  if (along <= 0) return dot(ap, ap);
  const double length2 = edge.length2;
  const Vec2 d = along >= length2 ? ap - edge.ab : ap - (along / length2) * edge.ab;
  return dot(d, d);
}

// Distance from x to the loop, searched from edge `segment` along the loop while it gets no
// worse; `segment` is updated to the nearest edge found, as the hint for the next query.
// (Called a few million times per model.)
double distance_near(const LoopEdges& loop, std::uint32_t& segment, Vec2 x) {
  using Edge = LoopEdges::Edge;
  const Edge* const first = loop.edges.data();
  const Edge* const end = first + loop.edges.size();
  if (first == end) return std::numeric_limits<double>::infinity();
  // Each walk stops at the first edge farther than the best so far, or back at its start
  // edge (the whole loop seen: n - 1 steps).
  const Edge* const start = first + segment;
  const Edge* nearest_edge = start;
  double best = clamped_distance2(x, *start);
  for (const Edge* e = start;;) {  // forwards
    if (++e == end) e = first;
    if (e == start) break;
    const double d = clamped_distance2(x, *e);
    if (d > best) break;
    if (d < best) {
      best = d;
      nearest_edge = e;
    }
  }
  // Backwards only from the start edge: where the forward walk found a nearer edge, the one
  // before it is strictly farther (it was the best so far, or the walk went on past it), so
  // the backward walk would stop at its first step.
  if (nearest_edge != start) {
    segment = static_cast<std::uint32_t>(nearest_edge - first);
    return std::sqrt(best);
  }
  const Edge* const back_start = nearest_edge;
  for (const Edge* e = back_start;;) {  // backwards
    if (e == first) e = end;
    if (--e == back_start) break;
    const double d = clamped_distance2(x, *e);
    if (d > best) break;
    if (d < best) {
      best = d;
      nearest_edge = e;
    }
  }
  segment = static_cast<std::uint32_t>(nearest_edge - first);
  return std::sqrt(best);
}

// From x to the side's loops. With `on` set, x is a sample on edge *on of the side's first
// loop, which is then its nearest edge: that edge's distance (0 or a rounding error, from the
// edge as LoopEdges keeps it), and the hint moved there, without a walk. The other loops are
// walked as always. With one loop on the side (nearly always) its distance is returned as the
// minimum over the side's loops would give it (min(infinity, d) is d wherever d is below
// infinity), without that loop: on bench_ma --quick these paths and the edge kept for `on`
// take axis_loops from 917.7 to 882.1 M instructions.
// Always inlined (GCC kept it a call): fairing asks it about three million times per model,
// and inlined into each caller the walks cost a tenth fewer instructions.
[[gnu::always_inline]] inline double nearest(std::array<AxisQuery::Near, 3>& side, int count,
                                             Vec2 x, const std::uint32_t* on = nullptr) {
  constexpr double kInfinity = std::numeric_limits<double>::infinity();
  if (count == 1 && !on) {
    const double d = distance_near(*side[0].loop, side[0].segment, x);
    return d < kInfinity ? d : kInfinity;
  }
  double best = kInfinity;
  if (on) {
    best = std::sqrt(clamped_distance2(x, side[0].loop->edges[side[0].segment = *on]));
    if (count == 1) return best;
  }
  for (int k = on ? 1 : 0; k < count; ++k) {
    best = std::min(best, distance_near(*side[k].loop, side[k].segment, x));
  }
  return best;
}

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

// The loop straightened within `tolerance` (douglas_peucker.h). A faired contour has a
// vertex wherever the triangulation crosses the axis, two or three per sample, most of them
// on straight stretches. Douglas-Peucker asks about 5 million distances on bench_ma --quick
// (171 M instructions). Measured and not taken: passing over blocks of 16 vertices whose
// bound (their bounding box's farthest corner, or their ends' distance plus their bulge off
// their own chord) is below the farthest vertex so far or a probe at the stretch's middle,
// the same flags: the bounds cost more than the distances they saved (216 M with the bulge,
// 241 M with boxes: most stretches Douglas-Peucker splits here are short, most vertices kept).
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

}  // namespace

LoopEdges::LoopEdges(const Loop& loop) : loop(&loop) {
  const std::size_t n = loop.size();
  edges.resize(n);
  for (std::size_t j = 0; j < n; ++j) {
    const Vec2 a = loop[j], ab = loop[j + 1 == n ? 0 : j + 1] - a;
    const double length2 = dot(ab, ab);
    edges[j] = length2 > 0 ? LoopEdges::Edge{a, ab, length2} : LoopEdges::Edge{a, Vec2{}, 0.0};
  }
}

// Inline, as they were inside AxisQuery: only fairing asks them, and inlined the walks cost less.
inline double AxisQuery::imbalance(Vec2 x) {
  return nearest(solid_side, solid_count, x) - nearest(empty_side, empty_count, x);
}

inline double AxisQuery::imbalance_at_solid_sample(Vec2 x, std::uint32_t segment) {
  return nearest(solid_side, solid_count, x, &segment) - nearest(empty_side, empty_count, x);
}

inline double AxisQuery::imbalance_at_empty_sample(Vec2 x, std::uint32_t segment) {
  return nearest(solid_side, solid_count, x) - nearest(empty_side, empty_count, x, &segment);
}

Vec2 equidistant_on(AxisQuery& query, const Sample& solid, const Sample& empty) {
  const Vec2 s = solid.at, e = empty.at;
  const double f_lo = query.imbalance_at_solid_sample(s, solid.segment);
  const double f_hi = query.imbalance_at_empty_sample(e, empty.segment);
  double t = 0.5;
  if (f_lo < 0 && f_hi > 0) {
    t = regula_falsi([&](double u) { return query.imbalance(s + u * (e - s)); }, 0, 1, f_lo, f_hi,
                     kAxisSolveTolerance / std::max(length(e - s), 1e-12));
  }
  t = std::clamp(t, 0.01, 0.99);
  return s + t * (e - s);
}

Loop axis_loop(const std::vector<ContourVertex>& chain, bool fairing) {
  Loop loop;
  loop.reserve(chain.size());
  for (std::size_t i = 0; i < chain.size(); ++i) {
    loop.push_back(chain[i].at);
    if (fairing) fair_between(chain[i], chain[(i + 1) % chain.size()], kFairingDepth, loop);
  }
  // Fairing between two crossings depends on those two alone, so this is one cyclic sequence
  // whichever crossing the chain began at; started at its least vertex it is one list, and
  // simplification (which splits the loop at its vertex 0) one result.
  std::rotate(loop.begin(), std::min_element(loop.begin(), loop.end(), before), loop.end());
  if (fairing) loop = simplified(loop, kSimplifyTolerance);
  return loop;
}

}  // namespace geometry::ma
