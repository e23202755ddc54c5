// The slice pipeline in one call (DESIGN.md §1): load the model (read, repair, place) ->
// layers (the printer's first-layer height, then --layer) -> each layer's region by the
// contour strategy -> toolpaths -> G-code for the printer and material. `mahost slice` runs it
// to write a file; `mahost print` runs it in-process before streaming an STL. Its command-line
// options are defined here once, for both commands.
#pragma once

#include <cstddef>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include <CLI/CLI.hpp>

#include "geometry/core/polygon.h"
#include "geometry/slicing/layer_stack.h"
#include "geometry/support/support_plan.h"
#include "geometry/toolpaths/toolpath_plan.h"
#include "host/layer_choice.h"
#include "host/model_input.h"
#include "printer/gcode_writer.h"
#include "printer/profile.h"
#include "sim/unsupported_extrusion.h"

namespace geometry {
struct ContourStrategy;  // geometry/contour/contour_strategy.h
}  // namespace geometry

namespace host {

// Supports, bridges, brim and raft (issue 12): each unset value is the profile's.
struct SupportCliOptions {
  std::string placement;           // --support: none, buildplate, everywhere; "": support.type
  double overhang_angle = -1;      // degrees from vertical; -1: the material's
  double xy_gap = -1;              // mm; -1: support.xy_gap
  double top_distance = -1;        // mm; -1: support.top_contact_distance
  double bottom_distance = -1;     // mm; -1: support.bottom_contact_distance
  double interface_thickness = -1;  // mm; -1: support.interface_thickness
  std::string pattern;             // lines, grid; "": support.pattern
  double spacing = -1;             // mm; -1: support.spacing
  std::vector<std::string> enforcers, blockers;  // "x0,y0,z0,x1,y1,z1", added to the profile's
  double bridge_length = -1;       // mm; -1: the material's bridge.max_length
  double brim = -1;                // mm; -1: brim.width
  bool raft = false, no_raft = false;  // neither: raft.enabled
};

struct SliceOptions {
  ModelOptions model;
  std::string printer = "up-plus-2";
  std::string material;    // "": the printer's
  double layer = 0;        // mm; 0: the printer's layer.default
  std::string boundaries;  // --boundaries FILE|z1,z2,...: explicit layer tops instead
  AdaptiveRequest adaptive;  // --adaptive, --tolerance, --max-layers
  std::string contour = "best";
  int perimeters = -1;     // -1: the printer profile's print.perimeters
  double infill = -1;      // percent; -1: the profile's print.infill_density
  std::vector<std::string> overrides;  // "key=value", one per --set
  SupportCliOptions support;
};

// The profiles' settings as the geometry stages take them: toolpaths, supports (boxes in the
// part's frame: the part is centred on the bed), the raft.
geometry::ToolpathOptions toolpath_options(const printer::PrinterProfile& machine);
geometry::SupportOptions support_options(const printer::Profiles& profiles);
geometry::RaftOptions raft_options(const printer::PrinterProfile& machine);

// Adds the slice options to a command: the model's placement (--units, --scale, --height,
// --up, --ignore-normals; not the MODEL argument itself), --printer, --material, --layer,
// --boundaries, --contour, --perimeters, --infill, --set, and the support options (--support,
// --overhang-angle, --support-xy-gap, --support-top-distance, --support-bottom-distance,
// --support-interface-thickness, --support-pattern, --support-spacing, --support-enforcer,
// --support-blocker, --bridge-length, --brim, --raft, --no-raft). They are listed under
// `group` in the command's help ("" leaves them among its other options).
void add_slice_options(CLI::App& command, SliceOptions& options, const std::string& group = {});

// The contour strategies (geometry/contour/contour_strategy.h's table) as --contour options
// show them: their names, and "name (description), ..." for a help text.
std::vector<std::string> contour_strategy_names();
// "none", "buildplate", "everywhere": --support's values.
std::vector<std::string> support_placement_names();
std::string contour_strategies_help();

// The strategy the user named after `flag` ("--contour"); an unknown name throws
// geometry::InputError listing the strategies.
const geometry::ContourStrategy& contour_strategy_option(const std::string& name,
                                                         const std::string& flag);

// The options of add_slice_options that only mean something for a model to slice (all but
// --printer), as written on the command line: for `print` to refuse them with a G-code file.
const std::vector<std::string>& model_only_slice_options();

// The printer and material profiles the options name, with --perimeters, --infill and the
// support options applied. Throws printer::ConfigError naming the profile, key or value that is wrong.
printer::Profiles load_slice_profiles(const SliceOptions& options);

// The layers the part is printed in, bottom up, from z = 0 to at least the part's top (the
// layer plan of DESIGN.md §1; every stage after it takes each layer's own thickness): the
// --boundaries given; else --adaptive's plan (host/layer_choice.h) for the contour printed;
// else uniform layers of --layer (or the printer's default) after the printer's first layer,
// flat tops and floors on boundaries. `index` is a stack over the model (its layers unused).
// With supports on, the adaptive plan keeps layers thin where thick ones would need support
// that thin ones do not (AdaptiveRequest::thick_overhangs). Every thickness is checked
// against the printer (ConfigError naming the layer and what is allowed), and the last layer
// must end within the build height.
LayerChoice plan_layers(const SliceOptions& options, const printer::Profiles& profiles,
                        const geometry::LayerStack& index, double part_height,
                        const geometry::ContourStrategy& printed,
                        const PlanningProgress& progress = {},
                        const PrintEstimate& estimate = {});

// The pipeline's stages, in order; progress is reported per stage.
enum class SliceStage { planning, contours, supports, toolpaths, writing };
// "planning layers", "contours", "supports", "toolpaths", "writing"
std::string_view stage_name(SliceStage stage);

// Called with done = 0 from the calling thread when a stage starts, then as its layers are
// done (done of total), possibly from several threads at once.
using SliceProgress = std::function<void(SliceStage stage, std::size_t done, std::size_t total)>;

struct SliceResult {
  printer::Profiles profiles;      // as used, overrides applied
  geometry::Vec3 part_size;        // mm, after placement
  double layer_thickness = 0;      // mm, the layers after the first (uniform); 0 for --boundaries
  std::vector<geometry::Layer> layers;  // as printed
  LayerChoice choice;              // how they were chosen (adaptive: the plan)
  printer::GcodeSummary summary;   // layers, estimated seconds, filament, bytes
  std::size_t bridges = 0;         // pieces of layers laid as bridges
  double support_seconds = 0;      // wall time of the support stage
  // An adaptive plan beside uniform slicing of the same part: at the thinnest thickness and
  // at the one giving about as many layers (estimated with mid sections).
  struct Uniform {
    double thickness = 0;
    std::size_t layers = 0;
    double print_seconds = 0;
  };
  std::vector<Uniform> uniform;
};

// Slices the model into a G-code file at `output` (written beside it and renamed at the end:
// a failed slice leaves no file). Throws geometry::InputError for a model that cannot be used
// and printer::ConfigError for profiles, a layer the printer cannot print, a part that does
// not fit, or a file that cannot be written.
SliceResult slice_to_gcode(const SliceOptions& options, const std::string& output,
                           const SliceProgress& progress = {});

// The unsupported-extrusion check's parameters for a print with these profiles: the
// filament, the material's bridge length, and as the air a bead may sag across the larger of
// the support's top and bottom contact distances (sim/unsupported_extrusion.h).
sim::SupportCheckOptions support_check_options(const printer::Profiles& profiles);

// A terminal progress bar per stage (host/progress.h), as a SliceProgress.
SliceProgress slice_progress_bars(const std::string& contour);

// "250 layers, estimated print time 56 min 51 s, filament 3.25 m (8.1 g ABS), 2.6 MiB"; with
// support or a raft, "250 layers, on 4 raft layers, ... filament 3.60 m (9.0 g ABS; 0.35 m of
// it support and raft)".
std::string slice_summary_text(const SliceResult& result);

// The layer plan in one line when there is something to say ("" otherwise): an adaptive plan
// (layers, thickness range, unmet layers and why, time against uniform slicing at the thinnest
// layer and at the same count), flat levels that could not land on a boundary.
std::string slice_plan_text(const SliceResult& result);

}  // namespace host
