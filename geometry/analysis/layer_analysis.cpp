#include "geometry/analysis/layer_analysis.h"

#include <tbb/parallel_for.h>
#include <time.h>

#include <algorithm>
#include <cmath>
#include <utility>
#include <atomic>
#include <limits>
#include <string_view>


namespace geometry {

namespace {

// CPU time of the calling thread: what a layer costs, whatever else shares the cores.
double thread_seconds() {
  timespec now{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &now);
  return static_cast<double>(now.tv_sec) + 1e-9 * static_cast<double>(now.tv_nsec);
}

}  // namespace

LayerAnalysis analyze_layer(const LayerStack& stack, std::size_t layer, Strategies strategies,
                            const AnalysisOptions& options) {
  LayerAnalysis analysis;
  if (layer >= stack.size()) return analysis;
  analysis.layer = stack.layers()[layer];
  double start = thread_seconds();
  const LayerReference reference = layer_reference(stack, layer, options.metrics);
  analysis.reference_seconds = thread_seconds() - start;
  for (const ContourStrategy* strategy : strategies) {
    StrategyLayer result;
    result.strategy = strategy;
    start = thread_seconds();
    ContourResult made = strategy->contour({stack, layer, options.contour, &reference});
    result.region = std::move(made.region);
    result.height = made.height;
    result.contour_seconds = thread_seconds() - start;
    start = thread_seconds();
    result.metrics = layer_metrics(reference, result.region, options.metrics);
    result.metric_seconds = thread_seconds() - start;
    if (!options.keep_regions) result.region = {};
    analysis.strategies.push_back(std::move(result));
  }
  return analysis;
}

std::vector<LayerAnalysis> analyze_layers(const LayerStack& stack, Strategies strategies,
                                          const AnalysisOptions& options,
                                          const std::function<void(std::size_t)>& progress) {
  std::vector<LayerAnalysis> layers(stack.size());
  std::atomic<std::size_t> done{0};
  tbb::parallel_for(std::size_t{0}, stack.size(), [&](std::size_t i) {
    layers[i] = analyze_layer(stack, i, strategies, options);
    const std::size_t finished = ++done;
    if (progress) progress(finished);
  });
  return layers;
}

double weighted_percentile(std::span<const double> values, std::span<const double> weights,
                           double share) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  if (values.size() != weights.size()) return nan;
  std::vector<std::pair<double, double>> items;  // value, weight
  double total = 0;
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (!(weights[i] > 0) || std::isnan(values[i])) continue;
    items.emplace_back(values[i], weights[i]);
    total += weights[i];
  }
  if (items.empty()) return nan;
  std::sort(items.begin(), items.end());
  // Sums of thicknesses are not exact: a share reached within rounding is reached.
  const double wanted = std::clamp(std::isnan(share) ? 100.0 : share, 0.0, 100.0) / 100 * total *
                        (1 - 1e-12);
  double covered = 0;
  for (const auto& [value, weight] : items) {
    covered += weight;
    if (covered >= wanted) return value;
  }
  return items.back().first;
}

double distance_percentile_by_height(std::span<const LayerAnalysis> layers, std::size_t strategy,
                                     double share, ZRange excluded) {
  std::vector<double> values, weights;
  values.reserve(layers.size());
  weights.reserve(layers.size());
  for (const LayerAnalysis& layer : layers) {
    if (strategy >= layer.strategies.size()) continue;
    double weight = layer.layer.thickness();
    if (!excluded.empty()) {
      const double overlap = std::min(layer.layer.z_hi, excluded.hi) -
                             std::max(layer.layer.z_lo, excluded.lo);
      if (overlap > 0) weight -= overlap;
    }
    values.push_back(layer.strategies[strategy].metrics.distance);
    weights.push_back(weight);
  }
  return weighted_percentile(values, weights, share);
}

std::vector<StrategySummary> summarize(std::span<const LayerAnalysis> layers,
                                       double distance_tolerance, ZRange excluded) {
  std::vector<StrategySummary> summaries;
  if (layers.empty()) return summaries;
  const auto& first = layers.front().strategies;
  const auto index_of = [&](std::string_view name) -> int {
    for (std::size_t k = 0; k < first.size(); ++k)
      if (first[k].strategy->name == name) return static_cast<int>(k);
    return -1;
  };
  const int lower = index_of("lower"), mid = index_of("mid");
  for (std::size_t k = 0; k < first.size(); ++k) {
    StrategySummary s;
    s.strategy = first[k].strategy;
    for (const LayerAnalysis& layer : layers) {
      if (k >= layer.strategies.size()) continue;
      const StrategyLayer& r = layer.strategies[k];
      const LayerMetrics& m = r.metrics;
      ++s.layers;
      s.mean_distance += m.distance;
      s.max_distance = std::max(s.max_distance, m.distance);
      s.mean_hausdorff += m.hausdorff;
      s.max_hausdorff = std::max(s.max_hausdorff, m.hausdorff);
      s.total_deviation += m.volume_deviation;
      s.total_limit += m.volume_limit;
      s.missed_features += m.missed_features;
      s.contour_seconds += r.contour_seconds;
      s.max_contour_seconds = std::max(s.max_contour_seconds, r.contour_seconds);
      if (lower >= 0 && m.distance > layer.strategies[lower].metrics.distance + distance_tolerance)
        ++s.worse_than_lower;
      if (mid >= 0 && m.distance > layer.strategies[mid].metrics.distance + distance_tolerance)
        ++s.worse_than_mid;
    }
    if (s.layers > 0) {
      s.mean_distance /= s.layers;
      s.mean_hausdorff /= s.layers;
      s.mean_deviation = s.total_deviation / s.layers;
    }
    // A part of vertical walls has no limit to speak of (1e-13 mm^3): a percentage of it
    // would be noise, so there is none.
    s.p95_distance_by_height = distance_percentile_by_height(layers, k, 95, excluded);
    s.above_limit_percent = s.total_limit > kNegligibleVolume * s.layers
                                ? (s.total_deviation - s.total_limit) / s.total_limit * 100
                                : std::numeric_limits<double>::quiet_NaN();
    summaries.push_back(s);
  }
  return summaries;
}

}  // namespace geometry
