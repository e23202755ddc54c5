// The model options every command shares (MODEL.stl, --units, --scale, --height, --up) and
// loading a model through them: read, repair, place. What every later stage slices.
#pragma once

#include <string>

#include <CLI/CLI.hpp>

#include "geometry/mesh/mesh.h"
#include "geometry/core/polygon.h"
#include "geometry/mesh/repair.h"

namespace host {

struct ModelOptions {
  std::string path;
  std::string units = "mm";
  double scale = 1.0;
  double height = 0;  // 0: keep the size
  std::string up = "z";
  bool ignore_normals = false;
};

// Adds the positional MODEL argument (required) and the placement flags to a subcommand.
void add_model_options(CLI::App& command, ModelOptions& options);
// Adds only the placement flags (--units, --scale, --height, --up, --ignore-normals), listed
// under `group` in the help ("" leaves them among the command's other options): for a command
// whose positional argument is not always a model (`mahost print FILE.gcode`).
void add_placement_options(CLI::App& command, ModelOptions& options, const std::string& group = {});

// Reads, repairs and places the model, centred on `center`. Throws geometry::InputError with a
// one-line reason for a file that cannot be used. Prints a one-line repair summary to stderr
// when something was repaired.
geometry::Mesh load_model(const ModelOptions& options, geometry::Vec2 center = {0, 0});

// The same, silent, also returning what the repair did (in file units), for `mahost info`.
struct LoadedModel {
  geometry::Mesh mesh;  // placed, mm
  geometry::RepairReport repair;
};
LoadedModel load_model_with_report(const ModelOptions& options, geometry::Vec2 center = {0, 0});

}  // namespace host
