// Reading and writing STL files (the triangle soup every model arrives as).
//
// Input of read_stl: a path to an ASCII or binary STL file of any size that fits in memory.
// A file is binary when its size is exactly 84 + 50 * (the facet count in its header), even
// if its header starts with "solid" (many exporters write that); otherwise it must be ASCII.
// Output: the facets in file order, coordinates in file units (STL has none; see placement.h).
// Stored normals never enter the geometry, as in every other slicer: the vertex order and the
// repair (repair.h, which orients every closed surface outward) decide which side is outside.
// A caller may take them (StlReadOptions::stored_normals) to count those that disagree with
// the repaired part (stored_normals.h); zero, NaN or contradicting normals are never refused.
//
// Errors (geometry::InputError, one line): "<path>: <problem> (facet N)" or "(line N)" for
// a missing, unreadable or empty file, an ASCII syntax error, a truncated file, a binary
// facet count that disagrees with the file size, a NaN or infinite coordinate, no facets.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "geometry/core/error.h"
#include "geometry/mesh/mesh.h"

namespace geometry {

struct StlReadOptions {
  // If set, receives each facet's stored normal, in file order (as stored: possibly zero,
  // NaN or not of unit length).
  std::vector<Vec3>* stored_normals = nullptr;
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
