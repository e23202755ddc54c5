// Reading 3MF files (3D Manufacturing Format: a zip archive of XML parts), as slicers and model
// sites write them.
//
// Input: the file's bytes (read_model in model_io.h reads the file). Output: every object of
// the build placed as the build says, all in one triangle list, in mm: each build item's
// object with the item's transform, components (also from other model parts, the
// production extension's p:path) with their transforms inside it, in the model's unit
// (micron, millimeter, centimeter, inch, foot, meter). Mirroring transforms keep the
// triangles' sides (their vertex order is reversed). Objects that are not "model" (the
// producer's own supports, surfaces, "other") and items PrusaSlicer marks printable="0" are
// left out, and so are PrusaSlicer's modifier, support blocker and enforcer volumes
// (Metadata/Slic3r_PE_model.config); a negative volume is refused, as mahost cannot cut it.
// Materials, colours, textures and beam lattices are not read.
//
// Errors (InputError, one line, naming `name` and the part): not a zip archive, no 3D model
// part, XML that does not parse (with the byte), an unknown unit, a missing or malformed
// attribute, an object id or vertex index that does not exist, a component cycle, a build
// with nothing printable.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include "geometry/mesh/mesh.h"

namespace geometry {

struct ThreeMfModel {
  std::vector<Triangle> triangles;  // mm, placed as the build places them
  std::size_t items = 0;            // build items read (object instances on the plate)
  std::string unit;                 // the model's unit as written ("millimeter")
};

ThreeMfModel read_3mf_bytes(std::string_view bytes, std::string_view name);

// True when `bytes` start like a zip archive (PK\3\4), as every 3MF does.
bool looks_like_zip(std::string_view bytes);

}  // namespace geometry
