// The layered part (paper §4, Fig. 26): every layer's region extruded over the layer's
// thickness, as one triangle mesh that a viewer or another slicer can open, so a user can see
// (and print, or measure) exactly what a contour strategy deposits.
//
// Input: the layers (z_lo, z_hi, mm) and one region per layer (valid: outer loops CCW, holes
// CW), in the same order. Output: a Mesh made of one closed prism per layer (top and bottom
// faces triangulated with CGAL's constrained Delaunay triangulation, holes kept; one wall quad
// per loop edge), faces oriented outward. Prisms of neighbouring layers touch along their
// shared plane but are separate shells: each is watertight on its own, and the mesh's signed
// volume is the sum of area(R_i) t_i. Empty regions and zero-thickness layers add nothing;
// extra layers or regions beyond the shorter list are ignored.
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
