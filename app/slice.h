// The slice pipeline in one call (DESIGN.md §1): load the model (read, repair, place) ->
// layers (the printer's first-layer height, then --layer) -> each layer's region by the
// contour strategy -> supports -> toolpaths -> G-code for the printer and material.
// `mahost slice` runs it to write a file, `mahost print` before streaming a model, `mahost
// serve` for an uploaded model, the tests in-process. It prints nothing: what a user should
// hear of comes back in the result, and as it happens through SliceEvents.
#pragma once

#include <cstddef>
#include <functional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "app/layer_choice.h"
#include "app/model.h"
#include "app/slice_options.h"
#include "geometry/core/polygon.h"
#include "geometry/mesh/repair.h"
#include "geometry/slicing/layer_stack.h"
#include "printer/gcode_writer.h"
#include "printer/profile.h"

namespace geometry {
struct ContourStrategy;  // geometry/contour/contour_strategy.h
}  // namespace geometry

namespace app {

// The pipeline's stages, in order; progress is reported per stage.
enum class SliceStage { planning, contours, supports, toolpaths, writing };
// "planning layers", "contours", "supports", "toolpaths", "writing"
std::string_view stage_name(SliceStage stage);

// What a caller hears while a slice runs. Each may be left empty.
struct SliceEvents {
  // Called with done = 0 from the calling thread when a stage starts, then as its layers are
  // done (done of total; planning: the candidate layers measured, total 0), possibly from
  // several threads at once.
  std::function<void(SliceStage stage, std::size_t done, std::size_t total)> progress;
  // A line a user should read (a repair, the orientation chosen, layer tops left out), from
  // the calling thread as soon as it is known; the same lines are in SliceResult::warnings.
  std::function<void(const std::string& line)> warning;
  // Asked at every progress step, from any thread: true stops the slice with SliceCancelled
  // (no file is left behind).
  std::function<bool()> cancelled;
};

// Thrown out of slice() when SliceEvents::cancelled said so.
struct SliceCancelled : std::runtime_error {
  SliceCancelled() : std::runtime_error("slicing cancelled") {}
};

struct SliceResult {
  printer::Profiles profiles;       // as used, overrides applied
  geometry::RepairReport repair;    // what the model's repair did (file units)
  std::vector<std::string> warnings;  // see SliceEvents::warning
  geometry::Vec3 part_size;         // mm, after placement
  double layer_thickness = 0;       // mm, the layers after the first (uniform); 0 otherwise
  std::vector<geometry::Layer> layers;  // as printed
  LayerChoice choice;               // how they were chosen (adaptive: the plan)
  printer::GcodeSummary summary;    // layers, estimated seconds, filament, bytes
  std::size_t bridges = 0;          // pieces of layers laid as bridges
  double support_seconds = 0;       // wall time of the support stage
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
SliceResult slice(const SliceOptions& options, const std::string& output,
                  const SliceEvents& events = {});

// The layers the part is printed in, bottom up, from z = 0 to at least the part's top (the
// layer plan of DESIGN.md §1; every stage after it takes each layer's own thickness): the
// --boundaries given; else --adaptive's plan (app/layer_choice.h) for the contour printed;
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

// The strategy the user named after `flag` ("--contour"); an unknown name throws
// geometry::InputError listing the strategies.
const geometry::ContourStrategy& contour_strategy_option(const std::string& name,
                                                         const std::string& flag);

// "250 layers, estimated print time 56 min 51 s, filament 3.25 m (8.1 g ABS), 2.6 MiB"; with
// support or a raft, "250 layers, on 4 raft layers, ... filament 3.60 m (9.0 g ABS; 0.35 m of
// it support and raft)".
std::string slice_summary_text(const SliceResult& result);

// The layer plan in one line when there is something to say ("" otherwise): an adaptive plan
// (layers, thickness range, unmet layers and why, time against uniform slicing at the thinnest
// layer and at the same count), flat levels that could not land on a boundary.
std::string slice_plan_text(const SliceResult& result);

}  // namespace app
