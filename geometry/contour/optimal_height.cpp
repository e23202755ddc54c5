#include "geometry/contour/optimal_height.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>

#include <boost/math/tools/minima.hpp>

#include "geometry/contour/contour_strategy.h"
#include "geometry/core/small_polygon.h"
#include "geometry/metrics/volume_deviation.h"
#include "geometry/slab/slab.h"

namespace geometry {

namespace {

// The part of a facet's outline where f0 + fx (x - o.x) + fy (y - o.y) >= 0.
SmallPolygon cut(const SmallPolygon& polygon, Vec2 o, double f0, double fx, double fy) {
  SmallPolygon out;
  cut_small(polygon, o, f0, fx, fy, out);
  return out;
}

// Area of a polygon and ∫ over it of w0 + wx (x - o.x) + wy (y - o.y).
struct Integrals {
  double area = 0, integral = 0;
};
Integrals integrals(const SmallPolygon& polygon, Vec2 o, double w0, double wx, double wy) {
  double area = 0, mx = 0, my = 0;
  for (int i = 0, n = polygon.size; i < n && n >= 3; ++i) {
    const SmallPolygon::Corner a = polygon.at[i], b = polygon.at[i + 1 == n ? 0 : i + 1];
    const Vec2 p{a.x - o.x, a.y - o.y}, q{b.x - o.x, b.y - o.y};
    const double c = cross(p, q);
    area += c / 2;
    mx += c * (p.x + q.x) / 6;
    my += c * (p.y + q.y) / 6;
  }
  return {area, w0 * area + wx * mx + wy * my};
}

// integrals(cut(polygon, o, f0, fx, fy), o, w0, wx, wy) with the cut's corners summed as they
// come instead of stored: a facet's pieces (add_pieces) take a few of these each, and a fold
// pair's intersection (operator()) one a height. Inlined into both: called, it cost
// add_pieces 18 M more instructions in the bunny's best slice.
[[gnu::always_inline]] inline Integrals integrals_of_cut(const SmallPolygon& polygon, Vec2 o, double f0,
                                                         double fx, double fy, double w0, double wx,
                                                         double wy) {
  const int n = polygon.size;
  if (n == 0) return {};
  const auto at = [&](SmallPolygon::Corner p) { return f0 + fx * (p.x - o.x) + fy * (p.y - o.y); };
  double area = 0, mx = 0, my = 0;
  int corners = 0;
  Vec2 first{}, last{};
  const auto take = [&](Vec2 q) {
    if (corners++ > 0) {
      const double c = cross(last, q);
      area += c / 2;
      mx += c * (last.x + q.x) / 6;
      my += c * (last.y + q.y) / 6;
    } else {
      first = q;
    }
    last = q;
  };
  SmallPolygon::Corner a = polygon.at[0];
  double fa = at(a);
  for (int i = 0; i < n && corners < kSmallCorners - 1; ++i) {
    const SmallPolygon::Corner b = polygon.at[i + 1 == n ? 0 : i + 1];
    const double fb = at(b);
    if (fa >= 0) take({a.x - o.x, a.y - o.y});
    if ((fa >= 0) != (fb >= 0)) {
      const double s = fa / (fa - fb);
      take({a.x + s * (b.x - a.x) - o.x, a.y + s * (b.y - a.y) - o.y});
    }
    a = b;
    fa = fb;
  }
  if (corners < 3) return {};
  const double c = cross(last, first);
  area += c / 2;
  mx += c * (last.x + first.x) / 6;
  my += c * (last.y + first.y) / 6;
  return {area, w0 * area + wx * mx + wy * my};
}

}  // namespace

struct SectionDeviation::Facet {
  SmallPolygon outline;
  Vec2 o;
  double w0 = 0, wx = 0, wy = 0;
  int sign = 0;
  double z_min = 0, z_max = 0;
  int lower = 0;                 // its projection: 1 inside C(z_lo), 0 outside, -1 crossing it
  std::vector<int> partners;     // facets it overlaps seen from above (folds)
  // Its projection's intersection with a partner's, where not empty: at h, the part of it
  // where z_f <= h is f_h ∩ g (a cut of a convex polygon by a line).
  struct Common {
    SmallPolygon polygon;
    int other = 0;
    double sign = 0;          // s_f s_g
    double shift = 0;         // f's w at the partner's origin minus f.w0
    double w_min = 0, w_max = 0;  // f's w over its corners
    double whole = 0;         // s_f s_g ∫ over all of it of w_g
  };
  std::vector<Common> commons;
  // While wholly below h: its share of the section's area and of ∫ over C(h) of occ.
  double area = 0, occupied = 0;
  Integrals whole;  // area and ∫ of w_f over its projection
};

SectionDeviation::SectionDeviation(const SlabColumns& columns)
    : lower_grid_(columns.lower), lower_(&columns.lower), z_hi_(columns.z_hi),
      thickness_(columns.thickness()), volume_(columns.volume) {
  const double t = thickness_;
  const std::vector<std::vector<int>>& overlapping = columns.overlapping;
  facets_.resize(columns.facets.size());
  for (std::size_t a = 0; a < overlapping.size(); ++a) {
    for (int b : overlapping[a]) {
      facets_[a].partners.push_back(b);
      facets_[b].partners.push_back(static_cast<int>(a));
    }
  }
  lower_area_ = columns.lower_area;
  occupied_lower_ = t * columns.lower_area;
  for (std::size_t i = 0; i < columns.facets.size(); ++i) {
    const ColumnFacet& f = columns.facets[i];
    Facet& facet = facets_[i];
    facet.outline = small_polygon(f.outline);
    facet.o = f.outline[0];
    facet.w0 = f.w0;
    facet.wx = f.wx;
    facet.wy = f.wy;
    facet.sign = f.sign;
    double w_min = f.w0, w_max = f.w0;
    for (Vec2 p : f.outline) {
      const double w = f.w0 + f.wx * (p.x - facet.o.x) + f.wy * (p.y - facet.o.y);
      w_min = std::min(w_min, w);
      w_max = std::max(w_max, w);
    }
    facet.z_min = columns.z_hi - w_max;
    facet.z_max = columns.z_hi - w_min;
    const Integrals whole = integrals(facet.outline, facet.o, f.w0, f.wx, f.wy);
    const AreaMoments in_lower =
        moments_of_intersection(f.outline, {f.lo, f.hi}, facet.o, lower_grid_, columns.lower);
    occupied_lower_ += f.sign * (f.w0 * in_lower.area + f.wx * in_lower.mx + f.wy * in_lower.my);
    // Inside or outside C(z_lo) to a billionth of its area (a facet with an edge on the lower
    // contour is either), else the lower contour crosses it (a fold).
    const double slack = 1e-9 * std::abs(whole.area) + 1e-15;
    facet.lower = std::abs(in_lower.area - whole.area) <= slack ? 1
                  : std::abs(in_lower.area) <= slack           ? 0
                                                                : -1;
    facet.whole = whole;
    facet.area = f.sign * whole.area;
    facet.occupied = t * f.sign * in_lower.area + whole.integral;
  }
  for (Facet& facet : facets_) {
    for (int g : facet.partners) {
      const Facet& other = facets_[g];
      Facet::Common common;
      common.polygon = intersect_small(facet.outline, other.outline);
      if (common.polygon.size < 3) continue;
      common.other = g;
      common.sign = facet.sign * other.sign;
      common.shift = facet.wx * (other.o.x - facet.o.x) + facet.wy * (other.o.y - facet.o.y);
      common.w_min = HUGE_VAL;
      common.w_max = -HUGE_VAL;
      for (int k = 0; k < common.polygon.size; ++k) {
        const SmallPolygon::Corner p = common.polygon.at[k];
        const double w = facet.w0 + facet.wx * (p.x - facet.o.x) + facet.wy * (p.y - facet.o.y);
        common.w_min = std::min(common.w_min, w);
        common.w_max = std::max(common.w_max, w);
      }
      common.whole = common.sign * integrals(common.polygon, other.o, other.w0, other.wx, other.wy).integral;
      facet.occupied += common.whole;
      facet.commons.push_back(common);
    }
  }
  // Facets wholly below h are a prefix of the facets by z_max: their sums are kept per prefix.
  by_top_.resize(facets_.size());
  for (std::size_t i = 0; i < facets_.size(); ++i) by_top_[i] = static_cast<int>(i);
  std::sort(by_top_.begin(), by_top_.end(), [&](int a, int b) { return facets_[a].z_max < facets_[b].z_max; });
  // The facets h may cut: a fold's or one the lower contour crosses is clipped at each h; any
  // other's share of ΔV while h cuts it is a polynomial per piece between its corners' heights.
  for (std::size_t i = 0; i < facets_.size(); ++i) {
    const Facet& facet = facets_[i];
    if (!(facet.z_min < facet.z_max)) continue;
    if (facet.lower == -1 || !facet.partners.empty()) {
      by_bottom_.push_back(static_cast<int>(i));
    } else {
      add_pieces(facet);
    }
  }
  std::sort(by_bottom_.begin(), by_bottom_.end(), [&](int a, int b) { return facets_[a].z_min < facets_[b].z_min; });
  std::sort(pieces_.begin(), pieces_.end(), [](const Piece& a, const Piece& b) { return a.z0 < b.z0; });
  prefix_area_.assign(facets_.size() + 1, 0);
  prefix_occupied_.assign(facets_.size() + 1, 0);
  for (std::size_t k = 0; k < by_top_.size(); ++k) {
    prefix_area_[k + 1] = prefix_area_[k] + facets_[by_top_[k]].area;
    prefix_occupied_[k + 1] = prefix_occupied_[k] + facets_[by_top_[k]].occupied;
  }
}

// Measured by callgrind, build/tests/bench/bench_best --quick (the bunny at 0.15 mm: 143 layers
// searched, 2,058 heights): clipping every facet h cuts at every height, the search cost 561 M
// instructions (~270 k a height) and the constructor 279 M; with the pieces, the search 243 M
// (the facets still clipped: their moments in C(z_lo) 62 M of it) and the constructor 421 M
// (the pieces 124 M). Not taken: the sum of all facets' pieces as one piecewise cubic per slab
// (a sweep over the corners' heights adding and removing each facet's polynomial), which would
// make a height a binary search: a running sum of polynomials whose pieces differ in length by
// orders of magnitude (a nearly horizontal facet's: 1e-9 mm long, its curvature 1e18) loses
// the precision of every piece after it; each piece summed at its own local d keeps its
// clipped values' precision. Nor the exact minimiser of that cubic in place of Brent's search:
// a different height than the search's at its tolerance, so different sections.
// The constructor runs once per slab searched, whatever the candidates. Intersecting the
// folds' facets with their partners at each height cost 136 M of operator()'s 232 M in
// bench_best --quick (131,859 intersections). The constructor intersects each pair once (it
// needs them for the facets wholly below h anyway) and operator() cuts that at h, or takes it
// whole or not at all where it lies wholly below or above h; callgrind of the bunny's best
// slice at 0.15 mm: operator() 248 -> 154 M, the constructor 406 -> 417 M instructions. The
// same sets, not the same rounding: ΔV's last bits steer Brent's parabolic steps, so the
// heights and sections differ in their last bits from the per-height intersections' (analyze
// on the bunny and the bench models: D and ΔV within 6e-11 relative). Only 7% of those pairs
// have boxes apart (nothing worth a test before the intersection).
// A facet's share of ΔV while h cuts it, F(h) = t s_f (1 - 2 [f inside C(z_lo)]) A(h) - 2 I(h),
// with A(h) the area of f_h and I(h) = ∫ over f_h of w_f. Between two consecutive corner
// heights z0 < z1, A is quadratic in h (f_h grows by strips whose length is linear in h): the
// one through A at z0, the middle and z1 (clipped there; none of f lies below z_min, all of it
// below z_max). I' = (z_hi - h) A' (the strip added at h has w_f = z_hi - h), so I is the cubic
// with that derivative through I at z0. Each piece stores F(z0 + d) = q0 + q1 d + q2 d^2 +
// q3 d^3 in the local d, which keeps a piece of a nearly horizontal facet (short and steep)
// as well conditioned as its clipped values.
void SectionDeviation::add_pieces(const Facet& facet) {
  const double t = thickness_;
  std::array<double, kSmallCorners + 2> heights{};
  int n = 0;
  heights[n++] = facet.z_min;
  heights[n++] = facet.z_max;
  for (int k = 0; k < facet.outline.size; ++k) {
    const SmallPolygon::Corner p = facet.outline.at[k];
    const double z = z_hi_ - (facet.w0 + facet.wx * (p.x - facet.o.x) + facet.wy * (p.y - facet.o.y));
    if (z > facet.z_min && z < facet.z_max) heights[n++] = z;
  }
  std::sort(heights.begin(), heights.begin() + n);
  n = static_cast<int>(std::unique(heights.begin(), heights.begin() + n) - heights.begin());
  const double alpha = facet.lower == 1 ? -t : t;  // t (1 - 2 [f inside C(z_lo)])
  const double sign = facet.sign;
  const auto clipped = [&](double h) {
    return integrals_of_cut(facet.outline, facet.o, facet.w0 - (z_hi_ - h), facet.wx, facet.wy,
                            facet.w0, facet.wx, facet.wy);
  };
  // Nothing of it lies below z_min, all of it below z_max.
  Integrals low;
  for (int k = 0; k + 1 < n; ++k) {
    const double z0 = heights[k], z1 = heights[k + 1], zm = z0 + (z1 - z0) / 2;
    const Integrals high = k + 2 == n ? facet.whole : clipped(z1);
    // s_f A through (0, a0), (dm, am), (w, a1): Newton's form, then a0 + b1 d + b2 d^2; a piece
    // too short to halve is taken as linear.
    const double w = z1 - z0, dm = zm - z0;
    const double a0 = sign * low.area, a1 = sign * high.area;
    double b1 = (a1 - a0) / w, b2 = 0;
    if (dm > 0 && w - dm > 0) {
      const double am = sign * clipped(zm).area;
      const double s1 = (am - a0) / dm, s2 = ((a1 - am) / (w - dm) - s1) / w;
      b1 = s1 - dm * s2;
      b2 = s2;
    }
    // I' = c A' with c = z_hi - h = c0 - d, A = s_f (a0 + b1 d + b2 d^2) unsigned.
    const double c0 = z_hi_ - z0;
    const double i1 = sign * c0 * b1, i2 = sign * (2 * c0 * b2 - b1) / 2, i3 = -sign * 2 * b2 / 3;
    Piece piece;
    piece.z0 = z0;
    piece.z1 = z1;
    piece.q = {alpha * a0 - 2 * low.integral, alpha * b1 - 2 * i1, alpha * b2 - 2 * i2, -2 * i3};
    pieces_.push_back(piece);
    low = high;
  }
}

SectionDeviation::~SectionDeviation() = default;
SectionDeviation::SectionDeviation(SectionDeviation&&) noexcept = default;

double SectionDeviation::operator()(double h) const {
  const double t = thickness_;
  const std::size_t below = static_cast<std::size_t>(
      std::upper_bound(by_top_.begin(), by_top_.end(), h,
                       [&](double value, int f) { return value < facets_[f].z_max; }) -
      by_top_.begin());
  double area = lower_area_ + prefix_area_[below];
  double occupied = occupied_lower_ + prefix_occupied_[below];
  // The facets h cuts: begun below h, ended above it. Pieces first, by their closed forms.
  double pieces = 0;
  for (const Piece& piece : pieces_) {
    if (piece.z0 > h) break;
    if (piece.z1 <= h) continue;
    const double d = h - piece.z0;
    pieces += piece.q[0] + d * (piece.q[1] + d * (piece.q[2] + d * piece.q[3]));
  }
  for (int i : by_bottom_) {
    const Facet& facet = facets_[i];
    if (facet.z_min > h) break;
    if (facet.z_max <= h) continue;
    // The part where z_f <= h, i.e. w_f >= z_hi - h.
    const SmallPolygon part = cut(facet.outline, facet.o, facet.w0 - (z_hi_ - h), facet.wx, facet.wy);
    if (part.size < 3) continue;
    const Integrals own = integrals(part, facet.o, facet.w0, facet.wx, facet.wy);
    area += facet.sign * own.area;
    double in_lower = 0;
    if (facet.lower == 1) {
      in_lower = own.area;
    } else if (facet.lower == -1) {
      // Reused: a vector per cut would be a malloc per facet and height.
      // Its box taken as it is copied (bounding_box's own minima and maxima).
      thread_local std::vector<Vec2> loop;
      loop.resize(part.size);
      Box2 box;
      for (int k = 0; k < part.size; ++k) {
        loop[k] = {part.at[k].x, part.at[k].y};
        box.add(loop[k]);
      }
      in_lower = moments_of_intersection(loop, box, loop[0], lower_grid_, *lower_).area;
    }
    occupied += t * facet.sign * in_lower + own.integral;
    // f_h ∩ g: the facets' common part cut at h, seen from the partner's origin. A common
    // part wholly below h or above it is the constant or nothing.
    const double level = z_hi_ - h;
    for (const Facet::Common& common : facet.commons) {
      if (common.w_max < level) continue;
      if (common.w_min >= level) {
        occupied += common.whole;
        continue;
      }
      const Facet& other = facets_[common.other];
      occupied += common.sign * integrals_of_cut(common.polygon, other.o, facet.w0 - level + common.shift,
                                                 facet.wx, facet.wy, other.w0, other.wx, other.wy).integral;
    }
  }
  return std::max(volume_ + t * area - 2 * occupied + pieces, 0.0);
}

OptimalHeight optimal_height_search(const LayerStack& stack, std::size_t layer,
                                    const SlabColumns& columns,
                                    const SectionDeviation& deviation_at,
                                    const OptimalHeightOptions& options) {
  OptimalHeight best;
  if (layer >= stack.size()) return best;
  const Layer bounds = stack.layers()[layer];
  // At z_hi the section from above differs from the sum's (from below) only by faces lying in
  // that plane, which need a vertex there; if there is one, it is built, not summed.
  const bool face_on_top = !stack.vertex_heights_between(bounds.z_hi, bounds.z_hi).empty();
  const auto try_height = [&](double h) {
    const double deviation = h < bounds.z_hi || !face_on_top
                                 ? deviation_at(std::min(h, bounds.z_hi))
                                 : volume_deviation(columns, stack.cross_section(h));
    ++best.evaluations;
    if (best.evaluations == 1 || deviation < best.volume_deviation) {
      best.height = h;
      best.volume_deviation = deviation;
    }
    return deviation;
  };
  if (!(bounds.thickness() > 0)) {
    best.height = bounds.z_lo;
    best.volume_deviation = volume_deviation(columns, stack.cross_section(bounds.z_lo));
    best.evaluations = 1;
    return best;
  }
  const int samples = std::max(options.coarse_samples, 3);
  const double step = bounds.thickness() / (samples - 1);
  std::vector<double> deviation(samples);
  int best_sample = 0;
  for (int k = 0; k < samples; ++k) {
    deviation[k] = try_height(k + 1 == samples ? bounds.z_hi : bounds.z_lo + k * step);
    if (deviation[k] < deviation[best_sample]) best_sample = k;
  }
  // Brent's search (parabolic steps where ΔV is smooth, golden ones where not) inside the
  // bracket of the best sample, until the bracket is shorter than the tolerance. Boost's
  // search stops at a share of its argument's size, so it runs on s in [1, 2] for h from a
  // to b: its bracket, about 8 shares of 2^(1 - bits) wide when it stops, times b - a.
  const double a = bounds.z_lo + std::max(best_sample - 1, 0) * step;
  const int upper = std::min(best_sample + 1, samples - 1);
  const double b = upper + 1 == samples ? bounds.z_hi : bounds.z_lo + upper * step;
  const double tolerance = std::max(options.tolerance, 1e-9);
  if (b - a > tolerance) {
    const int bits = static_cast<int>(std::ceil(1 - std::log2(tolerance / (8 * (b - a)))));
    std::uintmax_t iterations = 100;
    boost::math::tools::brent_find_minima(
        [&](double s) {
          // Its first try is the bracket's top, a sample already tried.
          return s == 2 ? deviation[upper] : try_height(a + (s - 1) * (b - a));
        },
        1.0, 2.0, bits, iterations);
  }
  return best;
}

OptimalHeight optimal_height(const LayerStack& stack, std::size_t layer,
                             const SlabColumns& columns, const OptimalHeightOptions& options) {
  if (layer >= stack.size()) return {};
  OptimalHeight best = optimal_height_search(stack, layer, columns, SectionDeviation(columns), options);
  best.section = stack.cross_section(best.height);
  return best;
}

OptimalHeight optimal_height(const LayerStack& stack, std::size_t layer,
                             const OptimalHeightOptions& options) {
  if (layer >= stack.size()) return {};
  const SlabColumns columns = slab_columns(slab_of(stack, layer), stack.lower(layer));
  return optimal_height(stack, layer, columns, options);
}

ContourResult optimal_height_strategy(const ContourInput& input) {
  const OptimalHeightOptions& options = input.options.optimal;
  const LayerReference* reference = input.reference;
  OptimalHeight best;
  if (reference && reference->volumes) {
    best = optimal_height(input.stack, input.layer, reference->columns, options);
  } else if (reference) {
    best = optimal_height(input.stack, input.layer,
                          slab_columns(reference->slab, input.stack.lower(input.layer)), options);
  } else {
    best = optimal_height(input.stack, input.layer, options);
  }
  return {std::move(best.section), best.height};
}

}  // namespace geometry
