// The normals an STL file stores, against the part its repair made (repair.h).
//
// Slicers take a facet's side from its vertex order and the repair orients every closed
// surface outward, so a stored normal decides nothing; but one that points into the repaired
// part says the exporter and the repair disagree about a facet, which a user may want to know
// (`mahost info`). Input: the facets and their stored normals as read (stl_io.h, file order)
// and the repaired mesh in the same units (before placement). Output: the counts below. A
// facet the repair dropped (degenerate, duplicate) and a needle or cap (twice its area below
// 1e-5 of its longest edge squared, where float rounding can turn its vertex-order normal any
// way) are not compared. Total: empty input gives zeros.
#pragma once

#include <cstddef>
#include <vector>

#include "geometry/mesh/mesh.h"

namespace geometry {

struct StoredNormals {
  std::size_t facets = 0;       // facets with a stored normal
  std::size_t no_direction = 0;  // zero, NaN or infinite: written by many exporters, harmless
  std::size_t compared = 0;     // found in the repaired mesh with a direction to compare
  std::size_t disagreeing = 0;  // pointing into the repaired part (cosine below -1e-3)
};

StoredNormals compare_stored_normals(const std::vector<Triangle>& facets,
                                     const std::vector<Vec3>& normals, const Mesh& repaired);

}  // namespace geometry
