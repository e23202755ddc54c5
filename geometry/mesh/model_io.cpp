// Reading a model file in any format; see model_io.h.
#include "geometry/mesh/model_io.h"

#include "geometry/mesh/file_bytes.h"
#include "geometry/mesh/obj_io.h"
#include "geometry/mesh/stl_io.h"
#include "geometry/mesh/threemf_io.h"

namespace geometry {
namespace {

bool ends_with_nocase(std::string_view name, std::string_view suffix) {
  if (name.size() < suffix.size()) return false;
  for (std::size_t i = 0; i < suffix.size(); ++i) {
    const char c = name[name.size() - suffix.size() + i];
    if ((c >= 'A' && c <= 'Z' ? c - 'A' + 'a' : c) != suffix[i]) return false;
  }
  return true;
}

}  // namespace

bool is_model_name(std::string_view name) {
  return ends_with_nocase(name, ".stl") || ends_with_nocase(name, ".3mf") || ends_with_nocase(name, ".obj");
}

std::string_view format_name(ModelFormat format) {
  switch (format) {
    case ModelFormat::stl: return "STL";
    case ModelFormat::threemf: return "3MF";
    case ModelFormat::obj: return "OBJ";
  }
  return "STL";
}

ModelFile read_model_bytes(std::string_view bytes, std::string_view name) {
  ModelFile model;
  if (looks_like_zip(bytes)) {
    ThreeMfModel file = read_3mf_bytes(bytes, name);
    model.format = ModelFormat::threemf;
    model.triangles = std::move(file.triangles);
    model.units_recorded = true;
    model.objects = file.items;
  } else if (ends_with_nocase(name, ".obj")) {
    model.format = ModelFormat::obj;
    model.triangles = read_obj_text(bytes, name);
  } else {
    StlReadOptions options;
    options.stored_normals = &model.stored_normals;
    model.triangles = read_stl_bytes(bytes, name, options);
  }
  return model;
}

ModelFile read_model(const std::string& path) { return read_model_bytes(read_file_bytes(path), path); }

}  // namespace geometry
