// The slice pipeline and its options; see slice_pipeline.h.
#include "host/slice_pipeline.h"

#include <atomic>
#include <memory>
#include <mutex>

#include <fmt/core.h>
#include <tbb/parallel_for.h>

#include "geometry/contour/contour_strategy.h"
#include "geometry/core/error.h"
#include "geometry/slicing/layer_stack.h"
#include "geometry/mesh/mesh.h"
#include "geometry/toolpaths/toolpath_plan.h"
#include "host/progress.h"

namespace host {
namespace {

std::string size_text(std::size_t bytes) {
  if (bytes >= (1u << 20)) return fmt::format("{:.1f} MiB", bytes / 1048576.0);
  if (bytes >= 1024) return fmt::format("{:.1f} KiB", bytes / 1024.0);
  return fmt::format("{} bytes", bytes);
}

geometry::ToolpathOptions toolpath_options(const printer::PrinterProfile& machine) {
  geometry::ToolpathOptions options;
  options.extrusion_width = machine.extrusion_width;
  options.first_layer_width = machine.first_layer_width;
  options.perimeters = machine.print.perimeters;
  options.infill_density = machine.print.infill_density;
  // The profile's values were checked on load; the fallbacks are never taken.
  options.infill_pattern = geometry::parse_infill_pattern(machine.print.infill_pattern)
                               .value_or(geometry::InfillPattern::grid);
  options.top_layers = machine.print.top_layers;
  options.bottom_layers = machine.print.bottom_layers;
  options.skirt_loops = machine.print.skirt_loops;
  options.skirt_distance = machine.print.skirt_distance;
  options.retract_min_travel = machine.retraction.min_travel;
  options.seam = geometry::parse_seam_position(machine.print.seam)
                     .value_or(geometry::SeamPosition::aligned);
  return options;
}

}  // namespace

void add_slice_options(CLI::App& command, SliceOptions& options, const std::string& group) {
  add_placement_options(command, options.model, group);
  std::vector<CLI::Option*> added;
  added.push_back(command.add_option(
      "--printer", options.printer,
      "printer profile: a name in the config directory (up-plus-2, generic-marlin) or a path "
      "to a .toml file (default: up-plus-2)"));
  added.push_back(command.add_option(
      "--material", options.material,
      "material profile: a name (abs, pla) or a path to a .toml file (default: the printer "
      "profile's material)"));
  added.push_back(command.add_option("--layer", options.layer,
                                     "layer thickness, mm; one the printer allows (default: "
                                     "the printer profile's layer.default)")
                      ->check(CLI::PositiveNumber));
  added.push_back(command.add_option("--contour", options.contour,
                                     fmt::format("the region each layer extrudes: {} (default: ma)",
                                                 contour_strategies_help()))
                      ->check(CLI::IsMember(contour_strategy_names())));
  added.push_back(command.add_option("--perimeters", options.perimeters,
                                     "wall loops (default: the printer profile's "
                                     "print.perimeters)")
                      ->check(CLI::Range(0, 50)));
  added.push_back(command.add_option("--infill", options.infill,
                                     "sparse infill density, percent (default: the printer "
                                     "profile's print.infill_density)")
                      ->check(CLI::Range(0.0, 100.0)));
  added.push_back(command
                      .add_option("--set", options.overrides,
                                  "override a profile key, e.g. --set retraction.length=1.5 or "
                                  "--set material.temperature.nozzle=250 (repeatable; default: "
                                  "none)")
                      // one key=value per --set: a model path after it stays the model
                      ->allow_extra_args(false));
  if (!group.empty()) {
    for (CLI::Option* option : added) option->group(group);
  }
}

const std::vector<std::string>& model_only_slice_options() {
  static const std::vector<std::string> names{
      "--units", "--scale",      "--height", "--up",  "--ignore-normals", "--material",
      "--layer", "--contour", "--perimeters", "--infill", "--set"};
  return names;
}

printer::Profiles load_slice_profiles(const SliceOptions& options) {
  printer::ProfileRequest request;
  request.printer = options.printer;
  request.material = options.material;
  request.config_dir = printer::config_directory(MAHOST_CONFIG_DIR);
  request.overrides = options.overrides;
  printer::Profiles profiles = printer::load_profiles(request);
  if (options.perimeters >= 0) profiles.printer.print.perimeters = options.perimeters;
  if (options.infill >= 0) profiles.printer.print.infill_density = options.infill;
  return profiles;
}

std::vector<std::string> contour_strategy_names() {
  std::vector<std::string> names;
  for (const geometry::ContourStrategy& strategy : geometry::contour_strategies()) {
    names.emplace_back(strategy.name);
  }
  return names;
}

std::string contour_strategies_help() {
  std::string text;
  for (const geometry::ContourStrategy& strategy : geometry::contour_strategies()) {
    if (!text.empty()) text += ", ";
    text += fmt::format("{} ({})", strategy.name, strategy.description);
  }
  return text;
}

const geometry::ContourStrategy& contour_strategy_option(const std::string& name,
                                                         const std::string& flag) {
  const geometry::ContourStrategy* strategy = geometry::find_contour_strategy(name);
  if (!strategy) {
    throw geometry::InputError(fmt::format("{}: unknown contour strategy '{}' (use {})", flag,
                                           name, geometry::contour_names()));
  }
  return *strategy;
}

std::string_view stage_name(SliceStage stage) {
  switch (stage) {
    case SliceStage::contours: return "contours";
    case SliceStage::toolpaths: return "toolpaths";
    case SliceStage::writing: return "writing";
  }
  return "slicing";
}

SliceResult slice_to_gcode(const SliceOptions& options, const std::string& output,
                           const SliceProgress& progress) {
  auto report = [&](SliceStage stage, std::size_t done, std::size_t total) {
    if (progress) progress(stage, done, total);
  };
  SliceResult result;
  result.profiles = load_slice_profiles(options);
  const printer::PrinterProfile& machine = result.profiles.printer;

  const geometry::ContourStrategy& contour = contour_strategy_option(options.contour, "--contour");
  result.layer_thickness = options.layer > 0 ? options.layer : machine.layer.default_thickness;
  printer::check_layer_thickness(machine, result.layer_thickness);

  const geometry::Mesh mesh = load_model(options.model);
  const geometry::Box3 box = geometry::bounding_box(mesh);
  result.part_size = box.max - box.min;
  const geometry::Vec3& size = result.part_size;
  printer::check_part_fits(machine, size.x, size.y, size.z);

  const std::vector<geometry::Layer> layers =
      geometry::uniform_layers(size.z, result.layer_thickness, machine.first_layer_height);
  // The last layer is a whole layer thick, so it can end above the part: refused now rather
  // than when the G-code is checked against the build volume after all the slicing.
  if (!layers.empty()) {
    printer::check_layer_tops_fit(machine, size.z, layers.back().z_hi, result.layer_thickness);
  }
  const std::size_t count = layers.size();
  const geometry::LayerStack stack(mesh, layers);

  std::vector<geometry::Region> regions(count);
  report(SliceStage::contours, 0, count);
  std::atomic<std::size_t> contours_done{0};
  tbb::parallel_for(std::size_t{0}, count, [&](std::size_t i) {
    regions[i] = geometry::layer_contour(stack, i, contour);
    report(SliceStage::contours, ++contours_done, count);
  });

  report(SliceStage::toolpaths, 0, count);
  const std::vector<geometry::LayerToolpaths> toolpaths = geometry::plan_toolpaths(
      regions, layers, toolpath_options(machine),
      [&](std::size_t done) { report(SliceStage::toolpaths, done, count); });
  regions.clear();
  regions.shrink_to_fit();

  printer::GcodeOptions gcode_options;
  gcode_options.layer_height = result.layer_thickness;
  gcode_options.notes = {
      fmt::format("model: {} ({:.2f} x {:.2f} x {:.2f} mm)", options.model.path, size.x, size.y,
                  size.z),
      fmt::format("contour: {}", contour.name),
      fmt::format("layer: {:g} mm, first layer {:g} mm", result.layer_thickness,
                  machine.first_layer_height),
      fmt::format("perimeters: {}, infill: {:g}% {}, top/bottom layers: {}/{}",
                  machine.print.perimeters, machine.print.infill_density,
                  machine.print.infill_pattern, machine.print.top_layers,
                  machine.print.bottom_layers)};
  report(SliceStage::writing, 0, count);
  result.summary = printer::write_gcode_file(
      output, toolpaths, result.profiles, gcode_options,
      [&](std::size_t done) { report(SliceStage::writing, done, count); });
  return result;
}

SliceProgress slice_progress_bars(const std::string& contour) {
  // One bar at a time: a stage's first call (done = 0, on the calling thread) replaces the
  // previous stage's bar, which clears its line.
  struct Bars {
    std::mutex mutex;
    std::unique_ptr<Progress> bar;
    SliceStage stage = SliceStage::contours;
  };
  auto bars = std::make_shared<Bars>();
  return [bars, contour](SliceStage stage, std::size_t done, std::size_t total) {
    std::lock_guard lock(bars->mutex);
    if (!bars->bar || stage != bars->stage) {
      bars->bar.reset();
      const std::string label = stage == SliceStage::contours
                                    ? fmt::format("contours ({})", contour)
                                    : std::string(stage_name(stage));
      bars->bar = std::make_unique<Progress>(label, total);
      bars->stage = stage;
    }
    bars->bar->update(done, fmt::format("layer {}/{}", done, total));
    if (stage == SliceStage::writing && done == total && total > 0) bars->bar.reset();
  };
}

std::string slice_summary_text(const SliceResult& result) {
  const printer::GcodeSummary& s = result.summary;
  return fmt::format("{} layers, estimated print time {}, filament {:.2f} m ({:.1f} g {}), {}",
                     s.layers, printer::format_duration(s.print_seconds), s.filament_mm / 1000.0,
                     s.filament_grams, result.profiles.material.name, size_text(s.bytes));
}

}  // namespace host
