// The slice pipeline and its options; see slice_pipeline.h.
#include "host/slice_pipeline.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <memory>
#include <mutex>
#include <ostream>
#include <streambuf>

#include <fmt/core.h>
#include <tbb/parallel_for.h>

#include "geometry/contour/contour_strategy.h"
#include "geometry/core/error.h"
#include "geometry/slicing/layer_stack.h"
#include "geometry/mesh/mesh.h"
#include "geometry/plan/flat_levels.h"
#include "geometry/plan/layer_plan.h"
#include "geometry/toolpaths/toolpath_plan.h"
#include "host/layer_boundaries.h"
#include "host/progress.h"
#include "printer/error.h"

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
  options.top_thickness = machine.print.top_thickness;
  options.bottom_thickness = machine.print.bottom_thickness;
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
  CLI::Option* layer = command.add_option("--layer", options.layer,
                                          "layer thickness, mm; one the printer allows "
                                          "(default: the printer profile's layer.default)")
                           ->check(CLI::PositiveNumber);
  added.push_back(layer);
  added.push_back(command
                      .add_option("--boundaries", options.boundaries,
                                  "explicit layer tops instead of --layer: a comma list in mm "
                                  "(0.3,0.5,0.7,...), a file with one top per line (# "
                                  "comments), or a G-code file of CuraEngine, PrusaSlicer, "
                                  "Slic3r or mahost, whose layer heights are used; the first "
                                  "layer must be the printer's first_layer.height, every other "
                                  "one a thickness it allows (default: none)")
                      ->excludes(layer));
  CLI::Option* boundaries = added.back();
  for (CLI::Option* option : add_adaptive_options(command, options.adaptive)) {
    option->excludes(layer)->excludes(boundaries);
    added.push_back(option);
  }
  added.push_back(command.add_option("--contour", options.contour,
                                     fmt::format("the region each layer extrudes: {} (default: best)",
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
      "--layer", "--boundaries", "--adaptive", "--tolerance", "--max-layers", "--contour",
      "--perimeters", "--infill", "--set"};
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
    case SliceStage::planning: return "planning layers";
    case SliceStage::contours: return "contours";
    case SliceStage::toolpaths: return "toolpaths";
    case SliceStage::writing: return "writing";
  }
  return "slicing";
}

LayerChoice plan_layers(const SliceOptions& options, const printer::PrinterProfile& machine,
                        const geometry::LayerStack& index, double part_height,
                        const geometry::ContourStrategy& printed,
                        const PlanningProgress& progress) {
  LayerChoice choice;
  double thickness = 0;  // for the build-height message: the last layer's
  if (!options.boundaries.empty()) {
    // A peer may end a layer or so below the top (rounding it down, or leaving out a tip too
    // small to print): up to the printer's thickest layer is taken, with a note.
    const double thickest = machine.layer.allowed.empty()
                                ? machine.layer.max
                                : *std::max_element(machine.layer.allowed.begin(),
                                                    machine.layer.allowed.end());
    choice.layers = boundary_layers(options.boundaries, part_height, thickest + 1e-6).layers;
    std::vector<double> tops;
    for (const geometry::Layer& layer : choice.layers) tops.push_back(layer.z_hi);
    try {
      printer::check_layer_tops(machine, tops);
    } catch (const printer::ConfigError& e) {
      throw printer::ConfigError(fmt::format("--boundaries {}: {}", options.boundaries, e.what()));
    }
  } else {
    thickness = options.layer > 0 ? options.layer : machine.layer.default_thickness;
    printer::check_layer_thickness(machine, thickness);
    choice = choose_layers(options.adaptive, machine, index, part_height, thickness, printed,
                           progress);
  }
  // The last layer is a whole layer thick, so it can end above the part: refused now rather
  // than when the G-code is checked against the build volume after all the slicing.
  if (!choice.layers.empty()) {
    if (choice.adaptive || thickness == 0) thickness = choice.layers.back().thickness();
    printer::check_layer_tops_fit(machine, part_height, choice.layers.back().z_hi, thickness);
  }
  return choice;
}

namespace {

// The print time of the part sliced in these layers with mid sections (the estimate hardly
// depends on the contour: the bunny's ma and mid estimates differ by 1%), s.
double estimated_seconds(const geometry::LayerStack& index, const std::vector<geometry::Layer>& layers,
                         const printer::Profiles& profiles) {
  const geometry::LayerStack stack(index, layers);
  std::vector<geometry::Region> regions(layers.size());
  tbb::parallel_for(std::size_t{0}, layers.size(), [&](std::size_t i) { regions[i] = stack.mid(i); });
  const auto toolpaths = geometry::plan_toolpaths(regions, layers, toolpath_options(profiles.printer));
  struct Discard : std::streambuf {
    int overflow(int c) override { return c; }
    std::streamsize xsputn(const char*, std::streamsize n) override { return n; }
  } discard;
  std::ostream nowhere(&discard);
  return printer::write_gcode(nowhere, toolpaths, profiles).print_seconds;
}

// The allowed thickness nearest to `wanted`.
double nearest_allowed(const geometry::AllowedThicknesses& allowed, double wanted) {
  if (!allowed.listed.empty()) {
    return *std::min_element(allowed.listed.begin(), allowed.listed.end(), [&](double a, double b) {
      return std::abs(a - wanted) < std::abs(b - wanted);
    });
  }
  double t = std::clamp(wanted, allowed.min, allowed.max);
  if (allowed.step > 0) t = allowed.min + std::round((t - allowed.min) / allowed.step) * allowed.step;
  return std::clamp(t, allowed.min, allowed.max);
}

}  // namespace

SliceResult slice_to_gcode(const SliceOptions& options, const std::string& output,
                           const SliceProgress& progress) {
  auto report = [&](SliceStage stage, std::size_t done, std::size_t total) {
    if (progress) progress(stage, done, total);
  };
  SliceResult result;
  result.profiles = load_slice_profiles(options);
  const printer::PrinterProfile& machine = result.profiles.printer;

  const geometry::ContourStrategy& contour = contour_strategy_option(options.contour, "--contour");
  const bool uniform = options.boundaries.empty();
  result.layer_thickness =
      !uniform ? 0 : options.layer > 0 ? options.layer : machine.layer.default_thickness;
  // A thickness the printer lacks is refused before the model is read.
  if (uniform) printer::check_layer_thickness(machine, result.layer_thickness);

  const geometry::Mesh mesh = load_model(options.model);
  const geometry::Box3 box = geometry::bounding_box(mesh);
  result.part_size = box.max - box.min;
  const geometry::Vec3& size = result.part_size;
  printer::check_part_fits(machine, size.x, size.y, size.z);

  const geometry::LayerStack index(mesh, {});
  report(SliceStage::planning, 0, 0);
  result.choice = plan_layers(options, machine, index, size.z, contour,
                              [&](std::size_t measured) { report(SliceStage::planning, measured, 0); });
  result.layers = result.choice.layers;
  const std::vector<geometry::Layer>& layers = result.layers;
  const std::size_t count = layers.size();
  const geometry::LayerStack stack(index, layers);

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
  // A variable stack's nominal height ({layer_height}, ";Layer height:") is its thinnest
  // layer after the first.
  double nominal = result.layer_thickness;
  if (!uniform) {
    nominal = layers.size() > 1 ? layers[1].thickness() : layers[0].thickness();
    for (std::size_t i = 1; i < layers.size(); ++i) nominal = std::min(nominal, layers[i].thickness());
    nominal = std::round(nominal * 1e6) / 1e6;
  }
  gcode_options.layer_height = nominal;
  gcode_options.notes = {
      fmt::format("model: {} ({:.2f} x {:.2f} x {:.2f} mm)", options.model.path, size.x, size.y,
                  size.z),
      fmt::format("contour: {}", contour.name),
      result.choice.adaptive
          ? fmt::format("layers: {} (adaptive, D within {:g} mm)", describe_layers(layers),
                        result.choice.plan.tolerance)
      : uniform ? fmt::format("layer: {:g} mm, first layer {:g} mm", result.layer_thickness,
                              machine.first_layer_height)
                : fmt::format("layers: {} from --boundaries {}", describe_layers(layers),
                              options.boundaries),
      fmt::format("perimeters: {}, infill: {:g}% {}, top/bottom layers: {}/{}{}",
                  machine.print.perimeters, machine.print.infill_density,
                  machine.print.infill_pattern, machine.print.top_layers,
                  machine.print.bottom_layers,
                  machine.print.top_thickness > 0 || machine.print.bottom_thickness > 0
                      ? fmt::format(", at least {:g}/{:g} mm", machine.print.top_thickness,
                                    machine.print.bottom_thickness)
                      : std::string())};
  report(SliceStage::writing, 0, count);
  result.summary = printer::write_gcode_file(
      output, toolpaths, result.profiles, gcode_options,
      [&](std::size_t done) { report(SliceStage::writing, done, count); });
  if (result.choice.adaptive && count > 1) {
    // What uniform slicing would take: at the thinnest layer, and at about as many layers.
    const geometry::AllowedThicknesses allowed = allowed_thicknesses(machine);
    const auto flats = geometry::flat_levels(mesh);
    const double same_count = nearest_allowed(
        allowed, (layers.back().z_hi - machine.first_layer_height) / static_cast<double>(count - 1));
    for (double t : {allowed.thinnest(), same_count}) {
      if (!result.uniform.empty() && std::abs(result.uniform.back().thickness - t) < 1e-9) continue;
      const auto plan = geometry::uniform_plan(size.z, t, allowed, flats);
      result.uniform.push_back({t, plan.layers.size(),
                                estimated_seconds(index, plan.layers, result.profiles)});
    }
  }
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
    // Planning has no total: the candidate layers measured so far.
    bars->bar->update(done, stage == SliceStage::planning
                                ? fmt::format("{} candidate layers measured", done)
                                : fmt::format("layer {}/{}", done, total));
    if (stage == SliceStage::writing && done == total && total > 0) bars->bar.reset();
  };
}

std::string slice_plan_text(const SliceResult& result) {
  std::string text = describe_choice(result.choice);
  if (!result.uniform.empty()) {
    text += "; estimated ";
    text += printer::format_duration(result.summary.print_seconds);
    for (std::size_t k = 0; k < result.uniform.size(); ++k) {
      const SliceResult::Uniform& u = result.uniform[k];
      text += fmt::format("{} {} at uniform {:g} mm ({} layers)", k == 0 ? " against" : " and",
                          printer::format_duration(u.print_seconds), u.thickness, u.layers);
    }
  }
  return text;
}

std::string slice_summary_text(const SliceResult& result) {
  const printer::GcodeSummary& s = result.summary;
  // A variable stack says its range: "212 layers, 0.15 to 0.4 mm thick, estimated ...".
  const std::string layers = result.layer_thickness > 0 || result.layers.empty()
                                 ? fmt::format("{} layers", s.layers)
                                 : describe_layers(result.layers);
  return fmt::format("{}, estimated print time {}, filament {:.2f} m ({:.1f} g {}), {}",
                     layers, printer::format_duration(s.print_seconds), s.filament_mm / 1000.0,
                     s.filament_grams, result.profiles.material.name, size_text(s.bytes));
}

}  // namespace host
