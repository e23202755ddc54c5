// Reading and writing STL files (the triangle soup every model arrives as).
//
// Input of read_stl: a path to an ASCII or binary STL file of any size that fits in memory.
// A file is binary when its size is exactly 84 + 50 * (the facet count in its header), even
// if its header starts with "solid" (many exporters write that); otherwise it must be ASCII.
// Output: the facets in file order, coordinates in file units (STL has none; see placement.h).
// Stored normals never enter the geometry: the orientation of a facet is its vertex order.
// By default they are checked, because a normal that contradicts its vertex order means the
// file is inconsistent and the part may come out inside-out; `check_normals = false` skips it.
//
// Errors (geometry::InputError, one line): "<path>: <problem> (facet N)" or "(line N)" for
// a missing, unreadable or empty file, an ASCII syntax error, a truncated file, a binary
// facet count that disagrees with the file size, a NaN or infinite coordinate, no facets.
// A bad stored normal throws StlNormalsError, a kind of InputError, so that a caller can say
// how to proceed (mahost: --ignore-normals).
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "geometry/core/error.h"
#include "geometry/mesh/mesh.h"

namespace geometry {

struct StlNormalsError : InputError {
  using InputError::InputError;
};

struct StlReadOptions {
  // Refuse a facet whose stored normal is NaN, infinite, zero, or points against the normal
  // of its vertex order (beyond rounding). Degenerate facets are only checked for NaN/zero.
  bool check_normals = true;
};

std::vector<Triangle> read_stl(const std::string& path, const StlReadOptions& options = {});

// The same for a file already in memory; `name` is what error messages call it.
std::vector<Triangle> read_stl_bytes(std::string_view bytes, std::string_view name,
                                     const StlReadOptions& options = {});

// Writes a binary STL (float32, little-endian) with normals computed from vertex order.
// Throws InputError naming `path` when it cannot be written.
void write_stl_binary(const std::string& path, const Mesh& mesh);
void write_stl_binary(const std::string& path, const std::vector<Triangle>& triangles);

// Writes an ASCII STL ("solid <name>" ... "endsolid <name>"), coordinates with full precision.
void write_stl_ascii(const std::string& path, const std::vector<Triangle>& triangles,
                     std::string_view solid_name = "mahost");

}  // namespace geometry
