#include "geometry/volume_limit.h"

#include <algorithm>
#include <numeric>


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

// The part of a loop where f >= 0 (Sutherland-Hodgman against one half-plane). A non-convex
// loop may come out with zero-width bridges along the line; they integrate to nothing.
Poly keep_nonnegative(const Poly& loop, const Linear& f) {
  Poly out;
  for (std::size_t i = 0, n = loop.size(); i < n; ++i) {
    const Vec2 a = loop[i], b = loop[(i + 1) % n];
    const double fa = f.at(a), fb = f.at(b);
    if (fa >= 0) out.push_back(a);
    if ((fa >= 0) != (fb >= 0)) out.push_back(a + (fa / (fa - fb)) * (b - a));
  }
  return out;
}

// ∫ over a loop (signed by its orientation) of min(f, t - f).
double integrate_min(const Poly& loop, const Linear& f, double t) {
  if (loop.size() < 3) return 0;
  const Linear below{f.o, t / 2 - f.f0, -f.fx, -f.fy};  // >= 0 where f <= t/2
  const Linear above{f.o, f.f0 - t / 2, f.fx, f.fy};    // >= 0 where f >= t/2
  const Poly low = keep_nonnegative(loop, below), high = keep_nonnegative(loop, above);
  return integrate_linear(low, f.o, f.f0, f.fx, f.fy) +
         integrate_linear(high, f.o, t - f.f0, -f.fx, -f.fy);
}

Linear depth_of(const ColumnFacet& facet) {
  return {facet.outline[0], facet.w0, facet.wx, facet.wy};
}

// Area of the intersection of two convex counter-clockwise polygons.
double convex_overlap(const Poly& a, const Poly& b) {
  Poly piece = a;
  for (std::size_t k = 0, n = b.size(); k < n && piece.size() >= 3; ++k) {
    const Vec2 p = b[k], d = b[(k + 1) % n] - p;
    // Left of p -> p + d: cross(d, x - p) >= 0, a linear function of x.
    const Linear left{p, 0, -d.y, d.x};
    piece = keep_nonnegative(piece, left);
  }
  return piece.size() >= 3 ? signed_area(piece) : 0;
}

struct Cell {
  ClipperLib::Paths paths;
  std::vector<int> cover;  // facets above every column of the cell
  ClipperLib::IntRect box;
};

ClipperLib::IntRect bounds(const ClipperLib::Paths& paths) {
  ClipperLib::IntRect box{0, 0, 0, 0};
  bool first = true;
  for (const auto& path : paths) {
    for (const auto& p : path) {
      if (first) {
        box = {p.X, p.Y, p.X, p.Y};
        first = false;
      }
      box.left = std::min(box.left, p.X);
      box.right = std::max(box.right, p.X);
      box.top = std::min(box.top, p.Y);
      box.bottom = std::max(box.bottom, p.Y);
    }
  }
  return box;
}

bool boxes_meet(const ClipperLib::IntRect& a, const ClipperLib::IntRect& b) {
  return a.left <= b.right && b.left <= a.right && a.top <= b.bottom && b.top <= a.bottom;
}

ClipperLib::Paths boolean(ClipperLib::ClipType type, const ClipperLib::Paths& a,
                          const ClipperLib::Paths& b) {
  ClipperLib::Clipper clipper;
  clipper.AddPaths(a, ClipperLib::ptSubject, true);
  clipper.AddPaths(b, ClipperLib::ptClip, true);
  ClipperLib::Paths result;
  clipper.Execute(type, result, ClipperLib::pftNonZero, ClipperLib::pftNonZero);
  return result;
}

// The cells of the arrangement of a group of overlapping facets: pieces of the plane with the
// same set of facets above them.
std::vector<Cell> arrangement(const SlabColumns& columns, const std::vector<int>& group) {
  std::vector<Cell> cells;
  for (int f : group) {
    const ClipperLib::Paths facet{to_fine_clipper(columns.facets[f].outline)};
    const ClipperLib::IntRect box = bounds(facet);
    std::vector<Cell> next;
    ClipperLib::Paths covered;
    for (Cell& cell : cells) {
      if (!boxes_meet(cell.box, box)) {
        next.push_back(std::move(cell));
        continue;
      }
      ClipperLib::Paths inside = boolean(ClipperLib::ctIntersection, cell.paths, facet);
      ClipperLib::Paths outside = boolean(ClipperLib::ctDifference, cell.paths, facet);
      covered.insert(covered.end(), cell.paths.begin(), cell.paths.end());
      if (!inside.empty()) {
        std::vector<int> cover = cell.cover;
        cover.push_back(f);
        const ClipperLib::IntRect inside_box = bounds(inside);
        next.push_back({std::move(inside), std::move(cover), inside_box});
      }
      if (!outside.empty()) {
        const ClipperLib::IntRect outside_box = bounds(outside);
        next.push_back({std::move(outside), std::move(cell.cover), outside_box});
      }
    }
    ClipperLib::Paths rest = covered.empty() ? facet : boolean(ClipperLib::ctDifference, facet, covered);
    if (!rest.empty()) {
      const ClipperLib::IntRect rest_box = bounds(rest);
      next.push_back({std::move(rest), {f}, rest_box});
    }
    cells = std::move(next);
  }
  return cells;
}

// ∫ over the cell of min(occ, t - occ) minus what the single-facet sums counted there.
double fold_correction(const SlabColumns& columns, const Cell& cell) {
  const double t = columns.thickness();
  std::vector<Poly> loops;
  for (const auto& path : cell.paths) {
    Poly loop;
    for (const auto& p : path) loop.push_back(from_fine_clipper(p));
    loops.push_back(std::move(loop));
  }
  const Vec2 o = loops[0][0];
  AreaMoments m;
  for (const Poly& loop : loops) {
    const AreaMoments part = moments_of_loop(loop, o);
    m.area += part.area;
    m.mx += part.mx;
    m.my += part.my;
  }
  if (!(m.area > 1e-18)) return 0;
  // Facets do not cross inside a cell, so the sign of z_f - z_g is constant on it; being
  // linear, its value at the centroid has that sign even if the centroid is outside the cell.
  const Vec2 centroid = o + Vec2{m.mx / m.area, m.my / m.area};
  std::vector<int> order = cell.cover;
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    // Larger depth below z_hi = lower facet.
    return depth_of(columns.facets[a]).at(centroid) > depth_of(columns.facets[b]).at(centroid);
  });
  // Walking up, an up-facing facet is an exit: if the lowest is one, the column starts solid.
  const bool solid_at_bottom = columns.facets[order.front()].sign < 0;
  Linear occ{o, solid_at_bottom ? t : 0.0, 0, 0};
  for (int f : cell.cover) {
    const Linear w = depth_of(columns.facets[f]).moved_to(o);
    const int s = columns.facets[f].sign;
    occ.f0 += s * w.f0;
    occ.fx += s * w.fx;
    occ.fy += s * w.fy;
  }
  double correction = 0;
  for (const Poly& loop : loops) {
    correction += integrate_min(loop, occ, t);
    for (int f : cell.cover) correction -= integrate_min(loop, depth_of(columns.facets[f]).moved_to(o), t);
  }
  return correction;
}

int find(std::vector<int>& parent, int i) {
  while (parent[i] != i) i = parent[i] = parent[parent[i]];
  return i;
}

}  // namespace

double volume_limit(const SlabColumns& columns) {
  const double t = columns.thickness();
  if (!(t > 0)) return 0;
  double limit = 0;
  for (const ColumnFacet& facet : columns.facets) limit += integrate_min(facet.outline, depth_of(facet), t);

  // Folds: up-facing facets overlapping down-facing ones seen from above.
  std::vector<Segment2> down_boxes;
  std::vector<int> down_ids;
  for (std::size_t i = 0; i < columns.facets.size(); ++i) {
    if (columns.facets[i].sign > 0) {
      down_boxes.push_back({columns.facets[i].lo, columns.facets[i].hi});
      down_ids.push_back(static_cast<int>(i));
    }
  }
  if (down_ids.empty() || down_ids.size() == columns.facets.size()) return std::max(limit, 0.0);
  // A segment's box is the facet's box, so the grid finds facets whose boxes meet.
  const BoundaryGrid down_grid(std::move(down_boxes));
  std::vector<int> parent(columns.facets.size());
  std::iota(parent.begin(), parent.end(), 0);
  std::vector<bool> folded(columns.facets.size(), false);
  bool any = false;
  for (std::size_t u = 0; u < columns.facets.size(); ++u) {
    const ColumnFacet& up = columns.facets[u];
    if (up.sign > 0) continue;
    down_grid.for_each_near(up.lo, up.hi, [&](std::uint32_t k) {
      const int d = down_ids[k];
      // Neighbours along an edge touch without overlapping: their overlap is rounding.
      if (convex_overlap(up.outline, columns.facets[d].outline) <= 1e-12) return;
      folded[u] = folded[d] = any = true;
      parent[find(parent, static_cast<int>(u))] = find(parent, d);
    });
  }
  if (!any) return std::max(limit, 0.0);
  std::vector<std::vector<int>> groups(columns.facets.size());
  for (std::size_t i = 0; i < columns.facets.size(); ++i)
    if (folded[i]) groups[find(parent, static_cast<int>(i))].push_back(static_cast<int>(i));
  for (const auto& group : groups) {
    if (group.size() < 2) continue;
    for (const Cell& cell : arrangement(columns, group)) {
      if (cell.cover.size() >= 2) limit += fold_correction(columns, cell);
    }
  }
  return std::max(limit, 0.0);
}

}  // namespace geometry
