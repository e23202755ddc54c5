#include "geometry/metrics/volume_limit.h"

#include <algorithm>
#include <bit>


namespace geometry {

namespace {

using Poly = std::vector<Vec2>;

// A linear function f(p) = f0 + fx (p.x - o.x) + fy (p.y - o.y).
struct Linear {
  Vec2 o;
  double f0 = 0, fx = 0, fy = 0;
  double at(Vec2 p) const { return f0 + fx * (p.x - o.x) + fy * (p.y - o.y); }
  Linear moved_to(Vec2 origin) const { return {origin, at(origin), fx, fy}; }
};

// The part of a loop where f >= 0 (Sutherland-Hodgman against one half-plane), into `out`. A
// non-convex loop may come out with zero-width bridges along the line; they integrate to
// nothing.
void keep_nonnegative(const Poly& loop, const Linear& f, Poly& out) {
  out.clear();
  for (std::size_t i = 0, n = loop.size(); i < n; ++i) {
    const Vec2 a = loop[i], b = loop[(i + 1) % n];
    const double fa = f.at(a), fb = f.at(b);
    if (fa >= 0) out.push_back(a);
    if ((fa >= 0) != (fb >= 0)) out.push_back(a + (fa / (fa - fb)) * (b - a));
  }
}

// ∫ over a loop (signed by its orientation) of min(f, t - f). Runs for every facet of every
// slab: the two halves go to reused buffers, not fresh vectors.
double integrate_min(const Poly& loop, const Linear& f, double t) {
  if (loop.size() < 3) return 0;
  thread_local Poly low, high;
  keep_nonnegative(loop, Linear{f.o, t / 2 - f.f0, -f.fx, -f.fy}, low);  // where f <= t/2
  keep_nonnegative(loop, Linear{f.o, f.f0 - t / 2, f.fx, f.fy}, high);   // where f >= t/2
  return integrate_linear(low, f.o, f.f0, f.fx, f.fy) +
         integrate_linear(high, f.o, t - f.f0, -f.fx, -f.fy);
}

Linear depth_of(const ColumnFacet& facet) {
  return {facet.outline[0], facet.w0, facet.wx, facet.wy};
}

// Folds (the header): the correction is ∫ phi(cover(x)) over the plane, cover(x) the facets
// above column x and, for a set T of facets,
//   phi(T) = min(occ_T, t - occ_T) - sum over f in T of min(w_f, t - w_f),
// occ_T the occupancy T alone would give (walking up from solid if T's lowest facet is an
// exit). phi vanishes on single facets. By Moebius inversion over the subsets of cover(x),
//   ∫ phi(cover) = sum over sets S of overlapping facets of ∫ over ∩S of psi(S),
//   psi(S) = sum over T ⊆ S, |T| >= 2, of (-1)^(|S| - |T|) phi(T),
// and every ∩S is convex (facets are convex). Facets overlapping seen from above do not cross
// (the surface does not intersect itself), so their vertical order is one on all of ∩S.
// A fold has two sheets over most of its area: pairs, and the odd triple along edges.
struct Folds {
  const SlabColumns& columns;
  const std::vector<std::vector<int>>& overlapping;  // larger indices only
  double t;
  double total = 0;

  // ∫ over `piece` of phi(T), T given by `members` (bits of `set`).
  double phi(const Poly& piece, const std::vector<int>& set, unsigned members, Vec2 centroid) const {
    std::vector<int> subset;
    for (std::size_t k = 0; k < set.size(); ++k)
      if (members & (1u << k)) subset.push_back(set[k]);
    int lowest = subset[0];
    for (int f : subset) {
      // Larger depth below z_hi = lower facet.
      if (depth_of(columns.facets[f]).at(centroid) > depth_of(columns.facets[lowest]).at(centroid)) lowest = f;
    }
    const Vec2 o = piece[0];
    Linear occ{o, columns.facets[lowest].sign < 0 ? t : 0.0, 0, 0};
    double value = 0;
    for (int f : subset) {
      const Linear w = depth_of(columns.facets[f]).moved_to(o);
      const int s = columns.facets[f].sign;
      occ.f0 += s * w.f0;
      occ.fx += s * w.fx;
      occ.fy += s * w.fy;
      value -= integrate_min(piece, w, t);
    }
    return value + integrate_min(piece, occ, t);
  }

  void add(const std::vector<int>& set, const Poly& piece) {
    const AreaMoments m = moments_of_loop(piece, piece[0]);
    const Vec2 centroid = piece[0] + Vec2{m.mx / m.area, m.my / m.area};
    const unsigned all = (1u << set.size()) - 1;
    for (unsigned members = all;; members = (members - 1) & all) {
      if (std::popcount(members) >= 2) {
        const int sign = (std::popcount(all) - std::popcount(members)) % 2 ? -1 : 1;
        total += sign * phi(piece, set, members, centroid);
      }
      if (members == 0) break;
    }
  }

  // Every set of facets, `set` extended by larger indices, whose common part has area.
  void extend(std::vector<int>& set, const Poly& common, const std::vector<int>& candidates) {
    for (int g : candidates) {
      const Poly next = convex_intersection(common, columns.facets[g].outline);
      if (next.size() < 3 || signed_area(next) <= kFoldArea) continue;
      set.push_back(g);
      add(set, next);
      if (set.size() < 16) {
        std::vector<int> further;
        for (int h : overlapping[g])
          if (std::find(candidates.begin(), candidates.end(), h) != candidates.end()) further.push_back(h);
        extend(set, next, further);
      }
      set.pop_back();
    }
  }
};

}  // namespace

double volume_limit(const SlabColumns& columns) {
  const double t = columns.thickness();
  if (!(t > 0)) return 0;
  double limit = 0;
  for (const ColumnFacet& facet : columns.facets) limit += integrate_min(facet.outline, depth_of(facet), t);

  const std::vector<std::vector<int>>& overlapping = columns.overlapping;
  if (std::all_of(overlapping.begin(), overlapping.end(), [](const auto& l) { return l.empty(); })) {
    return std::max(limit, 0.0);
  }
  Folds folds{columns, overlapping, t};
  std::vector<int> set;
  for (std::size_t a = 0; a < overlapping.size(); ++a) {
    if (overlapping[a].empty()) continue;
    set.assign(1, static_cast<int>(a));
    folds.extend(set, columns.facets[a].outline, overlapping[a]);
  }
  limit += folds.total;
  return std::max(limit, 0.0);
}

}  // namespace geometry
