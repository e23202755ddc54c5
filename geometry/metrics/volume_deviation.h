// Volume deviation of a layer (paper §2.1 eq. 1, §3.1 eq. 7; DESIGN.md §3).
//
// ΔV_i = vol(S_i △ P_i): the volume the layer's prism P_i = R_i x [z_lo, z_hi] overbuilds plus
// the volume of the slab S_i it leaves out, mm^3. Equivalently the integral over [z_lo, z_hi]
// of area(C(z) △ R_i). Computed through the slab's columns (slab_columns.h):
//   ΔV = vol(S_i) + t area(R_i) - 2 vol(S_i ∩ P_i),
// each term an exact integral of linear functions over polygons: the only errors are floating
// point (relative ~1e-12) and the 1 pm grid of the Clipper intersection with the lower
// section (under 1e-9 mm times its perimeter times t). Validated against adaptive Gauss-Legendre
// integration of Clipper XOR areas and CGAL corefinement (tests/geometry).
//
// Input: the slab's columns and any valid region (outer loops CCW, holes CW), mm.
// Output: mm^3, >= 0 up to rounding. Empty region: vol(S_i). Empty slab: t area(R_i).
#pragma once

#include "geometry/core/boundary_grid.h"
#include "geometry/core/polygon.h"
#include "geometry/slab/slab_columns.h"

namespace geometry {

double volume_deviation(const SlabColumns& columns, const Region& region);

// The same with the region's boundary already indexed (the grid must be built from `region`).
double volume_deviation(const SlabColumns& columns, const Region& region,
                        const BoundaryGrid& region_grid);

}  // namespace geometry
