// The layered part (paper §4, Fig. 26): every layer's region extruded over the layer's
// thickness, as one closed triangle mesh that a viewer or another slicer can open, so a user
// can see (and print, or measure) exactly what a contour strategy deposits.
//
// Input: the layers (z_lo, z_hi, mm; ascending, not overlapping: a stack of any thicknesses)
// and one region per layer (outer loops CCW, holes CW), in the same order. Output: the
// boundary of the union of the prisms R_i x [z_lo, z_hi] as one manifold mesh, faces outward:
//   - walls: per loop of R_i, one strip of triangles from z_lo to z_hi;
//   - at every plane between layers k and k+1 (and under the first and over the last), the
//     horizontal faces of the symmetric difference: R_k \ R_k+1 facing up, R_k+1 \ R_k facing
//     down (where a wall goes on from one layer to the next, nothing), so that no edge is
//     shared by more than two faces and no face lies on another.
// Each region first loses its gaps and parts thinner than a micrometre (closed, then opened,
// by half a micrometre): loops that touch in a point or along an edge, which Clipper's unions
// leave, or a spike thinner than the grid, would make a prism touching itself, which no
// manifold surface bounds.
// Both regions of a plane are cut at each other's crossings on one grid (snap rounding, Hobby
// 1999: every segment goes through the centre of every grid cell it meets that holds a
// vertex or a crossing, so the rounded segments meet only at vertices), and the horizontal
// faces are a constrained Delaunay triangulation of that arrangement, each triangle inside
// one region and outside the other; where a rounded route goes out to a vertex and straight
// back (a vertex within a cell of a hot centre both its segments pass through), the wall
// leaves that spike out. The grid is the finest power of two below which every
// coordinate stays under 2^23 units (2^-18 mm for a part 50 mm across), so every coordinate
// is exactly a float32 and an STL of the mesh reads back as
// written: no facet turns over when rounded. The mesh's signed volume is the sum of
// area(R_i) t_i (of the regions on the grid, within 1e-9 of the given ones per mm of edge).
// Closed and manifold except where the regions of two neighbouring layers touch only along an
// edge or in a point, from opposite sides (a solid touching itself there). Empty regions and zero-thickness layers add nothing; extra layers or
// regions beyond the shorter list are ignored.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "geometry/slicing/layer_stack.h"
#include "geometry/mesh/mesh.h"
#include "geometry/core/polygon.h"

namespace geometry {

Mesh extruded_layers(std::span<const Layer> layers, std::span<const Region> regions);

// The triangles of one region (indices into the returned points), counter-clockwise.
struct RegionTriangulation {
  std::vector<Vec2> points;
  std::vector<std::array<std::uint32_t, 3>> triangles;
};
RegionTriangulation triangulate_region(const Region& region);

}  // namespace geometry
