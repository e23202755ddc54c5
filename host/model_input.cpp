// The model options every command shares, and loading a model through them; see model_input.h.
#include "host/model_input.h"

#include <charconv>
#include <cmath>
#include <cstdio>

#include <fmt/core.h>

#include "geometry/core/error.h"
#include "geometry/mesh/placement.h"
#include "geometry/mesh/stl_io.h"

namespace host {
namespace {

// A positive, finite number; CLI11's PositiveNumber lets "inf" through.
CLI::Validator positive_number(const std::string& unit) {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        double value = 0;
        const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
        if (error != std::errc() || end != text.data() + text.size() || !std::isfinite(value) ||
            !(value > 0)) {
          return fmt::format("needs a number greater than 0, not '{}'", text);
        }
        return {};
      },
      unit);
}

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

}  // namespace

void add_model_options(CLI::App& command, ModelOptions& options) {
  command.add_option("MODEL", options.path, "the STL file (ASCII or binary)")->required();
  add_placement_options(command, options);
}

void add_placement_options(CLI::App& command, ModelOptions& options, const std::string& group) {
  std::vector<CLI::Option*> added;
  added.push_back(command.add_option("--units", options.units,
                                     "unit of the file's coordinates, which STL does not record "
                                     "(default: mm)")
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
  added.push_back(command.add_flag("--ignore-normals", options.ignore_normals,
                                   "rebuild the facets' normals from their vertex order instead "
                                   "of refusing a file whose stored normals contradict it (default: off)"));
  if (!group.empty()) {
    for (CLI::Option* option : added) option->group(group);
  }
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
  placement.center = center;

  geometry::StlReadOptions read_options;
  read_options.check_normals = !options.ignore_normals;
  std::vector<geometry::Triangle> facets;
  try {
    facets = geometry::read_stl(options.path, read_options);
  } catch (const geometry::StlNormalsError& e) {
    throw geometry::InputError(
        fmt::format("{}; if its vertex order is right, --ignore-normals rebuilds the normals "
                    "from it",
                    e.what()));
  }
  LoadedModel model;
  geometry::Mesh repaired = geometry::repair(facets, &model.repair);
  geometry::check_printable(model.repair, options.path);

  model.mesh = geometry::place(std::move(repaired), placement);
  return model;
}

geometry::Mesh load_model(const ModelOptions& options, geometry::Vec2 center) {
  LoadedModel model = load_model_with_report(options, center);
  if (model.repair.anything_repaired()) {
    fmt::print(stderr, "mahost: {}: repaired: {}\n", options.path, model.repair.summary());
  }
  return std::move(model.mesh);
}

}  // namespace host
