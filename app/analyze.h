// `mahost analyze` and `mahost advise` as requests and results (paper §4, Fig. 22-26). They
// print nothing: the command line formats the result as a table, CSV, JSON and charts.
//
// analyze slices the model into the layers asked for (uniform, --boundaries, or an adaptive
// plan), makes each layer's region with every strategy asked for, measures each region
// (geometry/metrics/layer_metrics.h: ΔV exactly, D to 1 um over the whole surface, H's reverse
// direction at 5 heights), sums them up per strategy and compares every strategy with lower
// (the paper's baseline) and with mid (what PrusaSlicer, Slic3r and CuraEngine print). Where
// asked it also measures the medial-axis contour at thicker layers, the plan's printed contour
// at uniform layers beside it, one layer's footprint and contours, and the layered part.
//
// advise takes lower's distance error at the thinnest thickness as the benchmark and, for
// every thickness (the printer's, or those given), the share of the contour's layers whose D
// stays within the benchmark at the same heights, the layer count, and the largest thickness
// that keeps at least `share` percent of layers within it. A layer plan (--boundaries,
// --adaptive) is one more row, judged against the same benchmark, not a candidate.
#pragma once

#include <cstddef>
#include <functional>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "app/layer_choice.h"
#include "app/model.h"
#include "geometry/analysis/layer_analysis.h"
#include "geometry/contour/contour_strategy.h"
#include "geometry/core/polygon.h"
#include "geometry/mesh/mesh.h"
#include "geometry/slicing/layer_stack.h"
#include "printer/profile.h"

namespace app {

using Strategies = std::vector<const geometry::ContourStrategy*>;

// "lower, mid, ..." (or with another separator): every strategy's name, for help and errors.
using geometry::contour_names;

// What a caller hears while analyze or advise runs. Each may be left empty.
struct AnalysisEvents {
  // What loading the model did that a user should hear of (app::model_notes), as it happens.
  std::function<void(const std::string& line)> model_note;
  // What --boundaries' layers leave out (BoundaryLayers::notes), as it happens.
  std::function<void(const std::string& line)> layers_note;
  // Called with done = 0 from the calling thread when a run of work starts: "planning
  // layers" (done: candidate layers measured, total 0), "analyze", "ma at 0.2 mm", ... (done
  // of total layers); then as it advances, possibly from several threads at once.
  std::function<void(const std::string& label, std::size_t done, std::size_t total)> progress;
  // Asked at every progress step, from any thread: true stops the work with
  // AnalysisCancelled.
  std::function<bool()> cancelled;
};

// Thrown out of analyze() and advise() when AnalysisEvents::cancelled said so.
struct AnalysisCancelled : std::runtime_error {
  AnalysisCancelled() : std::runtime_error("analysis cancelled") {}
};

// The strategies named (each once, in the order given); an unknown name, or none, throws
// geometry::InputError naming `flag`.
Strategies strategy_list(const std::vector<std::string>& names, const std::string& flag);

// Where `name` is among `strategies`, or -1.
int strategy_index(const Strategies& strategies, std::string_view name);

struct AnalyzeRequest {
  ModelOptions model;
  // The layers judged: `boundaries` when given (layer tops as a list, a file or another
  // slicer's G-code: any thicknesses, no printer asked; the part above the last is not
  // judged); else `adaptive`'s plan when wanted, on `printer`'s thicknesses for `contour`;
  // else uniform `layer` as `slice` lays them on `printer` (its first layer, flat tops and
  // floors landed; a thickness it lacks allowed, and any from its thinnest up to it); with
  // `from_zero`, the plain grid from the bed, every layer `layer` thick (the paper's).
  double layer = 0.15;  // mm
  std::string boundaries;
  bool from_zero = false;
  AdaptiveRequest adaptive;
  std::string printer = printer::kDefaultPrinter;
  Strategies strategies;  // compared, in this order (strategy_list)
  // The layered part's strategy, and the one an adaptive plan is made for: measured too
  // (after `strategies`) where `export_layers` or `adaptive` needs it.
  const geometry::ContourStrategy* contour = nullptr;
  geometry::ZRange excluded;  // left out of the by-height percentile of D
  // Thicknesses (mm) at which to measure ma against lower at `layer` (Fig. 24-25; one equal
  // to `layer` is skipped; needs lower among `strategies`).
  std::vector<double> thicker;
  // With an adaptive plan: measure `contour` at uniform layers beside it, for its charts.
  bool plan_beside_uniform = false;
  std::optional<std::size_t> layer_index;  // this layer's footprint and contours, drawn
  bool export_layers = false;              // the layered part of `contour`, as a mesh
};

// How strategy `strategy` compares with `baseline` (indices into AnalyzeResult::strategies).
struct Comparison {
  std::size_t strategy = 0, baseline = 0;
  // ΔV per layer against the baseline's, over `layers_compared` layers (those where the
  // baseline's is above geometry::kNegligibleVolume): the mean change, the least and the
  // greatest, in percent.
  double per_layer_change_percent = 0, least_change_percent = 0, greatest_change_percent = 0;
  std::size_t layers_compared = 0;
  // Layers whose D is below (better) or above (worse) the baseline's by more than the
  // distance tolerance; of the worse, those where the baseline misses more features than the
  // strategy (best printing a tip or a thin wall that mid's section leaves out, at a D that
  // an empty or smaller section does not have).
  std::size_t distance_better = 0, distance_worse = 0, distance_worse_keeping_features = 0;
  // Below these a D (mm) or a total ΔV (mm³) is rounding, not error: a change from a baseline
  // this small is no percentage.
  double negligible_distance = 0, negligible_volume = 0;
};

// How strategy k compares with baseline b over the layers (indices into each layer's
// strategies).
Comparison compare(const std::vector<geometry::LayerAnalysis>& layers, std::size_t k,
                   std::size_t b);

// Ma at thicker layers against lower at the analysed ones.
struct ThickerLayers {
  double thickness = 0;  // mm
  std::vector<geometry::LayerAnalysis> layers;
  double mean_distance = 0, max_distance = 0;  // mm
  double within_percent = 0;  // of layers whose D is within lower's at the same heights
};

// A plan's printed contour at uniform layers (the printer's thinnest, and the allowed
// thickness giving about as many layers as the plan).
struct UniformLayers {
  double thickness = 0;  // mm
  std::vector<geometry::LayerAnalysis> layers;
};

// One layer drawn: its slab's footprint, its islands, each strategy's region and metrics.
struct LayerDrawing {
  std::size_t index = 0;
  geometry::Layer layer;
  geometry::Region footprint;  // the boundary pair
  std::size_t islands = 0;
  geometry::LayerAnalysis analysis;
};

struct AnalyzeResult {
  double height = 0;  // the part's, mm
  double model_volume = 0;  // mm³
  std::optional<LayerChoice> plan;  // an adaptive plan's
  std::vector<geometry::Layer> layers;
  Strategies strategies;  // as measured: the request's, then `contour` where needed
  std::vector<geometry::LayerAnalysis> analysis;  // per layer, its strategies in that order
  std::vector<geometry::StrategySummary> summaries;
  double volume_limit = 0;  // mm³: the least ΔV any extruded layers can have
  // Each strategy against lower, and against mid (but lower and mid themselves).
  std::vector<Comparison> comparisons;
  std::vector<ThickerLayers> thicker;
  std::vector<UniformLayers> uniform;  // with plan_beside_uniform
  std::optional<LayerDrawing> drawing;  // with layer_index
  std::optional<geometry::Mesh> layered_part;  // with export_layers: `contour`'s regions extruded
  double layered_part_volume = 0;              // mm³
};

// Throws geometry::InputError for a model or layers that cannot be used, printer::ConfigError
// for profiles, AnalysisCancelled.
AnalyzeResult analyze(const AnalyzeRequest& request, const AnalysisEvents& events = {});

// Writes a mesh (the layered part) to `path` as binary STL; geometry::InputError when it
// cannot.
void write_stl(const geometry::Mesh& mesh, const std::string& path);

struct AdviseRequest {
  ModelOptions model;
  const geometry::ContourStrategy* contour = nullptr;  // for the thicker layers
  // mm, ascending (none given: refused); without them, the printer's.
  std::optional<std::vector<double>> thicknesses;
  std::string printer = printer::kDefaultPrinter;
  std::string boundaries;    // a layer plan judged as one more row
  AdaptiveRequest adaptive;  // or an adaptive plan for `contour`
  double share = 95;         // percent of layers that must stay within the benchmark
};

// One thickness (or the plan) against the benchmark.
struct AdviseRow {
  double thickness = 0;  // mm; 0 for the plan
  std::size_t layers = 0;
  double mean_distance = 0, max_distance = 0;  // mm
  double within_percent = 0;        // of layers within the benchmark's D at the same heights
  double fewer_layers_percent = 0;  // than the benchmark
};

struct AdviseResult {
  double height = 0;  // mm
  // "--thicknesses", or the printer's name and its layers ("up-plus-2 (0.15 to 0.4 mm ...)").
  std::string thicknesses_from;
  double benchmark_thickness = 0;  // the thinnest, mm
  std::size_t benchmark_layers = 0;
  double benchmark_mean_distance = 0, benchmark_max_distance = 0;  // mm
  std::vector<AdviseRow> rows;
  std::optional<AdviseRow> plan;  // --boundaries' or --adaptive's
  std::vector<geometry::Layer> plan_layers;
  std::optional<LayerChoice> adaptive;  // the adaptive plan's choice
  std::optional<double> advised;  // the largest thickness keeping `share` percent within
};

// Throws as analyze() does.
AdviseResult advise(const AdviseRequest& request, const AnalysisEvents& events = {});

}  // namespace app
