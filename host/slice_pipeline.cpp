// The slice pipeline and its options; see slice_pipeline.h.
#include "host/slice_pipeline.h"

#include <algorithm>
#include <filesystem>
#include <atomic>
#include <charconv>
#include <chrono>
#include <cmath>
#include <memory>
#include <mutex>
#include <optional>
#include <ostream>
#include <streambuf>

#include <fmt/core.h>
#include <tbb/parallel_for.h>
#include <tbb/task_group.h>

#include "geometry/contour/contour_strategy.h"
#include "geometry/core/error.h"
#include "geometry/slicing/layer_stack.h"
#include "geometry/mesh/mesh.h"
#include "geometry/plan/flat_levels.h"
#include "geometry/plan/layer_plan.h"
#include "geometry/support/support_plan.h"
#include "geometry/toolpaths/toolpath_plan.h"
#include "host/cli_checks.h"
#include "host/layer_boundaries.h"
#include "host/profile_paths.h"
#include "host/progress.h"
#include "host/uniform_estimate.h"
#include "printer/error.h"

namespace host {

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
  options.support.pattern = geometry::parse_support_pattern(machine.support.pattern)
                                .value_or(geometry::SupportPattern::lines);
  options.support.spacing = machine.support.spacing;
  options.support.sheath = machine.support.sheath;
  options.support.angle = machine.support.angle;
  options.support.interface_density = machine.support.interface_density;
  options.support.raft_base_width = machine.raft.base_width;
  options.support.raft_base_spacing = machine.raft.base_spacing;
  options.support.raft_interface_spacing = machine.raft.interface_spacing;
  options.brim_width = machine.brim_width;
  return options;
}

// The profile's support settings in the part's frame: boxes are given on the bed (the
// G-code's X and Y), and the part is centred on the bed.
geometry::SupportOptions support_options(const printer::Profiles& profiles) {
  const printer::PrinterProfile& machine = profiles.printer;
  const printer::SupportSettings& s = machine.support;
  geometry::SupportOptions options;
  options.placement =
      geometry::parse_support_placement(s.type).value_or(geometry::SupportPlacement::none);
  options.overhang_angle = profiles.material.overhang_angle;
  options.bead_width = machine.extrusion_width;
  options.min_area = s.min_area;
  options.xy_gap = s.xy_gap;
  options.top_contact_distance = s.top_contact_distance;
  options.bottom_contact_distance = s.bottom_contact_distance;
  options.interface_thickness = s.interface_thickness;
  options.bridge_length = profiles.material.bridge_length;
  options.pattern = geometry::parse_support_pattern(s.pattern).value_or(geometry::SupportPattern::lines);
  options.line_spacing = s.spacing;
  options.line_angle = s.angle;
  const double cx = printer::bed_centre_x(machine), cy = printer::bed_centre_y(machine);
  auto part_box = [&](const printer::SupportBoxMm& b) {
    return geometry::SupportBox{{b[0] - cx, b[1] - cy, b[2]}, {b[3] - cx, b[4] - cy, b[5]}};
  };
  for (const auto& b : s.enforcers) options.enforcers.push_back(part_box(b));
  for (const auto& b : s.blockers) options.blockers.push_back(part_box(b));
  return options;
}

geometry::RaftOptions raft_options(const printer::PrinterProfile& machine) {
  const printer::RaftSettings& r = machine.raft;
  geometry::RaftOptions options;
  options.enabled = r.enabled;
  options.margin = r.margin;
  options.air_gap = r.air_gap;
  options.base_thickness = r.base_thickness;
  options.interface_layers = r.interface_layers;
  options.surface_layers = r.surface_layers;
  options.layer_thickness = r.layer_thickness;
  return options;
}

namespace {

std::string size_text(std::size_t bytes) {
  if (bytes >= (1u << 20)) return fmt::format("{:.1f} MiB", bytes / 1048576.0);
  if (bytes >= 1024) return fmt::format("{:.1f} KiB", bytes / 1024.0);
  return fmt::format("{} bytes", bytes);
}

// "x0,y0,z0,x1,y1,z1" as a box, or ConfigError naming the option.
printer::SupportBoxMm parse_box(const std::string& text, std::string_view option) {
  printer::SupportBoxMm box{};
  std::string_view rest = text;
  std::size_t count = 0;
  bool ok = true;
  while (ok && !rest.empty()) {
    const std::size_t comma = rest.find(',');
    std::string_view field = rest.substr(0, comma);
    while (!field.empty() && field.front() == ' ') field.remove_prefix(1);
    while (!field.empty() && field.back() == ' ') field.remove_suffix(1);
    double v = 0;
    const auto [end, error] = std::from_chars(field.data(), field.data() + field.size(), v);
    ok = count < 6 && error == std::errc() && end == field.data() + field.size() && std::isfinite(v);
    if (ok) box[count++] = v;
    if (comma == std::string_view::npos) break;
    rest.remove_prefix(comma + 1);
  }
  if (!ok || count != 6 || !(box[0] < box[3] && box[1] < box[4] && box[2] < box[5])) {
    throw printer::ConfigError(fmt::format(
        "{} '{}': needs six numbers x0,y0,z0,x1,y1,z1 (mm; X and Y on the bed as in the G-code, "
        "Z from the bed up to the part) with x0 < x1, y0 < y1 and z0 < z1",
        option, text));
  }
  return box;
}

// The support options as one block of the help (issue 12).
void add_support_options(CLI::App& command, SupportCliOptions& options,
                         std::vector<CLI::Option*>& added) {
  added.push_back(command.add_option("--support", options.placement,
                                     "supports under overhangs: none, buildplate (columns from "
                                     "the bed only) or everywhere (also from the part's top "
                                     "surfaces); bridges are laid with supports only (default: "
                                     "the printer profile's support.type)")
                      ->check(CLI::IsMember(support_placement_names())));
  added.push_back(command.add_option("--overhang-angle", options.overhang_angle,
                                     "degrees from vertical a wall may lean without support "
                                     "(default: the material's support.overhang_angle)")
                      ->check(number_in(0.0, 89.0)));
  added.push_back(command.add_option("--support-xy-gap", options.xy_gap,
                                     "mm between support and the part beside it (default: "
                                     "support.xy_gap)")
                      ->check(number_in(0.0, 10.0)));
  added.push_back(command.add_option("--support-top-distance", options.top_distance,
                                     "mm of air between the support's top and the part over it, "
                                     "rounded up to the layers' own tops (default: "
                                     "support.top_contact_distance)")
                      ->check(number_in(0.0, 2.0)));
  added.push_back(command.add_option("--support-bottom-distance", options.bottom_distance,
                                     "mm of air between the part and support standing on it "
                                     "(default: support.bottom_contact_distance)")
                      ->check(number_in(0.0, 2.0)));
  added.push_back(command.add_option("--support-interface-thickness", options.interface_thickness,
                                     "mm of dense layers at the top of the support at least, "
                                     "rounded up to the layers' own tops; 0 for none (default: "
                                     "support.interface_thickness)")
                      ->check(number_in(0.0, 5.0)));
  added.push_back(command.add_option("--support-pattern", options.pattern,
                                     "the support's sparse body: lines or grid (default: "
                                     "support.pattern)")
                      ->check(CLI::IsMember({"lines", "grid"})));
  added.push_back(command.add_option("--support-spacing", options.spacing,
                                     "mm between the support body's lines (default: "
                                     "support.spacing)")
                      ->check(number_in(0.5, 20.0)));
  added.push_back(command.add_option("--support-enforcer", options.enforcers,
                                     "support every overhang inside the box x0,y0,z0,x1,y1,z1 "
                                     "(mm; X, Y on the bed as in the G-code, Z from the bed up), "
                                     "however gentle (repeatable; default: support.enforcers)")
                      ->allow_extra_args(false));
  added.push_back(command.add_option("--support-blocker", options.blockers,
                                     "support no overhang inside the box x0,y0,z0,x1,y1,z1 "
                                     "(repeatable; default: support.blockers)")
                      ->allow_extra_args(false));
  added.push_back(command.add_option("--bridge-length", options.bridge_length,
                                     "mm a bridge may span, held at both ends, before it is "
                                     "supported instead; 0 bridges nothing (default: the "
                                     "material's bridge.max_length)")
                      ->check(number_in(0.0, 200.0)));
  added.push_back(command.add_option("--brim", options.brim,
                                     "brim width round the first layer, mm; 0 for none "
                                     "(default: the printer profile's brim.width)")
                      ->check(number_in(0.0, 50.0)));
  CLI::Option* raft = command.add_flag("--raft", options.raft,
                                       "print the part on a raft (default: the printer "
                                       "profile's raft.enabled)");
  CLI::Option* no_raft = command.add_flag("--no-raft", options.no_raft,
                                          "print the part without a raft, on the bed (default: "
                                          "the printer profile's raft.enabled)");
  raft->excludes(no_raft);
  added.push_back(raft);
  added.push_back(no_raft);
}

void apply_support_options(const SupportCliOptions& options, printer::Profiles& profiles) {
  printer::PrinterProfile& machine = profiles.printer;
  printer::SupportSettings& s = machine.support;
  if (!options.placement.empty()) s.type = options.placement;
  if (options.overhang_angle >= 0) profiles.material.overhang_angle = options.overhang_angle;
  if (options.xy_gap >= 0) s.xy_gap = options.xy_gap;
  if (options.top_distance >= 0) s.top_contact_distance = options.top_distance;
  if (options.bottom_distance >= 0) s.bottom_contact_distance = options.bottom_distance;
  if (options.interface_thickness >= 0) s.interface_thickness = options.interface_thickness;
  if (!options.pattern.empty()) s.pattern = options.pattern;
  if (options.spacing > 0) s.spacing = options.spacing;
  for (const std::string& box : options.enforcers) s.enforcers.push_back(parse_box(box, "--support-enforcer"));
  for (const std::string& box : options.blockers) s.blockers.push_back(parse_box(box, "--support-blocker"));
  if (options.bridge_length >= 0) profiles.material.bridge_length = options.bridge_length;
  if (options.brim >= 0) machine.brim_width = options.brim;
  if (options.raft) machine.raft.enabled = true;
  if (options.no_raft) machine.raft.enabled = false;
  if (machine.raft.enabled) {
    for (const auto& [key, thickness] : {std::pair{"raft.base_thickness", machine.raft.base_thickness},
                                         std::pair{"raft.layer_thickness", machine.raft.layer_thickness}}) {
      if (!machine.layer.allows(thickness)) {
        throw printer::ConfigError(fmt::format(
            "--raft: {} = {:g} mm is not a layer thickness the {} allows ({}); set another "
            "with --set {}=...", key, thickness, machine.name, machine.layer.describe(), key));
      }
    }
  }
}

// How far a raft lifts the part: its layers and the air gap, mm (0 without a raft).
double raft_height(const printer::RaftSettings& r) {
  if (!r.enabled) return 0;
  return r.base_thickness + (r.interface_layers + r.surface_layers) * r.layer_thickness + r.air_gap;
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
                           ->check(positive_number());
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
  for (CLI::Option* option : add_adaptive_options(command, options.adaptive, {}, true)) {
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
                      ->check(whole_number_in(0, 50)));
  added.push_back(command.add_option("--infill", options.infill,
                                     "sparse infill density, percent (default: the printer "
                                     "profile's print.infill_density)")
                      ->check(number_in(0.0, 100.0)));
  added.push_back(command
                      .add_option("--set", options.overrides,
                                  "override a profile key, e.g. --set retraction.length=1.5 or "
                                  "--set material.temperature.nozzle=250 (repeatable; default: "
                                  "none)")
                      // one key=value per --set: a model path after it stays the model
                      ->allow_extra_args(false));
  add_support_options(command, options.support, added);
  if (!group.empty()) {
    for (CLI::Option* option : added) option->group(group);
  }
}

const std::vector<std::string>& model_only_slice_options() {
  static const std::vector<std::string> names{
      "--units", "--scale",      "--height", "--up",  "--ignore-normals", "--rotate", "--orient",
      "--material",
      "--layer", "--boundaries", "--adaptive", "--tolerance", "--max-layers", "--max-time",
      "--contour",
      "--perimeters", "--infill",
      // issue 12
      "--support", "--overhang-angle", "--support-xy-gap", "--support-top-distance",
      "--support-bottom-distance", "--support-interface-thickness", "--support-pattern",
      "--support-spacing", "--support-enforcer", "--support-blocker", "--bridge-length",
      "--brim", "--raft", "--no-raft"};
  return names;
}

printer::Profiles load_slice_profiles(const SliceOptions& options) {
  printer::ProfileRequest request;
  request.printer = options.printer;
  request.material = options.material;
  request.config_dir = host::profile_search_path();
  request.overrides = options.overrides;
  printer::Profiles profiles = printer::load_profiles(request);
  if (options.perimeters >= 0) profiles.printer.print.perimeters = options.perimeters;
  if (options.infill >= 0) profiles.printer.print.infill_density = options.infill;
  apply_support_options(options.support, profiles);
  return profiles;
}

std::vector<std::string> support_placement_names() {
  std::vector<std::string> names;
  for (const geometry::SupportPlacement placement : geometry::kSupportPlacements) {
    names.emplace_back(geometry::support_placement_name(placement));
  }
  return names;
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

  ModelOptions model = options.model;
  model.overhang_angle = result.profiles.material.overhang_angle;  // for --orient auto
  model.support_cost = support_cost(machine);
  const geometry::Mesh mesh = load_model(model);
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
  // Only when there is something of issue 12 to say: without it the header is as before.
  if (support.placement != geometry::SupportPlacement::none) {
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

sim::SupportCheckOptions support_check_options(const printer::Profiles& profiles) {
  sim::SupportCheckOptions options;
  options.filament_diameter = profiles.printer.filament_diameter;
  options.bridge_length = profiles.material.bridge_length;
  options.contact_gap = std::max(profiles.printer.support.top_contact_distance,
                                 profiles.printer.support.bottom_contact_distance);
  return options;
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

}  // namespace host
