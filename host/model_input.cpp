// The model options every command shares, and loading a model through them; see model_input.h.
#include "host/model_input.h"

#include <algorithm>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdio>

#include <fmt/core.h>

#include "geometry/core/error.h"
#include "geometry/mesh/model_io.h"
#include "geometry/mesh/placement.h"
#include "geometry/mesh/stored_normals.h"
#include "host/cli_checks.h"

namespace host {

geometry::SupportCost support_cost(const printer::PrinterProfile& machine) {
  const printer::SupportSettings& s = machine.support;
  geometry::SupportCost cost;
  const double sets = s.pattern == "grid" ? 2 : 1;
  cost.body_share = s.spacing > 0 ? std::min(1.0, sets * machine.extrusion_width / s.spacing) : 1;
  cost.interface_share = std::clamp(s.interface_density / 100, 0.0, 1.0);
  cost.interface_thickness = s.interface_thickness;
  cost.top_gap = s.top_contact_distance;
  cost.bottom_gap = s.bottom_contact_distance;
  return cost;
}

namespace {

CLI::Validator one_of(std::vector<std::string> choices, const std::string& what) {
  std::string list;
  for (const std::string& c : choices) list += (list.empty() ? "" : "|") + c;
  return CLI::Validator(
      [choices, list, what](std::string& text) -> std::string {
        for (const std::string& c : choices) {
          if (text == c) return {};
        }
        return fmt::format("'{}' is not {}; use one of {}", text, what, list);
      },
      list);
}

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

void add_model_options(CLI::App& command, ModelOptions& options) {
  command.add_option("MODEL", options.path,
                     "the model: STL (ASCII or binary), 3MF (every object of its build, placed "
                     "together) or OBJ")
      ->required();
  add_placement_options(command, options);
}

void add_placement_options(CLI::App& command, ModelOptions& options, const std::string& group) {
  std::vector<CLI::Option*> added;
  added.push_back(command.add_option("--units", options.units,
                                     "unit of the file's coordinates, which STL and OBJ do not "
                                     "record (3MF does) (default: mm)")
                      ->check(one_of({"m", "mm", "in"}, "a unit")));
  auto* scale = command.add_option("--scale", options.scale,
                                   "scale factor, applied after --units (default: 1)")
                    ->check(positive_number("F > 0"));
  added.push_back(scale);
  added.push_back(command.add_option("--height", options.height,
                                     "scale uniformly so the part is MM tall, mm (default: "
                                     "the file's size)")
                      ->check(positive_number("MM > 0"))
                      ->excludes(scale));
  added.push_back(command.add_option("--up", options.up,
                                     "the model's axis that points up on the bed (default: z)")
                      ->check(one_of({"x", "y", "z"}, "an axis")));
  added.push_back(command.add_option("--rotate", options.rotate,
                                     "turn the model by DEGREES about an AXIS (x, y, z or a "
                                     "vector a,b,c) after --up, e.g. --rotate x:90 or --rotate "
                                     "1,1,0:30; repeatable, applied in order (default: none)")
                      ->allow_extra_args(false));
  added.push_back(command.add_option("--orient", options.orient,
                                     "auto: rest the model on the face of its convex hull that "
                                     "needs the least support (then the lowest), after --up and "
                                     "--rotate (default: none, as given)")
                      ->check(one_of({"none", "auto"}, "an orientation")));
  if (!group.empty()) {
    for (CLI::Option* option : added) option->group(group);
  }
  // Accepted, and not listed, for the scripts of earlier versions, which refused an STL whose
  // stored normals disagreed with its vertex order unless given this: stored normals are
  // never used now (geometry/mesh/stl_io.h).
  command.add_flag("--ignore-normals", options.ignore_normals)->group("");
}

LoadedModel load_model_with_report(const ModelOptions& options, geometry::Vec2 center) {
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

geometry::Mesh load_model(const ModelOptions& options, geometry::Vec2 center) {
  LoadedModel model = load_model_with_report(options, center);
  if (model.repair.anything_repaired()) {
    fmt::print(stderr, "mahost: {}: repaired: {}\n", options.path, model.repair.summary());
  }
  if (model.orientation) fmt::print(stderr, "mahost: {}: {}\n", options.path, orientation_text(model));
  return std::move(model.mesh);
}

}  // namespace host
