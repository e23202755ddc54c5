// Loading a model; see model.h.
#include "app/model.h"

#include <algorithm>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdio>

#include <fmt/core.h>

#include "geometry/core/error.h"
#include "geometry/mesh/file_bytes.h"
#include "geometry/mesh/model_io.h"
#include "geometry/mesh/placement.h"
#include "geometry/mesh/stl_io.h"
#include "geometry/mesh/stored_normals.h"

namespace app {

namespace {

// The options are checked on the command line already; these guard other callers.
double units_to_mm(const std::string& units) {
  if (units == "m") return 1000.0;
  if (units == "mm") return 1.0;
  if (units == "in") return 25.4;
  throw geometry::InputError(fmt::format("--units: '{}' is not a unit; use m, mm or in", units));
}

geometry::Axis axis(const std::string& up) {
  if (up == "x") return geometry::Axis::x;
  if (up == "y") return geometry::Axis::y;
  if (up == "z") return geometry::Axis::z;
  throw geometry::InputError(fmt::format("--up: '{}' is not an axis; use x, y or z", up));
}

double parse_number(std::string_view text, bool& ok) {
  while (!text.empty() && text.front() == ' ') text.remove_prefix(1);
  while (!text.empty() && text.back() == ' ') text.remove_suffix(1);
  double value = 0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  ok = ok && !text.empty() && error == std::errc() && end == text.data() + text.size() &&
       std::isfinite(value);
  return value;
}

geometry::Rotation parse_rotation(const std::string& text) {
  const auto bad = [&]() {
    return geometry::InputError(fmt::format(
        "--rotate '{}': needs AXIS:DEGREES, AXIS x, y, z or a vector a,b,c (e.g. x:90, "
        "z:-45, 1,1,0:30)",
        text));
  };
  const std::size_t colon = text.rfind(':');
  if (colon == std::string::npos) throw bad();
  const std::string axis_text = text.substr(0, colon);
  bool ok = true;
  const double degrees = parse_number(std::string_view(text).substr(colon + 1), ok);
  geometry::Vec3 axis;
  if (axis_text == "x" || axis_text == "X") {
    axis = {1, 0, 0};
  } else if (axis_text == "y" || axis_text == "Y") {
    axis = {0, 1, 0};
  } else if (axis_text == "z" || axis_text == "Z") {
    axis = {0, 0, 1};
  } else {
    std::vector<double> parts;
    std::string_view rest = axis_text;
    while (ok) {
      const std::size_t comma = rest.find(',');
      parts.push_back(parse_number(rest.substr(0, comma), ok));
      if (comma == std::string_view::npos) break;
      rest.remove_prefix(comma + 1);
    }
    ok = ok && parts.size() == 3;
    if (ok) axis = {parts[0], parts[1], parts[2]};
    ok = ok && geometry::dot(axis, axis) > 0;
  }
  if (!ok) throw bad();
  return geometry::rotation_about(axis, degrees);
}

}  // namespace

geometry::Rotation parse_rotations(const std::vector<std::string>& texts) {
  geometry::Rotation total;
  for (const std::string& text : texts) total = parse_rotation(text) * total;
  return total;
}

std::string orientation_text(const LoadedModel& model) {
  if (!model.orientation) return {};
  const geometry::OrientResult& o = *model.orientation;
  const geometry::AxisAngle turn = geometry::axis_angle(o.chosen.rotation);
  const std::string how =
      turn.degrees < 1e-6
          ? std::string("kept as given")
          : fmt::format("turned {:.1f} deg about ({:.2f}, {:.2f}, {:.2f})", turn.degrees,
                        turn.axis.x, turn.axis.y, turn.axis.z);
  return fmt::format(
      "--orient auto: resting on the face whose outward normal was ({:.2f}, {:.2f}, {:.2f}), "
      "{}; support material ~{:.0f} mm^3 against {:.0f} mm^3 as given, {:.1f} mm tall "
      "against {:.1f} mm ({} stable faces of {} on the hull), {:.2f} s",
      o.chosen.down.x, o.chosen.down.y, o.chosen.down.z, how, o.chosen.support_volume,
      o.input.support_volume, o.chosen.height, o.input.height, o.stable_faces, o.hull_faces,
      model.orient_seconds);
}

LoadedModel load_model(const ModelOptions& options, geometry::Vec2 center) {
  if (!(options.scale > 0) || !std::isfinite(options.scale)) {
    throw geometry::InputError(
        fmt::format("--scale: needs a number greater than 0, not {}", options.scale));
  }
  if (options.height < 0 || !std::isfinite(options.height)) {
    throw geometry::InputError(
        fmt::format("--height: needs a number greater than 0, not {}", options.height));
  }
  geometry::Placement placement;
  placement.units_to_mm = units_to_mm(options.units);
  placement.scale = options.scale;
  if (options.height > 0) placement.height = options.height;
  placement.up = axis(options.up);
  placement.rotation = parse_rotations(options.rotate);
  placement.center = center;

  geometry::ModelFile file = geometry::read_model(options.path);
  if (file.units_recorded) {
    if (options.units != "mm") {
      throw geometry::InputError(fmt::format(
          "--units {}: {} is {}, which records its unit; --units is for STL and OBJ files, "
          "which do not (scale with --scale or --height)",
          options.units, options.path, geometry::format_name(file.format)));
    }
    placement.units_to_mm = 1;  // the reader gave mm
  }
  LoadedModel model;
  model.format = file.format;
  model.objects = file.objects;
  geometry::Mesh repaired = geometry::repair(file.triangles, &model.repair);
  geometry::check_printable(model.repair, options.path);
  if (!file.stored_normals.empty()) {
    model.normals = geometry::compare_stored_normals(file.triangles, file.stored_normals, repaired);
  }

  model.mesh = geometry::place(std::move(repaired), placement);
  if (options.orient == "auto") {
    // Turned from where --up and --rotate put it, at the size they gave it (a --height is
    // the part's as given), then placed again.
    const auto start = std::chrono::steady_clock::now();
    geometry::OrientOptions orient;
    orient.overhang_angle = options.overhang_angle;
    orient.cost = options.support_cost;
    model.orientation = geometry::orient_for_least_support(model.mesh, orient);
    geometry::Placement again;
    again.rotation = model.orientation->chosen.rotation;
    again.center = center;
    model.mesh = geometry::place(std::move(model.mesh), again);
    model.orient_seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  return model;
}

ModelFigures model_figures(const LoadedModel& model, double overhang_angle) {
  ModelFigures figures;
  figures.format = std::string(geometry::format_name(model.format));
  if (model.format == geometry::ModelFormat::threemf) {
    figures.format += model.objects == 1 ? std::string(", 1 object")
                                         : fmt::format(", {} objects placed together", model.objects);
  }
  figures.triangles = model.mesh.faces.size();
  figures.vertices = model.mesh.vertices.size();
  figures.box = geometry::bounding_box(model.mesh);
  figures.volume = geometry::signed_volume(model.mesh);
  figures.surface_area = geometry::surface_area(model.mesh);
  figures.support_volume = geometry::support_volume_estimate(model.mesh, overhang_angle);
  return figures;
}

void export_stl(const LoadedModel& model, const std::string& path) {
  geometry::write_stl_binary(path, model.mesh);
}

void check_model_file(const std::string& path, const std::string& name) {
  geometry::read_model_bytes(geometry::read_file_bytes(path), name);
}

std::vector<std::string> model_notes(const ModelOptions& options, const LoadedModel& model) {
  std::vector<std::string> notes;
  if (model.repair.anything_repaired()) {
    notes.push_back(fmt::format("{}: repaired: {}", options.path, model.repair.summary()));
  }
  if (model.orientation) notes.push_back(fmt::format("{}: {}", options.path, orientation_text(model)));
  return notes;
}

}  // namespace app
