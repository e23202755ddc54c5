// Reading Wavefront OBJ files (the geometry: vertices and faces).
//
// Input: the file's text. Output: every face as triangles, in file units (OBJ has none, like
// STL; see placement.h), in file order; a face of n corners is cut into the fan of n - 2
// triangles from its first corner (right for the convex faces exporters write). Corners may
// be written v, v/vt, v//vn or v/vt/vn, counted from 1 or, negative, back from the last
// vertex read. Texture coordinates, normals, groups, objects, materials, smoothing and lines
// are skipped; a vertex's optional fourth coordinate (w) is ignored.
//
// Errors (InputError, one line, "<name>: <problem> (line N)"): a vertex that is not three
// numbers, a face with fewer than three corners or a corner that names no vertex read so far,
// a NaN or infinite coordinate, no faces at all.
#pragma once

#include <string_view>
#include <vector>

#include "geometry/mesh/mesh.h"

namespace geometry {

std::vector<Triangle> read_obj_text(std::string_view text, std::string_view name);

}  // namespace geometry
