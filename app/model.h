// A model as every command takes it (the file: STL, 3MF or OBJ; its units, scale, height, up
// axis, rotations, orientation) and loading it: read, repair, place. What every later stage
// slices. The options' flags and checks are in app/slice_options.h's table.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "geometry/mesh/mesh.h"
#include "geometry/mesh/model_io.h"
#include "geometry/mesh/orientation.h"
#include "geometry/core/polygon.h"
#include "geometry/mesh/repair.h"
#include "geometry/mesh/stored_normals.h"
#include "app/stage_options.h"

namespace app {

struct ModelOptions {
  std::string path;  // STL, 3MF or OBJ
  std::string units = "mm";
  double scale = 1.0;
  double height = 0;  // 0: keep the size
  std::string up = "z";
  bool ignore_normals = false;      // accepted and unused: stored normals never decide
  std::vector<std::string> rotate;  // "x:90", "1,1,0:30", ... applied in order after --up
  std::string orient = "none";      // "auto": the resting face needing the least support
  double overhang_angle = 50;       // degrees, for --orient auto (slice: the material's)
  // What support costs, for --orient auto (slice: the printer's; else the stock profile's).
  geometry::SupportCost support_cost = app::support_cost(printer::PrinterProfile{});
};

// --rotate's text as a rotation: AXIS:DEGREES, AXIS x, y, z or a vector "a,b,c"; several
// applied in order (each about the bed's fixed axes). Throws geometry::InputError naming
// the bad one.
geometry::Rotation parse_rotations(const std::vector<std::string>& texts);

// A model read, repaired and placed, with what the repair did (in file units) and what
// --orient auto chose.
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

// Whether a file name is a model's: .stl, .3mf or .obj, in any case.
using geometry::is_model_name;

// Reads the file at `path` as the model `name` says it is (an .obj as OBJ) and keeps nothing: a
// check that an upload can be sliced. Throws geometry::InputError, naming `name` where the
// content is at fault.
void check_model_file(const std::string& path, const std::string& name);

// Reads, repairs and places the model, centred on `center`. Throws geometry::InputError with a
// one-line reason for a file that cannot be used.
LoadedModel load_model(const ModelOptions& options, geometry::Vec2 center = {0, 0});

// What `mahost info` reports of a loaded model besides its repair report and stored normals.
struct ModelFigures {
  std::string format;         // "STL", "3MF, 1 object", "3MF, 2 objects placed together"
  std::size_t triangles = 0;  // after repair
  std::size_t vertices = 0;
  geometry::Box3 box;         // the placed part's, mm
  double volume = 0;          // mm^3
  double surface_area = 0;    // mm^2
  // mm^3 of support under the walls leaning past `overhang_angle` degrees from vertical, in
  // columns to the bed or the part below (support_volume_estimate, orientation.h).
  double support_volume = 0;
};
ModelFigures model_figures(const LoadedModel& model, double overhang_angle);

// Writes the placed, repaired mesh to `path` as binary STL, mm.
void export_stl(const LoadedModel& model, const std::string& path);

// What loading did that a user should hear of, one line each (none when nothing was repaired
// or turned): "FILE: repaired: ...", "FILE: --orient auto: ...".
std::vector<std::string> model_notes(const ModelOptions& options, const LoadedModel& model);

}  // namespace app
