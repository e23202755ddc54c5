// Comparing contour strategies layer by layer (paper §4; DESIGN.md §2-3): for every layer,
// each strategy's region and its metrics (layer_metrics.h), and per strategy the part's
// summary the paper reports, with mid-plane slicing (what PrusaSlicer, Slic3r and CuraEngine
// print) as a second baseline beside the paper's lower contour.
//
// Input: a layer stack, the strategies to compare, options. Layers are independent and run in
// parallel (TBB); `progress` (if set) is called with the number of layers done, from any thread.
// Output: one LayerAnalysis per layer, in order, and one StrategySummary per strategy:
//   mean and max D over layers (the paper's "average" and "maximum distance error"), mean
//   and max Hausdorff distance, total and mean ΔV, the total volume limit, ΔV above the limit
//   in %, missed features, the defect cases: layers whose D exceeds lower's, and mid's,
//   on the same layer by more than the distance tolerance; and the 95th percentile of D by
//   height (distance_percentile_by_height below), which judges stacks of different layer
//   thicknesses alike. Units mm, mm^3, s; times are the
//   CPU seconds of the thread that did the work, so they do not grow when others share the
//   cores.
#pragma once

#include <cstddef>
#include <functional>
#include <span>
#include <vector>

#include "geometry/contour/contour_strategy.h"
#include "geometry/metrics/layer_metrics.h"
#include "geometry/slicing/layer_stack.h"

namespace geometry {

struct AnalysisOptions {
  ContourOptions contour;
  MetricOptions metrics;
  bool keep_regions = true;  // false: drop each region once measured (saves memory)
};

struct StrategyLayer {
  const ContourStrategy* strategy = nullptr;
  Region region;
  LayerMetrics metrics;
  double height = 0;            // ContourResult::height: where the region was cut
  double contour_seconds = 0;   // making the region
  double metric_seconds = 0;    // measuring it
};

struct LayerAnalysis {
  Layer layer;
  std::vector<StrategyLayer> strategies;  // in the order asked
  double reference_seconds = 0;           // slab, footprint, columns, surface, limit
};

// The strategies are entries of contour_strategies() (contour_strategy.h).
using Strategies = std::span<const ContourStrategy* const>;

LayerAnalysis analyze_layer(const LayerStack& stack, std::size_t layer, Strategies strategies,
                            const AnalysisOptions& options = {});

std::vector<LayerAnalysis> analyze_layers(const LayerStack& stack, Strategies strategies,
                                          const AnalysisOptions& options = {},
                                          const std::function<void(std::size_t)>& progress = {});

// Volumes below this per layer (mm^3, a cube of 10 um) are rounding, not deviation: ratios to
// them mean nothing.
inline constexpr double kNegligibleVolume = 1e-6;

// A height range left out of a by-height judgement (the bunny's hole-filled base: 0 to 2.25
// mm); empty (lo >= hi) leaves out nothing.
struct ZRange {
  double lo = 0, hi = 0;  // mm
  bool empty() const { return !(hi > lo); }
};

// The weighted percentile: the least v among `values` such that the values <= v carry at
// least `share` percent of the total weight. Weights <= 0 (or NaN) count for nothing. NaN
// when no weight is positive or the spans differ in length. share is clamped to [0, 100];
// share 0 gives the least value of positive weight, 100 the largest.
double weighted_percentile(std::span<const double> values, std::span<const double> weights,
                           double share);

// The D within which layers covering `share` percent of the judged height stay: each layer
// weighted by its thickness outside `excluded` (a count of layers would favour plans of many
// thin layers), for strategy `strategy` (an index into each layer's strategies). NaN when no
// layer is judged.
double distance_percentile_by_height(std::span<const LayerAnalysis> layers, std::size_t strategy,
                                     double share = 95, ZRange excluded = {});

struct StrategySummary {
  const ContourStrategy* strategy = nullptr;
  std::size_t layers = 0;
  double mean_distance = 0, max_distance = 0;
  double p95_distance_by_height = 0;   // distance_percentile_by_height(.., 95, excluded)
  double mean_hausdorff = 0, max_hausdorff = 0;
  double total_deviation = 0, mean_deviation = 0;
  double total_limit = 0;
  double above_limit_percent = 0;      // (total ΔV - total limit) / total limit * 100; NaN
                                       // when the limit is negligible (vertical walls only)
  std::size_t missed_features = 0;
  std::size_t worse_than_lower = 0;    // layers with D above lower's (if lower was analysed)
  std::size_t worse_than_mid = 0;      // ... above mid's (if mid was analysed)
  double contour_seconds = 0;          // summed over layers (CPU time, not wall time)
  double max_contour_seconds = 0;      // the slowest layer
};

std::vector<StrategySummary> summarize(std::span<const LayerAnalysis> layers,
                                       double distance_tolerance = DistanceOptions{}.tolerance,
                                       ZRange excluded = {});

}  // namespace geometry
