// The benchmarks' model: read, repaired and placed as `mahost slice` places it. The Stanford
// bunny (data/bunny.stl, its file name contains "bunny") is in metres with +Y up, so it is
// scaled to 50 mm tall standing on Z; any other model is taken as it is, in mm with +Z up.
#pragma once

#include <string>

#include "geometry/mesh/placement.h"
#include "geometry/mesh/repair.h"
#include "geometry/mesh/stl_io.h"

namespace bench {

inline bool is_bunny(const std::string& path) { return path.find("bunny") != std::string::npos; }

inline geometry::Placement bunny_placement() {
  geometry::Placement placement;
  placement.units_to_mm = 1000;
  placement.up = geometry::Axis::y;
  placement.height = 50;
  return placement;
}

inline geometry::Placement placement_for(const std::string& path) {
  return is_bunny(path) ? bunny_placement() : geometry::Placement{};
}

inline geometry::Mesh load_model(const std::string& path, geometry::RepairReport* report = nullptr) {
  return geometry::place(geometry::repair(geometry::read_stl(path), report), placement_for(path));
}

}  // namespace bench
