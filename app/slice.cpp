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

// What slice() tells its caller as it goes: progress (which also asks whether to stop) and
// the lines a user should read, kept in the result as well.
struct SliceReporter {
  const SliceEvents& events;
  SliceResult& result;

  void progress(SliceStage stage, std::size_t done, std::size_t total) const {
    if (events.cancelled && events.cancelled()) throw SliceCancelled();
    if (events.progress) events.progress(stage, done, total);
  }
  void warn(const std::string& line) const {
    result.warnings.push_back(line);
    if (events.warning) events.warning(line);
  }
};

// The uniform thickness: one the printer lacks is refused before the model is read.
void check_uniform_thickness(const SliceOptions& options, SliceResult& result) {
  const printer::PrinterProfile& machine = result.profiles.printer;
  const bool uniform = options.boundaries.empty();
  result.layer_thickness = uniform ? uniform_thickness(options, machine) : 0;
  if (uniform) printer::check_layer_thickness(machine, result.layer_thickness);
}

// The placed, repaired part, checked against the build volume.
geometry::Mesh load_part(const SliceOptions& options, SliceResult& result,
                         const SliceReporter& reporter) {
  const printer::PrinterProfile& machine = result.profiles.printer;
  ModelOptions model = options.model;
  model.overhang_angle = result.profiles.material.overhang_angle;  // for --orient auto
  model.support_cost = support_cost(machine);
  LoadedModel loaded = load_model(model);
  for (const std::string& line : model_notes(model, loaded)) reporter.warn(line);
  result.repair = loaded.repair;
  const geometry::Box3 box = geometry::bounding_box(loaded.mesh);
  result.part_size = box.max - box.min;
  const geometry::Vec3& size = result.part_size;
  printer::check_part_fits(machine, size.x, size.y, size.z);
  return std::move(loaded.mesh);
}

// The plan line compares an adaptive plan with uniform slicing at the thinnest layer and at
// about as many layers (uniform_estimate.h): a sample of each is timed beside the work, the
// first beside the planning, whose rounds of measurements leave cores idle, the second beside
// what follows the plan; the plan's own program fills in the rest at the end. The samples are
// joined on every way out: a failed slice does not leave them running.
class UniformSamples {
 public:
  UniformSamples(const geometry::Mesh& mesh, const geometry::LayerStack& index,
                 const SliceResult& result, bool adaptive)
      : index_(index),
        profiles_(result.profiles),
        part_height_(result.part_size.z),
        allowed_(allowed_thicknesses(result.profiles.printer)),
        flats_(adaptive ? geometry::flat_levels(mesh) : std::vector<geometry::FlatLevel>{}) {}
  UniformSamples(const UniformSamples&) = delete;
  UniformSamples& operator=(const UniformSamples&) = delete;
  ~UniformSamples() {
    beside_.cancel();
    try {
      beside_.wait();
    } catch (...) {
    }
  }

  void start_thinnest() {
    beside_.run([this] { thinnest_ = sample(allowed_.thinnest()); });
  }

  // At about the plan's count, unless that is the thinnest again.
  void start_same_count(const std::vector<geometry::Layer>& layers, double first_layer_height) {
    const double t = nearest_allowed(
        allowed_, (layers.back().z_hi - first_layer_height) / static_cast<double>(layers.size() - 1));
    if (std::abs(t - allowed_.thinnest()) > 1e-9) beside_.run([this, t] { same_count_ = sample(t); });
  }

  // Waits for the samples started.
  void join() { beside_.wait(); }

  // What uniform slicing would take, after join(): at the thinnest layer, and at about as many
  // layers, scaled by a program of the part planned in `layers` (uniform_estimate.h).
  std::vector<SliceResult::Uniform> uniform(const std::vector<geometry::Layer>& layers,
                                            const printer::GcodeSummary& summary) const {
    std::vector<SliceResult::Uniform> uniform;
    for (const std::optional<Sampled>* sampled : {&thinnest_, &same_count_}) {
      if (!*sampled) continue;
      const auto& [t, sample] = **sampled;
      uniform.push_back({t, sample.layers.size(), uniform_seconds(sample, layers, summary)});
    }
    return uniform;
  }

 private:
  using Sampled = std::pair<double, LayerSample>;  // the thickness, the sample

  Sampled sample(double t) const {
    return Sampled{t, sample_layers(index_, geometry::uniform_plan(part_height_, t, allowed_, flats_).layers,
                                    profiles_)};
  }

  const geometry::LayerStack& index_;
  const printer::Profiles& profiles_;
  const double part_height_;
  const geometry::AllowedThicknesses allowed_;
  const std::vector<geometry::FlatLevel> flats_;
  // Declared before the group whose tasks write into them, so they outlive those tasks.
  std::optional<Sampled> thinnest_, same_count_;
  tbb::task_group beside_;
};

// The layer plan into the result, its notes reported. A print-time budget's candidate plans
// are estimated from a sample of their layers (uniform_estimate.h), times `estimate_factor`.
void plan_part_layers(const SliceOptions& options, const geometry::LayerStack& index,
                      const geometry::ContourStrategy& contour, SliceResult& result,
                      const SliceReporter& reporter, double estimate_factor) {
  reporter.progress(SliceStage::planning, 0, 0);
  result.choice = plan_layers(
      options, result.profiles, index, result.part_size.z, contour,
      [&](std::size_t measured) { reporter.progress(SliceStage::planning, measured, 0); },
      [&](const std::vector<geometry::Layer>& layers) {
        return estimate_factor * estimated_seconds(index, layers, result.profiles);
      });
  for (const std::string& line : result.choice.notes) reporter.warn(line);
  result.layers = result.choice.layers;
}

// Each layer's region, in parallel.
std::vector<geometry::Region> layer_regions(const geometry::LayerStack& stack,
                                            const geometry::ContourStrategy& contour,
                                            const SliceResult& result,
                                            const SliceReporter& reporter) {
  const std::size_t count = result.layers.size();
  std::vector<geometry::Region> regions(count);
  reporter.progress(SliceStage::contours, 0, count);
  std::atomic<std::size_t> contours_done{0};
  // A plan by mid's D has measured it on every layer: a strategy that compares mid (best)
  // takes it from there.
  const std::vector<double>& planned = result.choice.plan.distance;
  const bool mid_measured =
      result.choice.adaptive && result.choice.planned_by == "mid" && planned.size() == count;
  tbb::parallel_for(std::size_t{0}, count, [&](std::size_t i) {
    regions[i] = geometry::layer_contour(stack, i, contour, {},
                                         mid_measured ? planned[i] : std::nan(""));
    reporter.progress(SliceStage::contours, ++contours_done, count);
  });
  return regions;
}

// Supports, bridges and the raft, under the regions the layers really print; their wall time
// and bridge count into the result.
geometry::SupportPlan part_supports(const std::vector<geometry::Region>& regions,
                                    SliceResult& result, const SliceReporter& reporter) {
  const std::size_t count = result.layers.size();
  reporter.progress(SliceStage::supports, 0, count);
  const auto support_start = std::chrono::steady_clock::now();
  const geometry::SupportOptions support = support_options(result.profiles);
  geometry::SupportPlan plan = geometry::plan_supports(regions, result.layers, support,
                                                       raft_options(result.profiles.printer));
  result.support_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - support_start).count();
  for (const geometry::LayerSupport& layer : plan.layers) result.bridges += layer.bridges.size();
  reporter.progress(SliceStage::supports, count, count);
  return plan;
}

// The toolpaths of every layer; the regions are freed once they are laid.
std::vector<geometry::LayerToolpaths> part_toolpaths(std::vector<geometry::Region>& regions,
                                                     const geometry::SupportPlan& plan,
                                                     const SliceResult& result,
                                                     const SliceReporter& reporter) {
  const std::size_t count = result.layers.size();
  reporter.progress(SliceStage::toolpaths, 0, count);
  std::vector<geometry::LayerToolpaths> toolpaths = geometry::plan_toolpaths(
      regions, result.layers, toolpath_options(result.profiles.printer), plan,
      [&](std::size_t done) { reporter.progress(SliceStage::toolpaths, done, count); });
  regions.clear();
  regions.shrink_to_fit();
  return toolpaths;
}

// What the planned layers print: their supports and toolpaths, and the program's summary
// where it was timed before it is written (for a print-time budget).
struct PrintedLayers {
  geometry::SupportPlan supports;
  std::vector<geometry::LayerToolpaths> toolpaths;
  std::optional<printer::GcodeSummary> timed;
};

// The planned layers' contours, supports and toolpaths.
PrintedLayers print_planned_layers(const geometry::LayerStack& index, const geometry::ContourStrategy& contour,
                                   SliceResult& result, const SliceReporter& reporter) {
  const geometry::LayerStack stack(index, result.layers);
  std::vector<geometry::Region> regions = layer_regions(stack, contour, result, reporter);
  PrintedLayers printed;
  printed.supports = part_supports(regions, result, reporter);
  printed.toolpaths = part_toolpaths(regions, printed.supports, result, reporter);
  return printed;
}

// The G-code file and its summary into the result.
void write_part_gcode(const std::string& output, const SliceOptions& options,
                      const geometry::ContourStrategy& contour, const PrintedLayers& printed,
                      SliceResult& result, const SliceReporter& reporter) {
  const std::size_t count = result.layers.size();
  const printer::GcodeOptions gcode_options = gcode_options_for(options, result, contour, printed.supports);
  reporter.progress(SliceStage::writing, 0, count);
  result.summary = printer::write_gcode_file(
      output, printed.toolpaths, result.profiles, gcode_options,
      [&](std::size_t done) { reporter.progress(SliceStage::writing, done, count); },
      printed.timed ? &*printed.timed : nullptr);
}

// A print-time budget's plan takes its estimates this share higher from the start: the plan
// fits them within the budget to a few seconds, and what the estimate leaves out (best's
// contours where it times mid's sections, straightened) puts the program over it by a few
// tenths of a percent and would make the plan again, which costs as much CPU as the first.
// On the bunny at --max-time 80min two plans' programs took 0.1% and 0.7% more than their
// estimates (at 70min, with sections not straightened, 0.6%; the frustums of
// tests/app/slice_test.cpp, printed by mid's sections, 0.01% and 0.08% less).
constexpr double kBudgetHeadroom = 0.01;
// How many times a plan is made again, in fewer layers, for a print-time budget its
// program's estimate is over.
constexpr int kBudgetReplans = 3;

// A program of the part: its layers and its clock's summary.
struct PlannedProgram {
  std::vector<geometry::Layer> layers;
  printer::GcodeSummary summary;
};

// --max-time holds for the G-code's own estimate (the file's header's, and what `print
// --dry-run` says), not only for the plan's: the plan estimates its candidates from a sample
// of their layers with mid sections (uniform_estimate.h), which can fall short of the printed
// program (best prints other contours than mid; the sample's sections are straightened), by
// more for plans of more layers (the bunny at --max-time 80min: 219 layers estimated at
// 1 h 18 min 57 s printed in 1 h 20 min 5 s, 207 within a few seconds of their estimate).
// While the program's estimate is over the budget and the plan fitted its own (else no plan
// does, and the thickest layers were taken), the part is planned again as --max-layers plans
// it, in fewer layers than the first plan: as many fewer as the program's excess takes at its
// mean time per layer (at least one), then each time the current program's excess more, or
// twice as many if that is more, and its program timed.
// Raising the estimates by the shortfall seen and planning again by them instead took the
// bunny from 219 layers to 206 (1 h 17 min 53 s), and cost the whole search again. The plan
// line then says the program's estimate; the program's summary goes to the writer in
// `printed`. Returns the first plan's program where the plan was made again.
std::optional<PlannedProgram> keep_time_budget(const SliceOptions& options, const geometry::LayerStack& index,
                                               const geometry::ContourStrategy& contour, SliceResult& result,
                                               const SliceReporter& reporter, PrintedLayers& printed) {
  const double budget = result.choice.budget_seconds;
  if (!(budget > 0)) return std::nullopt;
  const auto program_seconds = [&] {
    printed.timed = printer::time_gcode(printed.toolpaths, result.profiles,
                                        gcode_options_for(options, result, contour, printed.supports));
    return printed.timed->print_seconds;
  };
  double seconds = program_seconds();
  const double first_plan = result.choice.estimated_seconds;
  const bool fitted_its_own = first_plan > 0 && first_plan <= budget;
  std::optional<PlannedProgram> first;
  const std::size_t first_count = result.layers.size();
  std::size_t fewer = 0;
  int replans = 0;
  for (; replans < kBudgetReplans && seconds > budget && fitted_its_own; ++replans) {
    if (!first) first = PlannedProgram{result.layers, *printed.timed};
    // The excess is the current plan's, which already has `fewer` layers fewer than the first.
    const auto excess = static_cast<std::size_t>(std::ceil((seconds - budget) / seconds * result.layers.size()));
    fewer = std::max({fewer * 2, fewer + excess, std::size_t{1}});
    if (fewer >= first_count) break;
    SliceOptions counted = options;
    counted.adaptive.max_seconds = 0;
    counted.adaptive.max_layers = first_count - fewer;
    const double planned_before = result.choice.seconds;
    plan_part_layers(counted, index, contour, result, reporter, 1);
    result.choice.seconds += planned_before;
    result.choice.budget_seconds = budget;
    result.choice.max_layers = 0;
    printed = print_planned_layers(index, contour, result, reporter);
    seconds = program_seconds();
  }
  if (first) {
    reporter.warn(fmt::format(
        "--max-time {}: the first plan's G-code ({} layers) takes {}, where the plan's estimate from a sample of "
        "its layers said {}; planned again {}, in {} layers as --max-layers plans them: {}",
        printer::format_duration(budget), first_count, printer::format_duration(first->summary.print_seconds),
        printer::format_duration(first_plan / (1 + kBudgetHeadroom)), replans == 1 ? "once" : fmt::format("{} times", replans),
        result.layers.size(), printer::format_duration(seconds)));
  }
  if (seconds > budget && fitted_its_own) {
    reporter.warn(fmt::format("--max-time {}: the G-code's estimate, {}, is still over it after {} plans",
                              printer::format_duration(budget), printer::format_duration(seconds), replans + 1));
  }
  result.choice.estimated_seconds = seconds;
  return first;
}

}  // namespace

SliceResult slice(const SliceOptions& options, const std::string& output,
                  const SliceEvents& events) {
  SliceResult result;
  const SliceReporter reporter{events, result};
  result.profiles = load_slice_profiles(options);
  const geometry::ContourStrategy& contour = contour_strategy_option(options.contour, "--contour");
  check_uniform_thickness(options, result);
  const geometry::Mesh mesh = load_part(options, result, reporter);
  const geometry::LayerStack index(mesh, {});
  const bool adaptive = options.adaptive.wanted();
  UniformSamples samples(mesh, index, result, adaptive);
  if (adaptive) samples.start_thinnest();
  plan_part_layers(options, index, contour, result, reporter, 1 + kBudgetHeadroom);
  const bool compared = result.choice.adaptive && result.layers.size() > 1;
  if (compared) samples.start_same_count(result.layers, result.profiles.printer.first_layer_height);
  PrintedLayers printed = print_planned_layers(index, contour, result, reporter);
  // The uniform figures are scaled by the first plan's program: made again for a print-time
  // budget, the plan does not move them.
  const std::optional<PlannedProgram> first = keep_time_budget(options, index, contour, result, reporter, printed);
  write_part_gcode(output, options, contour, printed, result, reporter);
  samples.join();
  if (compared) {
    result.uniform = first ? samples.uniform(first->layers, first->summary) : samples.uniform(result.layers, result.summary);
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
