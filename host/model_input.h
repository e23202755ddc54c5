// The model options every command shares (MODEL: STL, 3MF or OBJ; --units, --scale, --height,
// --up) and loading a model through them: read, repair, place. What every later stage slices.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "geometry/mesh/mesh.h"
#include "geometry/mesh/model_io.h"
#include "geometry/mesh/stored_normals.h"
#include "geometry/mesh/orientation.h"
#include "geometry/core/polygon.h"
#include "geometry/mesh/repair.h"
#include "printer/profile.h"

namespace host {

// What a column of support costs on this printer, as --orient auto weighs the resting faces
// (geometry/mesh/orientation.h): its body's lines (bead width over the spacing, twice that
// for a grid), its interface (thickness and density) and its contact gaps.
geometry::SupportCost support_cost(const printer::PrinterProfile& machine);

struct ModelOptions {
  std::string path;
  std::string units = "mm";
  double scale = 1.0;
  double height = 0;  // 0: keep the size
  std::string up = "z";
  bool ignore_normals = false;      // accepted and unused: stored normals never decide
  std::vector<std::string> rotate;  // "x:90", "1,1,0:30", ... applied in order after --up
  std::string orient = "none";      // "auto": the resting face needing the least support
  double overhang_angle = 50;       // degrees, for --orient auto (slice: the material's)
  // What support costs, for --orient auto (slice: the printer's; else the stock profile's).
  geometry::SupportCost support_cost = host::support_cost(printer::PrinterProfile{});
};

// --rotate's text as a rotation: AXIS:DEGREES, AXIS x, y, z or a vector "a,b,c"; several
// applied in order (each about the bed's fixed axes). Throws geometry::InputError naming
// the bad one.
geometry::Rotation parse_rotations(const std::vector<std::string>& texts);

// Adds the positional MODEL argument (required) and the placement flags to a subcommand.
void add_model_options(CLI::App& command, ModelOptions& options);
// Adds only the placement flags (--units, --scale, --height, --up, --ignore-normals,
// --rotate, --orient), listed
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
  geometry::ModelFormat format = geometry::ModelFormat::stl;
  std::size_t objects = 1;  // 3MF: the build's objects placed together
  geometry::RepairReport repair;
  std::optional<geometry::StoredNormals> normals;  // STL: its stored normals against the repair
  std::optional<geometry::OrientResult> orientation;  // with --orient auto
  double orient_seconds = 0;
};

// "--orient auto: rests on the face whose normal was (0.00, -1.00, 0.00) (turned 90.0 deg
// about (1.00, 0.00, 0.00)); support ~1234 mm^3 against 5678 mm^3 as given, 30.0 mm tall
// (38 stable faces of 412), 0.41 s".
std::string orientation_text(const LoadedModel& model);
LoadedModel load_model_with_report(const ModelOptions& options, geometry::Vec2 center = {0, 0});

}  // namespace host
