// The slab as vertical columns: how much of each column (x, y) x [z_lo, z_hi] the model fills
// (paper §3.1, eq. 1 and 7; DESIGN.md §3). Every volume figure of a layer is an integral of
// this occupied height occ(x, y):
//   vol(S_i)              = integral of occ over the plane
//   vol(S_i ∩ R x [z_lo, z_hi]) = integral of occ over R
//   ΔV(R) = vol(S_i △ P_i) = vol(S_i) + t area(R) - 2 integral of occ over R
//   the volume limit      = integral of min(occ, t - occ)             (volume_limit.h)
//
// Why columns and not cross-sections: a vertical line meets the slab's surface at its facets;
// walking up, every up-facing facet is an exit and every down-facing one an entry, so
//   occ(x, y) = t [(x, y) in C(z_lo)] + sum over facets f above (x, y) of s_f (z_hi - z_f(x, y)),
// s_f = -1 for up-facing, +1 for down-facing facets, z_f the facet's plane. Each term is
// linear over a convex polygon (the facet's projection), so the integral over any polygonal
// region R is a sum of exact integrals of linear functions over (facet ∩ R): no quadrature,
// no sampling. That is what makes ΔV exact (to floating point) and fast.
//
// Input: a Slab (slab.h: facets clipped to the slab, faces lying in the planes z_lo or z_hi
// left out) and the section at z_lo as the limit from above (LayerStack::lower), mm.
// Conventions match: a horizontal face at z_lo is not a facet of the slab, and the lower
// section holds exactly what lies just above it. Vertical facets have no area and drop out.
// Empty slab: no facets, zero volume.
#pragma once

#include <array>
#include <vector>

#include "geometry/core/boundary_grid.h"
#include "geometry/core/polygon.h"
#include "geometry/slab/slab.h"

namespace geometry {

// A facet of the slab seen from above: its projection (convex, counter-clockwise) and the
// depth of the slab's top below it, w(x, y) = z_hi - z_f(x, y) = w0 + wx (x - origin.x) +
// wy (y - origin.y), with origin its first vertex.
struct ColumnFacet {
  std::vector<Vec2> outline;
  double w0 = 0, wx = 0, wy = 0;
  int sign = 0;  // -1 up-facing (an exit), +1 down-facing (an entry)
  Vec2 lo, hi;   // bounding box
};

struct SlabColumns {
  double z_lo = 0, z_hi = 0;
  std::vector<ColumnFacet> facets;
  Region lower;                   // C(z_lo), limit from above
  double lower_area = 0;
  double volume = 0;              // vol(S_i), mm^3
  // Folds: overlapping_facets(*this) below, for the volume limit and optimal-height.
  std::vector<std::vector<int>> overlapping;
  double thickness() const { return z_hi - z_lo; }
};

SlabColumns slab_columns(const Slab& slab, const Region& lower_section);
// The same into `columns`, whatever it held: its facets' outlines keep their storage, for a
// caller that builds one slab's columns after another (a facet's outline is an allocation).
void slab_columns(const Slab& slab, const Region& lower_section, SlabColumns& columns);

// Exact integrals of 1, x - o.x and y - o.y over (convex polygon ∩ region), mm^2 and mm^3:
// the region's boundary (as a grid, whose segments must be those of `region`) clipped by
// the polygon plus the polygon's boundary inside the region (Green's theorem). Degenerate
// configurations (the region's boundary through a polygon corner, or exactly along it) fall
// back to Clipper on the whole region (1 pm grid). AreaMoments: core/polygon.h.
AreaMoments moments_of_intersection(const std::vector<Vec2>& convex, Vec2 origin,
                                    const BoundaryGrid& region_grid, const Region& region);
// The same with the polygon's bounding_box given (a ColumnFacet's lo and hi), for callers
// that have it: the same value.
AreaMoments moments_of_intersection(const std::vector<Vec2>& convex, const Box2& box, Vec2 origin,
                                    const BoundaryGrid& region_grid, const Region& region);

// Integral of occ over R, mm^3: vol(S_i ∩ R x [z_lo, z_hi]).
double occupied_volume_inside(const SlabColumns& columns, const Region& region);
double occupied_volume_inside(const SlabColumns& columns, const Region& region,
                              const BoundaryGrid& region_grid);

// Clipper on the picometre grid (clipper.h's to_fine_clipper), not the nanometre one: these
// intersections feed volume integrals that should be exact, and a nanometre grid would move
// them by up to 0.7 nm times the boundary's length times t (1e-5 mm^3 on a bunny layer).
// Coordinates stay far below Clipper's limit (2^62 pm, 4600 km); above 2^30 pm (1 mm) it uses
// 128-bit products, about twice as slow, which these few calls per layer can afford.
// Area of the intersection of two regions (Clipper on the 1 pm grid), mm^2.
double intersection_area(const Region& a, const Region& b);

// Integral over a polygon (one loop, any orientation: signed) of w0 + wx (x - o.x) +
// wy (y - o.y), from its boundary.
double integrate_linear(const std::vector<Vec2>& loop, Vec2 origin, double w0, double wx,
                        double wy);

// The part of a polygon where the linear function f0 + fx (x - o.x) + fy (y - o.y) is >= 0
// (Sutherland-Hodgman against one half-plane; a convex polygon stays convex, a non-convex one
// may come out with zero-width bridges along the line, which integrate to nothing).
std::vector<Vec2> clip_to_half_plane(const std::vector<Vec2>& polygon, Vec2 o, double f0,
                                     double fx, double fy);

// The intersection of a convex polygon with a convex counter-clockwise one.
std::vector<Vec2> convex_intersection(std::vector<Vec2> polygon, const std::vector<Vec2>& by);

// Folds (columns that meet two or more facets, where an up-facing and a down-facing facet
// overlap seen from above): for every facet a, the larger indices b of the facets whose
// projection overlaps a's by more than kFoldArea, ascending. Facets of no fold, and every
// facet of a slab without folds, have none.
inline constexpr double kFoldArea = 1e-12;  // mm^2: less is neighbours touching along an edge
std::vector<std::vector<int>> overlapping_facets(const SlabColumns& columns);

}  // namespace geometry
