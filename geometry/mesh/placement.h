// Placing a model for printing: units, scale, which axis is up, centred, resting on z = 0.
//
// Input: a mesh in file units. Output: the same mesh in mm, rotated so that `up` becomes +Z
// (a proper rotation, so outward faces stay outward), then by `rotation` (orientation.h),
// scaled, its bounding box centred on `center` in XY and its lowest point on z = 0. Heights are snapped to a 1 nm grid, so faces
// that are flat up to the file's float noise come out exactly flat. An empty mesh stays empty.
#pragma once

#include <optional>

#include "geometry/mesh/mesh.h"
#include "geometry/mesh/orientation.h"
#include "geometry/core/polygon.h"

namespace geometry {

enum class Axis { x, y, z };

struct Placement {
  double units_to_mm = 1.0;       // m: 1000, mm: 1, in: 25.4
  double scale = 1.0;             // applied after units
  std::optional<double> height;   // if set, scale uniformly so the part is this tall, mm
  Axis up = Axis::z;              // the model's axis that points up on the bed
  Rotation rotation;              // then this turn (identity: none)
  Vec2 center{0, 0};              // where the bounding box centre goes in XY, mm
};

Mesh place(Mesh mesh, const Placement& placement);

}  // namespace geometry
