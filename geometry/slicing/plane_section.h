// One plane's cross-section of a mesh, from the faces that cross it: the core that
// slice_mesh (slicer.h) and LayerStack::cross_section (layer_stack.h) share.
//
// Input: an indexed, outward-oriented Mesh; `faces`, indices of (at least) every face with
// min z <= z < max z (other faces are skipped, so a superset is fine); the height z, mm.
// Output: the Region at z with slicer.h's conventions. The plane is taken symbolically just
// above z (a vertex with height exactly z counts as below it), so each crossing face gives
// one segment between two of its edges and no case is degenerate. Each point is identified
// by the mesh edge it lies on, or by the vertex when that lies exactly at z, and segments are
// chained by that identity, never by comparing coordinates; the direction of a segment (solid
// on its left) comes from the face's orientation, so outer loops come out CCW and holes CW
// without any re-orientation. What has zero width in the limit is left out: segments of zero
// length, and pairs of opposite segments between the same two points (a slit: the plane
// touching a notch's tip or a ring of vertices from above, as at a torus's bottom). Loops of
// fewer than three points or of no area (a section shrinking to an apex or a ridge) are
// dropped. Loops may touch one another at a vertex (two parts meeting at a point).
//
// Not closed input (never crashes): a chain that ends at an open edge is closed by the
// straight line from its last point back to its first.
#pragma once

#include <cstdint>
#include <span>

#include "geometry/mesh/mesh.h"
#include "geometry/core/polygon.h"

namespace geometry {

Region plane_section(const Mesh& mesh, std::span<const std::uint32_t> faces, double z);

}  // namespace geometry
