// analyze and advise; see analyze.h.
#include "app/analyze.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/core.h>

#include "app/layer_boundaries.h"
#include "app/profile_paths.h"
#include "app/slice.h"
#include "geometry/core/error.h"
#include "geometry/mesh/stl_io.h"
#include "geometry/metrics/extruded_layers.h"
#include "geometry/plan/flat_levels.h"
#include "geometry/plan/layer_plan.h"
#include "geometry/slab/boundary_pair.h"
#include "geometry/slab/slab.h"

namespace app {

namespace {

using geometry::LayerAnalysis;
using geometry::StrategySummary;

// Reports progress and asks for cancellation: one label's run of work at a time.
class Reporter {
 public:
  explicit Reporter(const AnalysisEvents& events) : events_(events) {}

  void operator()(const std::string& label, std::size_t done, std::size_t total) const {
    if (events_.cancelled && events_.cancelled()) throw AnalysisCancelled();
    if (events_.progress) events_.progress(label, done, total);
  }
  void model_note(const std::string& line) const {
    if (events_.model_note) events_.model_note(line);
  }
  void layers_note(const std::string& line) const {
    if (events_.layers_note) events_.layers_note(line);
  }

 private:
  const AnalysisEvents& events_;
};

double part_height(const geometry::Mesh& mesh) {
  const geometry::Box3 box = geometry::bounding_box(mesh);
  return box.max.z - box.min.z;
}

geometry::Mesh load_model_noting(const ModelOptions& options, const Reporter& report) {
  LoadedModel model = load_model(options);
  for (const std::string& line : model_notes(options, model)) report.model_note(line);
  return std::move(model.mesh);
}

printer::PrinterProfile printer_profile(const std::string& name) {
  return printer::load_printer_profile(name, profile_search_path());
}

// Layers from --boundaries (any thicknesses; the part above the last top is not judged).
std::vector<geometry::Layer> boundary_layers_noting(const std::string& boundaries, double height,
                                                    const Reporter& report) {
  BoundaryLayers layers = boundary_layers(boundaries, height, std::numeric_limits<double>::infinity());
  for (const std::string& note : layers.notes) report.layers_note(note);
  return std::move(layers.layers);
}

// Uniform `layer` as `slice` lays them on the printer (its first layer, flat tops and floors
// on boundaries where its thicknesses reach them; for a thickness it lacks, any thickness from
// its thinnest to that one lands them), or with `from_zero` the plain grid from the bed.
std::vector<geometry::Layer> uniform_analysis_layers(double layer, bool from_zero,
                                                     const std::string& printer_name,
                                                     const geometry::Mesh& mesh, double height) {
  if (from_zero) return geometry::uniform_layers(height, layer);
  geometry::AllowedThicknesses allowed = allowed_thicknesses(printer_profile(printer_name));
  if (!allowed.allows(layer)) {
    allowed = {.listed = {}, .min = std::min(layer, allowed.thinnest()),
               .max = std::max(layer, allowed.thickest()), .step = 0, .first = allowed.first};
  }
  return geometry::uniform_plan(height, layer, allowed, geometry::flat_levels(mesh)).layers;
}

// The adaptive plan analyze and advise judge: for `printed`, on the printer's thicknesses
// (its first layer too).
LayerChoice adaptive_choice(const AdaptiveRequest& request, const std::string& printer_name,
                            const geometry::Mesh& mesh, double height,
                            const geometry::ContourStrategy& printed, const Reporter& report) {
  const printer::PrinterProfile profile = printer_profile(printer_name);
  const geometry::LayerStack index(mesh, {});
  const std::string label = "planning layers";
  report(label, 0, 0);
  return choose_layers(request, profile, index, height, 0, printed,
                       [&](std::size_t measured) { report(label, measured, 0); });
}

// Analyses every layer with the given strategies. Where only the distance error D is compared
// (advise, the thicker layers), `distance_only` leaves out the volume metrics and the reverse
// distance, a third of the work.
std::vector<LayerAnalysis> run_analysis(const geometry::LayerStack& stack, const Strategies& kinds,
                                        bool keep_regions, const std::string& label,
                                        const Reporter& report, bool distance_only = false) {
  geometry::AnalysisOptions options;
  options.keep_regions = keep_regions;
  if (distance_only) {
    options.metrics.volumes = false;
    options.metrics.distance.reverse = false;
  }
  report(label, 0, stack.size());
  return geometry::analyze_layers(stack, kinds, options,
                                  [&](std::size_t done) { report(label, done, stack.size()); });
}

// The share of `layers` (in percent) whose D of strategy k is within the benchmark's at the
// same heights: the largest D of the benchmark layers overlapping the layer (the worst the
// benchmark prints there), plus the distance tolerance.
double share_within(const std::vector<LayerAnalysis>& layers, std::size_t k,
                    const std::vector<LayerAnalysis>& benchmark, std::size_t bench_k) {
  if (layers.empty()) return 0;
  const double tolerance = geometry::DistanceOptions{}.tolerance;
  std::size_t within = 0, first = 0;
  for (const LayerAnalysis& layer : layers) {
    double limit = 0;
    while (first < benchmark.size() && benchmark[first].layer.z_hi <= layer.layer.z_lo) ++first;
    for (std::size_t b = first; b < benchmark.size() && benchmark[b].layer.z_lo < layer.layer.z_hi; ++b)
      limit = std::max(limit, benchmark[b].strategies[bench_k].metrics.distance);
    if (layer.strategies[k].metrics.distance <= limit + tolerance) ++within;
  }
  return 100.0 * within / layers.size();
}

// Each strategy against lower, and against mid (but lower and mid themselves).
std::vector<Comparison> comparisons_of(const std::vector<LayerAnalysis>& layers, const Strategies& kinds) {
  const int lower = strategy_index(kinds, "lower"), mid = strategy_index(kinds, "mid");
  std::vector<Comparison> comparisons;
  for (std::size_t k = 0; k < kinds.size(); ++k) {
    if (lower >= 0 && static_cast<int>(k) != lower)
      comparisons.push_back(compare(layers, k, static_cast<std::size_t>(lower)));
    if (mid >= 0 && static_cast<int>(k) != mid && static_cast<int>(k) != lower)
      comparisons.push_back(compare(layers, k, static_cast<std::size_t>(mid)));
  }
  return comparisons;
}

// The least ΔV any extruded layers can have, mm³: the layers' volume limits summed.
double total_volume_limit(const std::vector<LayerAnalysis>& layers) {
  double total = 0;
  for (const LayerAnalysis& layer : layers)
    if (!layer.strategies.empty()) total += layer.strategies[0].metrics.volume_limit;
  return total;
}

// Fig. 24-25: the medial-axis contour at thicker layers against lower at `layer`.
std::vector<ThickerLayers> thicker_ma(const AnalyzeRequest& request, const geometry::Mesh& mesh,
                                      double height, const std::vector<LayerAnalysis>& layers,
                                      std::size_t lower, const Reporter& report) {
  std::vector<ThickerLayers> thicker;
  const Strategies ma_only{&geometry::contour_strategy("ma")};
  for (double t : request.thicker) {
    if (std::abs(t - request.layer) < 1e-9) continue;
    const geometry::LayerStack stack(mesh, geometry::uniform_layers(height, t));
    ThickerLayers row;
    row.thickness = t;
    row.layers = run_analysis(stack, ma_only, false, fmt::format("ma at {:g} mm", t), report, true);
    row.within_percent = share_within(row.layers, 0, layers, lower);
    const std::vector<StrategySummary> summary = geometry::summarize(row.layers);
    if (!summary.empty()) {
      row.mean_distance = summary[0].mean_distance;
      row.max_distance = summary[0].max_distance;
    }
    thicker.push_back(std::move(row));
  }
  return thicker;
}

// The plan's printed contour at uniform layers of the printer's thinnest thickness and of the
// allowed one nearest the plan's mean after the first layer (about as many layers).
std::vector<UniformLayers> uniform_beside(const LayerChoice& plan, const geometry::ContourStrategy& printed,
                                          const std::string& printer_name, const geometry::Mesh& mesh,
                                          double height, const Reporter& report) {
  const geometry::AllowedThicknesses allowed = allowed_thicknesses(printer_profile(printer_name));
  const std::size_t count = plan.layers.size();
  double same = allowed.thinnest();
  if (count > 1) {
    const double mean = (plan.layers.back().z_hi - plan.layers.front().z_hi) / static_cast<double>(count - 1);
    for (double t = allowed.thinnest(); t <= allowed.thickest() + 1e-9;
         t += allowed.step > 0 ? allowed.step : 0.01) {
      if (allowed.allows(t) && std::abs(t - mean) < std::abs(same - mean)) same = t;
    }
  }
  const auto flats = geometry::flat_levels(mesh);
  const Strategies printed_only{&printed};
  std::vector<UniformLayers> uniform;
  for (double t : {allowed.thinnest(), same}) {
    if (!uniform.empty() && std::abs(t - allowed.thinnest()) < 1e-9) break;
    const geometry::LayerStack stack(mesh, geometry::uniform_plan(height, t, allowed, flats).layers);
    uniform.push_back({t, run_analysis(stack, printed_only, false,
                                       fmt::format("{} at {:g} mm", printed.name, t), report, true)});
  }
  return uniform;
}

LayerDrawing draw_layer(const geometry::LayerStack& stack, std::size_t index, const Strategies& kinds) {
  LayerDrawing drawing;
  drawing.index = index;
  drawing.layer = stack.layers()[index];
  drawing.analysis = geometry::analyze_layer(stack, index, kinds, geometry::AnalysisOptions{});
  drawing.footprint = geometry::slab_footprint(geometry::slab_of(stack, index));
  drawing.islands = geometry::boundary_pairs(drawing.footprint).size();
  return drawing;
}

// `export_kind`'s regions extruded between their layers' planes.
geometry::Mesh layered_part(const geometry::LayerStack& stack, const std::vector<LayerAnalysis>& layers,
                            std::size_t k) {
  std::vector<geometry::Region> regions;
  regions.reserve(layers.size());
  for (const LayerAnalysis& layer : layers) regions.push_back(layer.strategies[k].region);
  return geometry::extruded_layers(stack.layers(), regions);
}

// The strategies measured: the request's, then --contour's where the export or the plan
// needs it.
Strategies measured_strategies(const AnalyzeRequest& request) {
  Strategies kinds = request.strategies;
  const bool needs_contour = request.export_layers || request.adaptive.wanted();
  if (needs_contour && strategy_index(kinds, request.contour->name) < 0) kinds.push_back(request.contour);
  return kinds;
}

// The layers analyze judges (see AnalyzeRequest).
std::vector<geometry::Layer> analyzed_layers(const AnalyzeRequest& request, const geometry::Mesh& mesh,
                                             double height, std::optional<LayerChoice>& plan,
                                             const Reporter& report) {
  if (request.adaptive.wanted()) {
    plan = adaptive_choice(request.adaptive, request.printer, mesh, height, *request.contour, report);
    return plan->layers;
  }
  if (!request.boundaries.empty()) return boundary_layers_noting(request.boundaries, height, report);
  return uniform_analysis_layers(request.layer, request.from_zero, request.printer, mesh, height);
}

}  // namespace

Comparison compare(const std::vector<LayerAnalysis>& layers, std::size_t k, std::size_t b) {
  double per_layer = 0, lowest = 0, highest = 0;
  std::size_t counted = 0, better = 0, worse = 0, keeping = 0;
  const double tolerance = geometry::DistanceOptions{}.tolerance;
  for (const LayerAnalysis& layer : layers) {
    const auto& m = layer.strategies[k].metrics;
    const auto& base = layer.strategies[b].metrics;
    if (base.volume_deviation > geometry::kNegligibleVolume) {
      const double change = (m.volume_deviation - base.volume_deviation) / base.volume_deviation;
      per_layer += change;
      lowest = counted ? std::min(lowest, change) : change;
      highest = counted ? std::max(highest, change) : change;
      ++counted;
    }
    if (m.distance < base.distance - tolerance) ++better;
    if (m.distance > base.distance + tolerance) {
      ++worse;
      if (base.missed_features > m.missed_features) ++keeping;
    }
  }
  Comparison c;
  c.strategy = k;
  c.baseline = b;
  c.per_layer_change_percent = counted ? 100 * per_layer / counted : 0.0;
  c.least_change_percent = 100 * lowest;
  c.greatest_change_percent = 100 * highest;
  c.layers_compared = counted;
  c.distance_better = better;
  c.distance_worse = worse;
  c.distance_worse_keeping_features = keeping;
  // Below the distance metric's tolerance a D is zero; below a 10 um cube per layer a ΔV is.
  c.negligible_distance = tolerance;
  c.negligible_volume = geometry::kNegligibleVolume * static_cast<double>(layers.size());
  return c;
}

Strategies strategy_list(const std::vector<std::string>& names, const std::string& flag) {
  Strategies kinds;
  for (const std::string& name : names) {
    const geometry::ContourStrategy& kind = contour_strategy_option(name, flag);
    if (strategy_index(kinds, kind.name) < 0) kinds.push_back(&kind);
  }
  if (kinds.empty()) {
    throw geometry::InputError(fmt::format("{}: give at least one of {}", flag, geometry::contour_names()));
  }
  return kinds;
}

int strategy_index(const Strategies& strategies, std::string_view name) {
  for (std::size_t k = 0; k < strategies.size(); ++k)
    if (strategies[k]->name == name) return static_cast<int>(k);
  return -1;
}

AnalyzeResult analyze(const AnalyzeRequest& request, const AnalysisEvents& events) {
  const Reporter report(events);
  AnalyzeResult result;
  result.strategies = measured_strategies(request);
  const Strategies& kinds = result.strategies;
  const geometry::Mesh mesh = load_model_noting(request.model, report);
  result.height = part_height(mesh);
  result.model_volume = geometry::signed_volume(mesh);
  const geometry::LayerStack stack(mesh, analyzed_layers(request, mesh, result.height, result.plan, report));
  if (stack.size() == 0) {
    throw geometry::InputError(fmt::format("{}: the model has no height to slice", request.model.path));
  }
  result.layers = stack.layers();
  if (request.layer_index && *request.layer_index >= stack.size()) {
    throw geometry::InputError(fmt::format("--layer-index {}: the part has {} (indices 0 to {})",
                                           *request.layer_index, describe_layers(result.layers),
                                           stack.size() - 1));
  }

  result.analysis = run_analysis(stack, kinds, request.export_layers, "analyze", report);
  result.summaries =
      geometry::summarize(result.analysis, geometry::DistanceOptions{}.tolerance, request.excluded);
  result.volume_limit = total_volume_limit(result.analysis);
  result.comparisons = comparisons_of(result.analysis, kinds);
  if (const int lower = strategy_index(kinds, "lower"); lower >= 0) {
    result.thicker = thicker_ma(request, mesh, result.height, result.analysis,
                                static_cast<std::size_t>(lower), report);
  }
  if (result.plan && request.plan_beside_uniform) {
    result.uniform = uniform_beside(*result.plan, *request.contour, request.printer, mesh, result.height, report);
  }
  if (request.layer_index) result.drawing = draw_layer(stack, *request.layer_index, kinds);
  if (request.export_layers) {
    result.layered_part = layered_part(
        stack, result.analysis, static_cast<std::size_t>(strategy_index(kinds, request.contour->name)));
    result.layered_part_volume = geometry::signed_volume(*result.layered_part);
  }
  return result;
}

void write_stl(const geometry::Mesh& mesh, const std::string& path) { geometry::write_stl_binary(path, mesh); }

namespace {

// The printer's layer thicknesses, ascending: its list, or its range by its step.
std::vector<double> printer_thicknesses(const printer::PrinterProfile& profile) {
  const printer::LayerThicknesses& layer = profile.layer;
  if (!layer.allowed.empty()) {
    std::vector<double> values = layer.allowed;
    std::sort(values.begin(), values.end());
    return values;
  }
  if (!(layer.step > 0)) {
    throw geometry::InputError(fmt::format(
        "--printer {}: it allows any layer from {:g} to {:g} mm, not a list; give the "
        "thicknesses to compare with --thicknesses, e.g. --thicknesses 0.1,0.15,0.2",
        profile.name, layer.min, layer.max));
  }
  std::vector<double> values;
  for (int i = 0;; ++i) {
    const double t = layer.min + i * layer.step;
    if (t > layer.max + 1e-9) break;
    values.push_back(std::round(t * 1e6) / 1e6);
  }
  return values;
}

// The contour at `layers` against the benchmark.
AdviseRow advise_row(const geometry::LayerStack& stack, const std::vector<LayerAnalysis>& layers,
                     const std::vector<LayerAnalysis>& benchmark, std::size_t benchmark_layers) {
  const std::vector<StrategySummary> summary = geometry::summarize(layers);
  AdviseRow row;
  row.layers = stack.size();
  row.mean_distance = summary.empty() ? 0.0 : summary[0].mean_distance;
  row.max_distance = summary.empty() ? 0.0 : summary[0].max_distance;
  row.within_percent = share_within(layers, 0, benchmark, 0);
  row.fewer_layers_percent = 100.0 * (1.0 - static_cast<double>(stack.size()) / benchmark_layers);
  return row;
}

// --boundaries' or --adaptive's layers, judged as one more row.
void advise_plan(const AdviseRequest& request, const geometry::Mesh& mesh,
                 const std::vector<LayerAnalysis>& benchmark, AdviseResult& result, const Reporter& report) {
  const geometry::ContourStrategy& kind = *request.contour;
  if (request.adaptive.wanted()) {
    result.adaptive = adaptive_choice(request.adaptive, request.printer, mesh, result.height, kind, report);
  }
  const geometry::LayerStack stack(
      mesh, result.adaptive ? result.adaptive->layers
                            : boundary_layers_noting(request.boundaries, result.height, report));
  const auto layers = run_analysis(stack, {&kind}, false, fmt::format("{} at the boundaries", kind.name),
                                   report, true);
  result.plan = advise_row(stack, layers, benchmark, result.benchmark_layers);
  result.plan_layers = stack.layers();
}

}  // namespace

AdviseResult advise(const AdviseRequest& request, const AnalysisEvents& events) {
  const Reporter report(events);
  AdviseResult result;
  std::vector<double> thicknesses;
  if (request.thicknesses) {
    thicknesses = *request.thicknesses;
    result.thicknesses_from = "--thicknesses";
  } else {
    const printer::PrinterProfile profile = printer_profile(request.printer);
    thicknesses = printer_thicknesses(profile);
    result.thicknesses_from = fmt::format("{} ({})", profile.name, profile.layer.describe());
  }
  if (thicknesses.empty()) throw geometry::InputError("--thicknesses: give at least one thickness");

  const geometry::Mesh mesh = load_model_noting(request.model, report);
  result.height = part_height(mesh);
  result.benchmark_thickness = thicknesses.front();
  const geometry::LayerStack bench_stack(mesh, geometry::uniform_layers(result.height, result.benchmark_thickness));
  const auto benchmark = run_analysis(bench_stack, {&geometry::contour_strategy("lower")}, false,
                                      fmt::format("lower at {:g} mm", result.benchmark_thickness), report, true);
  result.benchmark_layers = bench_stack.size();
  if (const auto summary = geometry::summarize(benchmark); !summary.empty()) {
    result.benchmark_mean_distance = summary[0].mean_distance;
    result.benchmark_max_distance = summary[0].max_distance;
  }
  const geometry::ContourStrategy& kind = *request.contour;
  double best = 0;
  for (double t : thicknesses) {
    const geometry::LayerStack stack(mesh, geometry::uniform_layers(result.height, t));
    const auto layers =
        run_analysis(stack, {&kind}, false, fmt::format("{} at {:g} mm", kind.name, t), report, true);
    AdviseRow row = advise_row(stack, layers, benchmark, result.benchmark_layers);
    row.thickness = t;
    if (row.within_percent >= request.share) best = std::max(best, t);
    result.rows.push_back(row);
  }
  if (!request.boundaries.empty() || request.adaptive.wanted()) advise_plan(request, mesh, benchmark, result, report);
  if (best > 0) result.advised = best;
  return result;
}

}  // namespace app
