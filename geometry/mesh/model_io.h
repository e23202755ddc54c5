// Reading a model file in any format mahost takes: STL (stl_io.h), 3MF (threemf_io.h) or OBJ
// (obj_io.h). The format is the file's: a zip archive is 3MF, a name ending in .obj is OBJ,
// anything else STL. Each reader's contract holds (errors: InputError, one line naming the
// file).
#pragma once

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include "geometry/mesh/mesh.h"

namespace geometry {

enum class ModelFormat { stl, threemf, obj };

// "STL", "3MF", "OBJ".
std::string_view format_name(ModelFormat format);

struct ModelFile {
  ModelFormat format = ModelFormat::stl;
  std::vector<Triangle> triangles;   // every object together; mm if units_recorded, else file units
  std::vector<Vec3> stored_normals;  // STL: each facet's stored normal, in file order; else empty
  bool units_recorded = false;       // 3MF records its unit (triangles are in mm); STL and OBJ do not
  std::size_t objects = 1;           // 3MF: the build items placed together
};

// Whether a file's name says it is a model mahost reads: .stl, .3mf or .obj, in any case.
bool is_model_name(std::string_view name);

// Reads the whole file. Errors: a missing or unreadable file, a directory, then the format's.
ModelFile read_model(const std::string& path);

// The same for bytes already in memory; `name` is the file's name (its extension says OBJ) and
// what messages call it.
ModelFile read_model_bytes(std::string_view bytes, std::string_view name);

}  // namespace geometry
