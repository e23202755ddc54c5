// `mahost slice MODEL.stl [placement] -o OUT.gcode [--printer up-plus-2] [--material abs]
//  [--layer 0.2] [--contour ma] [--perimeters 2] [--infill 20] [--set key=value ...]`
//
// Model -> layers (the printer's first-layer height, then --layer) -> each layer's region by
// the chosen contour strategy -> toolpaths -> G-code for the chosen printer and material.
// The default printer is the UP Plus 2 (the paper's machine class); the default layer is the
// printer profile's layer.default, the default material its `material`.
// A progress bar per stage on a terminal; one final line: layers, print-time estimate,
// filament, output size.
#include <atomic>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <fmt/core.h>
#include <tbb/parallel_for.h>

#include "geometry/contour_strategy.h"
#include "geometry/layer_stack.h"
#include "geometry/mesh.h"
#include "geometry/toolpath_plan.h"
#include "host/commands.h"
#include "host/model_input.h"
#include "host/progress.h"
#include "printer/error.h"
#include "printer/gcode_writer.h"
#include "printer/profile.h"

namespace host {
namespace {

struct SliceOptions {
  ModelOptions model;
  std::string output;
  std::string printer = "up-plus-2";
  std::string material;
  double layer = 0;  // 0: the printer's default
  std::string contour = "ma";
  int perimeters = -1;   // -1: the printer profile's print.perimeters
  double infill = -1;    // -1: the profile's print.infill_density
  std::vector<std::string> overrides;
};

std::string size_text(std::size_t bytes) {
  if (bytes >= (1u << 20)) return fmt::format("{:.1f} MiB", bytes / 1048576.0);
  if (bytes >= 1024) return fmt::format("{:.1f} KiB", bytes / 1024.0);
  return fmt::format("{} bytes", bytes);
}

void run_slice(const SliceOptions& options) {
  printer::ProfileRequest request;
  request.printer = options.printer;
  request.material = options.material;
  request.config_dir = printer::config_directory(MAHOST_CONFIG_DIR);
  request.overrides = options.overrides;
  printer::Profiles profiles = printer::load_profiles(request);
  printer::PrinterProfile& machine = profiles.printer;
  if (options.perimeters >= 0) machine.print.perimeters = options.perimeters;
  if (options.infill >= 0) machine.print.infill_density = options.infill;

  const geometry::ContourKind contour =
      geometry::parse_contour_kind(options.contour).value_or(geometry::ContourKind::ma);
  const double thickness = options.layer > 0 ? options.layer : machine.layer.default_thickness;
  printer::check_layer_thickness(machine, thickness);

  const geometry::Mesh mesh = load_model(options.model);
  const geometry::Box3 box = geometry::bounding_box(mesh);
  const geometry::Vec3 size = box.max - box.min;
  printer::check_part_fits(machine, size.x, size.y, size.z);

  const std::vector<geometry::Layer> layers =
      geometry::uniform_layers(size.z, thickness, machine.first_layer_height);
  const geometry::LayerStack stack(mesh, layers);

  std::vector<geometry::Region> regions(layers.size());
  {
    Progress progress(fmt::format("contours ({})", options.contour), layers.size());
    std::atomic<std::size_t> done{0};
    tbb::parallel_for(std::size_t{0}, layers.size(), [&](std::size_t i) {
      regions[i] = geometry::layer_contour(stack, i, contour);
      const std::size_t n = ++done;
      progress.update(n, fmt::format("layer {}/{}", n, layers.size()));
    });
  }

  geometry::ToolpathOptions toolpath_options;
  toolpath_options.extrusion_width = machine.extrusion_width;
  toolpath_options.first_layer_width = machine.first_layer_width;
  toolpath_options.perimeters = machine.print.perimeters;
  toolpath_options.infill_density = machine.print.infill_density;
  toolpath_options.infill_pattern =
      geometry::parse_infill_pattern(machine.print.infill_pattern).value_or(geometry::InfillPattern::grid);
  toolpath_options.top_layers = machine.print.top_layers;
  toolpath_options.bottom_layers = machine.print.bottom_layers;
  toolpath_options.skirt_loops = machine.print.skirt_loops;
  toolpath_options.skirt_distance = machine.print.skirt_distance;
  toolpath_options.retract_min_travel = machine.retraction.min_travel;
  toolpath_options.seam =
      geometry::parse_seam_position(machine.print.seam).value_or(geometry::SeamPosition::aligned);

  std::vector<geometry::LayerToolpaths> toolpaths;
  {
    Progress progress("toolpaths", layers.size());
    toolpaths = geometry::plan_toolpaths(regions, layers, toolpath_options, [&](std::size_t n) {
      progress.update(n, fmt::format("layer {}/{}", n, layers.size()));
    });
  }
  regions.clear();
  regions.shrink_to_fit();

  printer::GcodeOptions gcode_options;
  gcode_options.layer_height = thickness;
  gcode_options.notes = {
      fmt::format("model: {} ({:.2f} x {:.2f} x {:.2f} mm)", options.model.path, size.x, size.y,
                  size.z),
      fmt::format("contour: {}", options.contour),
      fmt::format("layer: {:g} mm, first layer {:g} mm", thickness, machine.first_layer_height),
      fmt::format("perimeters: {}, infill: {:g}% {}, top/bottom layers: {}/{}",
                  machine.print.perimeters, machine.print.infill_density,
                  machine.print.infill_pattern, machine.print.top_layers,
                  machine.print.bottom_layers)};
  printer::GcodeSummary summary;
  {
    Progress progress("writing", layers.size());
    summary = printer::write_gcode_file(options.output, toolpaths, profiles, gcode_options,
                                        [&](std::size_t n) {
                                          progress.update(n, fmt::format("layer {}/{}", n, layers.size()));
                                        });
  }
  fmt::print("{}: {} layers, estimated print time {}, filament {:.2f} m ({:.1f} g {}), {}\n",
             options.output, summary.layers, printer::format_duration(summary.print_seconds),
             summary.filament_mm / 1000.0, summary.filament_grams, profiles.material.name,
             size_text(summary.bytes));
}

}  // namespace

void add_slice_command(CLI::App& app) {
  auto options = std::make_shared<SliceOptions>();
  CLI::App* slice = app.add_subcommand(
      "slice",
      "Slice a model into G-code for a Marlin-style printer: layers of the chosen contour "
      "strategy, walls, skins, infill and skirt, a print-time estimate in the header.");
  add_model_options(*slice, options->model);
  slice->add_option("-o,--output", options->output, "the G-code file to write")->required();
  slice->add_option("--printer", options->printer,
                    "printer profile: a name in the config directory (up-plus-2, "
                    "generic-marlin) or a path to a .toml file")
      ->capture_default_str();
  slice->add_option("--material", options->material,
                    "material profile: a name (abs, pla) or a path; default: the printer's");
  slice->add_option("--layer", options->layer,
                    "layer thickness, mm; one the printer allows (default: the printer's)")
      ->check(CLI::PositiveNumber);
  slice->add_option("--contour", options->contour,
                    "which region each layer extrudes: lower (section at the layer's bottom), "
                    "mid (at its middle, as other slicers), optimal-height (the section with the "
                    "least volume deviation), ma (the paper's medial-axis contour)")
      ->check(CLI::IsMember({"lower", "mid", "optimal-height", "ma"}))
      ->capture_default_str();
  slice->add_option("--perimeters", options->perimeters, "wall loops (default: the printer's)")
      ->check(CLI::Range(0, 50));
  slice->add_option("--infill", options->infill, "sparse infill density, percent (default: the printer's)")
      ->check(CLI::Range(0.0, 100.0));
  slice->add_option("--set", options->overrides,
                    "override a profile key, e.g. --set retraction.length=1.5 or "
                    "--set material.temperature.nozzle=250 (repeatable)")
      ->allow_extra_args(false);  // one key=value per --set: a model path after it stays the model
  slice->callback([options] { run_slice(*options); });
}

}  // namespace host
