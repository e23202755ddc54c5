// The slice pipeline; see slice.h.
#include "app/slice.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <optional>

#include <fmt/core.h>
#include <tbb/parallel_for.h>
#include <tbb/task_group.h>

#include "app/layer_boundaries.h"
#include "app/stage_options.h"
#include "app/uniform_estimate.h"
#include "geometry/contour/contour_strategy.h"
#include "geometry/core/error.h"
#include "geometry/mesh/mesh.h"
#include "geometry/plan/flat_levels.h"
#include "geometry/plan/layer_plan.h"
#include "geometry/slicing/layer_stack.h"
#include "geometry/support/support_plan.h"
#include "geometry/toolpaths/toolpath_plan.h"
#include "printer/error.h"

namespace app {

namespace {

std::string size_text(std::size_t bytes) {
  if (bytes >= (1u << 20)) return fmt::format("{:.1f} MiB", bytes / 1048576.0);
  if (bytes >= 1024) return fmt::format("{:.1f} KiB", bytes / 1024.0);
  return fmt::format("{} bytes", bytes);
}

}  // namespace

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
    case SliceStage::supports: return "supports";
    case SliceStage::toolpaths: return "toolpaths";
    case SliceStage::writing: return "writing";
  }
  return "slicing";
}

LayerChoice plan_layers(const SliceOptions& options, const printer::Profiles& profiles,
                        const geometry::LayerStack& index, double part_height,
                        const geometry::ContourStrategy& printed,
                        const PlanningProgress& progress, const PrintEstimate& estimate) {
  const printer::PrinterProfile& machine = profiles.printer;
  const geometry::SupportOptions supports = support_options(profiles);
  LayerChoice choice;
  double thickness = 0;  // for the build-height message: the last layer's
  if (!options.boundaries.empty()) {
    // A peer may end a layer or so below the top (rounding it down, or leaving out a tip too
    // small to print): up to the printer's thickest layer is taken, with a note.
    const double thickest = machine.layer.allowed.empty()
                                ? machine.layer.max
                                : *std::max_element(machine.layer.allowed.begin(),
                                                    machine.layer.allowed.end());
    BoundaryLayers boundaries = boundary_layers(options.boundaries, part_height, thickest + 1e-6);
    choice.layers = std::move(boundaries.layers);
    choice.notes = std::move(boundaries.notes);
    std::vector<double> tops;
    for (const geometry::Layer& layer : choice.layers) tops.push_back(layer.z_hi);
    try {
      printer::check_layer_tops(machine, tops);
    } catch (const printer::ConfigError& e) {
      throw printer::ConfigError(fmt::format("--boundaries {}: {}", options.boundaries, e.what()));
    }
  } else {
    thickness = uniform_thickness(options, machine);
    printer::check_layer_thickness(machine, thickness);
    AdaptiveRequest request = options.adaptive;
    if (supports.placement != geometry::SupportPlacement::none) {
      request.thick_overhangs = {supports.overhang_angle, supports.bead_width, supports.min_area};
    }
    choice = choose_layers(request, machine, index, part_height, thickness, printed, progress,
                           estimate);
  }
  // The last layer is a whole layer thick, so it can end above the part: refused now rather
  // than when the G-code is checked against the build volume after all the slicing.
  if (!choice.layers.empty()) {
    if (choice.adaptive || thickness == 0) thickness = choice.layers.back().thickness();
    printer::check_layer_tops_fit(machine, part_height, choice.layers.back().z_hi, thickness,
                                  raft_height(machine.raft));
  }
  return choice;
}

namespace {

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

// The G-code's layer height and the header's notes: the model, the contour, the layers, walls
// and infill, and the supports, raft and brim where there are any.
printer::GcodeOptions gcode_options_for(const SliceOptions& options, const SliceResult& result,
                                        const geometry::ContourStrategy& contour,
                                        const geometry::SupportPlan& plan) {
  const printer::PrinterProfile& machine = result.profiles.printer;
  const std::vector<geometry::Layer>& layers = result.layers;
  const geometry::Vec3& size = result.part_size;
  const bool uniform = options.boundaries.empty();
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
  gcode_options.input_filename_base = std::filesystem::path(options.model.path).stem().string();
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
  // Only with supports on: a part without them has no support line in its header.
  if (support_options(result.profiles).placement != geometry::SupportPlacement::none) {
    const printer::SupportSettings& s = machine.support;
    gcode_options.notes.push_back(fmt::format(
        "support: {}, overhang {:g} deg, xy gap {:g} mm, top/bottom contact {:g}/{:g} mm, "
        "interface {:g} mm, {} {:g} mm; bridges up to {:g} mm ({} laid)",
        s.type, result.profiles.material.overhang_angle, s.xy_gap, s.top_contact_distance,
        s.bottom_contact_distance, s.interface_thickness, s.pattern, s.spacing,
        result.profiles.material.bridge_length, result.bridges));
  }
  if (!plan.raft.empty()) {
    gcode_options.notes.push_back(fmt::format(
        "raft: {} layers, {:.2f} mm under the part (air gap {:g} mm), margin {:g} mm",
        plan.raft.size(), plan.lift, machine.raft.air_gap, machine.raft.margin));
  }
  if (machine.brim_width > 0) gcode_options.notes.push_back(fmt::format("brim: {:g} mm", machine.brim_width));
  return gcode_options;
}

}  // namespace

SliceResult slice(const SliceOptions& options, const std::string& output,
                  const SliceEvents& events) {
  auto report = [&](SliceStage stage, std::size_t done, std::size_t total) {
    if (events.cancelled && events.cancelled()) throw SliceCancelled();
    if (events.progress) events.progress(stage, done, total);
  };
  SliceResult result;
  auto warn = [&](const std::string& line) {
    result.warnings.push_back(line);
    if (events.warning) events.warning(line);
  };
  result.profiles = load_slice_profiles(options);
  const printer::PrinterProfile& machine = result.profiles.printer;

  const geometry::ContourStrategy& contour = contour_strategy_option(options.contour, "--contour");
  const bool uniform = options.boundaries.empty();
  result.layer_thickness = uniform ? uniform_thickness(options, machine) : 0;
  // A thickness the printer lacks is refused before the model is read.
  if (uniform) printer::check_layer_thickness(machine, result.layer_thickness);

  ModelOptions model = options.model;
  model.overhang_angle = result.profiles.material.overhang_angle;  // for --orient auto
  model.support_cost = support_cost(machine);
  LoadedModel loaded = load_model(model);
  for (const std::string& line : model_notes(model, loaded)) warn(line);
  result.repair = loaded.repair;
  const geometry::Mesh mesh = std::move(loaded.mesh);
  const geometry::Box3 box = geometry::bounding_box(mesh);
  result.part_size = box.max - box.min;
  const geometry::Vec3& size = result.part_size;
  printer::check_part_fits(machine, size.x, size.y, size.z);

  const geometry::LayerStack index(mesh, {});
  // The plan line compares an adaptive plan with uniform slicing at the thinnest layer and at
  // about as many layers (uniform_estimate.h): a sample of each is timed beside the work, the
  // first beside the planning, whose rounds of measurements leave cores idle, the second
  // beside what follows the plan; the plan's own program fills in the rest at the end.
  const geometry::AllowedThicknesses allowed = allowed_thicknesses(machine);
  const bool adaptive = options.adaptive.wanted();
  const std::vector<geometry::FlatLevel> flats =
      adaptive ? geometry::flat_levels(mesh) : std::vector<geometry::FlatLevel>{};
  using Sampled = std::pair<double, LayerSample>;  // the thickness, the sample
  const auto sample_uniform = [&](double t) {
    return Sampled{t, sample_layers(index, geometry::uniform_plan(size.z, t, allowed, flats).layers,
                                    result.profiles)};
  };
  // The samples, the thinnest and the one at about the plan's count: declared before the
  // guard that joins the tasks writing into them, so they outlive those tasks on every way out.
  std::optional<Sampled> thinnest, same_count;
  tbb::task_group beside;
  // Joined on every way out: a failed slice does not leave the estimate running.
  struct Joined {
    tbb::task_group& group;
    ~Joined() {
      group.cancel();
      try {
        group.wait();
      } catch (...) {
      }
    }
  } joined{beside};
  if (adaptive) beside.run([&] { thinnest = sample_uniform(allowed.thinnest()); });
  report(SliceStage::planning, 0, 0);
  result.choice = plan_layers(
      options, result.profiles, index, size.z, contour,
      [&](std::size_t measured) { report(SliceStage::planning, measured, 0); },
      [&](const std::vector<geometry::Layer>& layers) {
        return estimated_seconds(index, layers, result.profiles);
      });
  for (const std::string& line : result.choice.notes) warn(line);
  result.layers = result.choice.layers;
  const std::vector<geometry::Layer>& layers = result.layers;
  const std::size_t count = layers.size();
  const geometry::LayerStack stack(index, layers);
  // The second, at about the plan's count, beside the contours, toolpaths and writing.
  if (result.choice.adaptive && count > 1) {
    const double t = nearest_allowed(
        allowed, (layers.back().z_hi - machine.first_layer_height) / static_cast<double>(count - 1));
    if (std::abs(t - allowed.thinnest()) > 1e-9) beside.run([&, t] { same_count = sample_uniform(t); });
  }

  std::vector<geometry::Region> regions(count);
  report(SliceStage::contours, 0, count);
  std::atomic<std::size_t> contours_done{0};
  // A plan by mid's D has measured it on every layer: a strategy that compares mid (best)
  // takes it from there.
  const std::vector<double>& planned = result.choice.plan.distance;
  const bool mid_measured =
      result.choice.adaptive && result.choice.planned_by == "mid" && planned.size() == count;
  tbb::parallel_for(std::size_t{0}, count, [&](std::size_t i) {
    regions[i] = geometry::layer_contour(stack, i, contour, {},
                                         mid_measured ? planned[i] : std::nan(""));
    report(SliceStage::contours, ++contours_done, count);
  });

  // Supports, bridges and the raft, under the regions the layers really print.
  report(SliceStage::supports, 0, count);
  const auto support_start = std::chrono::steady_clock::now();
  const geometry::SupportOptions support = support_options(result.profiles);
  const geometry::SupportPlan plan =
      geometry::plan_supports(regions, layers, support, raft_options(machine));
  result.support_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - support_start).count();
  for (const geometry::LayerSupport& layer : plan.layers) result.bridges += layer.bridges.size();
  report(SliceStage::supports, count, count);

  report(SliceStage::toolpaths, 0, count);
  const std::vector<geometry::LayerToolpaths> toolpaths = geometry::plan_toolpaths(
      regions, layers, toolpath_options(machine), plan,
      [&](std::size_t done) { report(SliceStage::toolpaths, done, count); });
  regions.clear();
  regions.shrink_to_fit();

  const printer::GcodeOptions gcode_options = gcode_options_for(options, result, contour, plan);
  report(SliceStage::writing, 0, count);
  result.summary = printer::write_gcode_file(
      output, toolpaths, result.profiles, gcode_options,
      [&](std::size_t done) { report(SliceStage::writing, done, count); });
  beside.wait();
  if (result.choice.adaptive && count > 1) {
    // What uniform slicing would take: at the thinnest layer, and at about as many layers.
    for (const std::optional<Sampled>* sampled : {&thinnest, &same_count}) {
      if (!*sampled) continue;
      const auto& [t, sample] = **sampled;
      result.uniform.push_back({t, sample.layers.size(), uniform_seconds(sample, layers, result.summary)});
    }
  }
  return result;
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
  // A variable stack says its range: "212 layers, 0.15 to 0.4 mm thick, estimated ...", and
  // a raft under it its layers.
  // The part's layers; the raft's, when there is one, after them.
  const std::size_t raft = !result.layers.empty() && s.layers > result.layers.size()
                               ? s.layers - result.layers.size()
                               : 0;
  std::string layers = result.layer_thickness > 0 || result.layers.empty()
                           ? fmt::format("{} layer{}", s.layers - raft, s.layers - raft == 1 ? "" : "s")
                           : describe_layers(result.layers);
  if (raft > 0) layers += fmt::format(", on {} raft layers", raft);
  const std::string support =
      s.support_filament_mm > 0
          ? fmt::format("; {:.2f} m of it support and raft", s.support_filament_mm / 1000.0)
          : "";
  return fmt::format("{}, estimated print time {}, filament {:.2f} m ({:.1f} g {}{}), {}",
                     layers, printer::format_duration(s.print_seconds), s.filament_mm / 1000.0,
                     s.filament_grams, result.profiles.material.name, support, size_text(s.bytes));
}

}  // namespace app
