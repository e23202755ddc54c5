// `mahost analyze MODEL.stl [placement] [--layer 0.15 | --boundaries FILE|z1,z2,...]
//  [--contours lower,mid,optimal-height,ma] [--exclude-z LO:HI] [--csv F] [--json F]
//  [--plots DIR] [--thick 0.2,0.25] [--layer-index N] [--export-layers F.stl --contour K]`
// `mahost advise MODEL.stl [placement] [--printer up-plus-2] [--contour ma]
//  [--thicknesses 0.15,0.2,...] [--boundaries FILE|z1,z2,...] [--share 95] [--json F]`
//
// analyze (paper §4, Fig. 22-26): slices the model into uniform layers (or the layers of
// --boundaries: any plan, a peer's read from its G-code, no printer asked), makes each layer's
// region with every strategy asked for, measures each region (geometry/metrics/layer_metrics.h:
// ΔV exactly, D to 1 um over the whole surface, H's reverse direction at 5 heights)
// and prints one summary row per strategy, then how every strategy compares with lower (the
// paper's baseline) and with mid (what PrusaSlicer, Slic3r and CuraEngine print). Optional
// outputs: a CSV row per layer and strategy, a JSON summary, SVG charts (D per layer, ΔV per
// layer, the medial-axis contour at thicker layers against lower at this one), a drawing of
// one layer's contours, and the layered part as an STL.
//
// advise (paper §4): takes lower's distance error at the printer's thinnest layer as the
// benchmark and, for every layer thickness the printer allows, reports the share of the
// contour's layers whose D stays within the benchmark at the same heights, the layer count,
// and the largest thickness that keeps at least --share percent of layers within it. Advise
// compares thicknesses, so a plan of mixed ones (--boundaries) is one more row beside them,
// judged against the same benchmark, not a candidate for the advice.
#include <algorithm>
#include <atomic>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <memory>
#include <optional>
#include <numeric>
#include <sstream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <fmt/core.h>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "geometry/slab/boundary_pair.h"
#include "geometry/contour/contour_strategy.h"
#include "geometry/core/error.h"
#include "geometry/metrics/extruded_layers.h"
#include "geometry/analysis/layer_analysis.h"
#include "geometry/slicing/layer_stack.h"
#include "geometry/mesh/mesh.h"
#include "geometry/slab/slab.h"
#include "geometry/mesh/stl_io.h"
#include "geometry/plan/flat_levels.h"
#include "app/layer_boundaries.h"
#include "app/layer_choice.h"
#include "app/model.h"
#include "app/profile_paths.h"
#include "app/slice.h"
#include "app/slice_options.h"
#include "host/cli_checks.h"
#include "host/commands.h"
#include "host/plots.h"
#include "host/progress.h"
#include "host/slice_flags.h"
#include "printer/profile.h"

namespace host {
namespace {

using geometry::ContourStrategy;
using geometry::LayerAnalysis;
using geometry::StrategySummary;

struct AnalyzeOptions {
  app::ModelOptions model;
  double layer = 0.15;
  std::string boundaries;  // explicit layer tops instead of --layer
  std::string exclude_z;   // "LO:HI", mm: left out of the by-height percentile
  std::string contours = geometry::contour_names(",");  // all of them
  std::string csv, json, plots, export_layers;
  std::string contour = "best";  // for --export-layers, and the contour --adaptive plans for
  std::string thick = "0.2,0.25";
  int layer_index = -1;
  bool from_zero = false;          // --from-zero: uniform layers from the bed, no first layer
  app::AdaptiveRequest adaptive;   // --adaptive: the layers of a plan, not uniform
  std::string printer = printer::kDefaultPrinter;  // whose first layer and thicknesses the layers use
};

struct AdviseOptions {
  app::ModelOptions model;
  std::string boundaries;  // a layer plan to judge beside the uniform thicknesses
  std::string printer = printer::kDefaultPrinter;
  std::string contour = "ma";
  std::string thicknesses;
  double share = 95;
  std::string json;
  app::AdaptiveRequest adaptive;  // --adaptive: the plan as one more row
};

using Strategies = std::vector<const ContourStrategy*>;

std::string name_of(const ContourStrategy* strategy) { return std::string(strategy->name); }

std::vector<std::string> split_list(const std::string& text) {
  std::vector<std::string> items;
  std::stringstream stream(text);
  for (std::string item; std::getline(stream, item, ',');) {
    item.erase(0, item.find_first_not_of(" \t"));
    item.erase(item.find_last_not_of(" \t") + 1);
    if (!item.empty()) items.push_back(item);
  }
  return items;
}

std::vector<double> thickness_list(const std::string& text, const std::string& flag) {
  std::vector<double> values;
  for (const std::string& item : split_list(text)) {
    char* end = nullptr;
    const double v = std::strtod(item.c_str(), &end);
    if (end == item.c_str() || *end != '\0' || !std::isfinite(v) || !(v > 0) || v > 100) {
      throw geometry::InputError(fmt::format(
          "{}: '{}' is not a layer thickness in mm (give positive numbers, e.g. 0.15,0.2)", flag,
          item));
    }
    values.push_back(v);
  }
  std::sort(values.begin(), values.end());
  values.erase(std::unique(values.begin(), values.end(),
                           [](double a, double b) { return std::abs(a - b) < 1e-9; }),
               values.end());
  return values;
}

std::ofstream open_output(const std::string& path, const std::string& flag) {
  std::ofstream out(path);
  if (!out) {
    throw geometry::InputError(fmt::format("{} {}: cannot write this file; give a path in a "
                                           "directory you can write to",
                                           flag, path));
  }
  return out;
}

double part_height(const geometry::Mesh& mesh) {
  const geometry::Box3 box = geometry::bounding_box(mesh);
  return box.max.z - box.min.z;
}

// "0:2.25" -> [0, 2.25] mm.
geometry::ZRange parse_z_range(const std::string& text) {
  geometry::ZRange range;
  const std::size_t colon = text.find(':');
  bool fine = colon != std::string::npos;
  if (fine) {
    const std::string lo = text.substr(0, colon), hi = text.substr(colon + 1);
    char* end = nullptr;
    range.lo = std::strtod(lo.c_str(), &end);
    fine = !lo.empty() && *end == '\0';
    range.hi = std::strtod(hi.c_str(), &end);
    fine = fine && !hi.empty() && *end == '\0' && std::isfinite(range.lo) &&
           std::isfinite(range.hi) && range.hi > range.lo;
  }
  if (!fine) {
    throw geometry::InputError(fmt::format(
        "--exclude-z {}: give a height range LO:HI in mm with LO below HI, e.g. 0:2.25", text));
  }
  return range;
}

// The layers analyze judges: --boundaries (any thicknesses: a peer's plan need not suit our
// printer; the part above its last layer, if any, is not judged); else uniform --layer as
// `slice` lays them on --printer (its first layer, flat tops and floors on boundaries where its
// thicknesses reach them; for a thickness it lacks, any thickness from its thinnest to that one
// lands them); or with
// `from_zero` the plain grid from the bed, every layer --layer thick (the paper's comparison).
std::vector<geometry::Layer> analysis_layers(const std::string& boundaries, double layer,
                                             bool from_zero, const std::string& printer_name,
                                             const geometry::Mesh& mesh, double height) {
  if (!boundaries.empty()) {
    app::BoundaryLayers layers =
        app::boundary_layers(boundaries, height, std::numeric_limits<double>::infinity());
    for (const std::string& note : layers.notes) fmt::print(stderr, "{}\n", note);
    return std::move(layers.layers);
  }
  if (from_zero) return geometry::uniform_layers(height, layer);
  const printer::PrinterProfile profile =
      printer::load_printer_profile(printer_name, app::profile_search_path());
  geometry::AllowedThicknesses allowed = app::allowed_thicknesses(profile);
  if (!allowed.allows(layer)) {
    allowed = {.listed = {}, .min = std::min(layer, allowed.thinnest()),
               .max = std::max(layer, allowed.thickest()), .step = 0, .first = allowed.first};
  }
  return geometry::uniform_plan(height, layer, allowed, geometry::flat_levels(mesh)).layers;
}

// The adaptive plan analyze and advise judge: for `printed`, on the printer's thicknesses
// (its first layer too), with a progress line while it measures candidate layers.
app::LayerChoice adaptive_choice(const app::AdaptiveRequest& request, const std::string& printer_name,
                            const geometry::Mesh& mesh, double height,
                            const ContourStrategy& printed) {
  const printer::PrinterProfile profile =
      printer::load_printer_profile(printer_name, app::profile_search_path());
  const geometry::LayerStack index(mesh, {});
  Progress bar("planning layers", 0);
  app::LayerChoice choice = app::choose_layers(request, profile, index, height, 0, printed,
                                     [&](std::size_t measured) {
                                       bar.update(measured, fmt::format("{} candidate layers measured", measured));
                                     });
  bar.finish();
  return choice;
}

// Analyses every layer with the given strategies, with a progress line on stderr. Where only
// the distance error D is compared (advise, the thicker layers), `distance_only` leaves out the
// volume metrics and the reverse distance, a third of the work.
std::vector<LayerAnalysis> run_analysis(const geometry::LayerStack& stack,
                                        const Strategies& kinds, bool keep_regions,
                                        const std::string& label, bool distance_only = false) {
  geometry::AnalysisOptions options;
  options.keep_regions = keep_regions;
  if (distance_only) {
    options.metrics.volumes = false;
    options.metrics.distance.reverse = false;
  }
  Progress progress(label, stack.size());
  auto layers = geometry::analyze_layers(stack, kinds, options, [&](std::size_t done) {
    progress.update(done, fmt::format("layer {}/{}", done, stack.size()));
  });
  progress.finish();
  return layers;
}

// D of strategy k per layer, and the benchmark's D over the same heights: the largest D of the
// benchmark layers overlapping the layer (the worst the benchmark prints there). Returns the
// share of layers within it (D <= benchmark + tolerance), in percent.
double share_within(const std::vector<LayerAnalysis>& layers, std::size_t k,
                    const std::vector<LayerAnalysis>& benchmark, std::size_t bench_k,
                    double tolerance, std::vector<double>* limits = nullptr) {
  if (layers.empty()) return 0;
  std::size_t within = 0, first = 0;
  for (const LayerAnalysis& layer : layers) {
    double limit = 0;
    while (first < benchmark.size() && benchmark[first].layer.z_hi <= layer.layer.z_lo) ++first;
    for (std::size_t b = first; b < benchmark.size() && benchmark[b].layer.z_lo < layer.layer.z_hi; ++b)
      limit = std::max(limit, benchmark[b].strategies[bench_k].metrics.distance);
    if (limits) limits->push_back(limit);
    if (layer.strategies[k].metrics.distance <= limit + tolerance) ++within;
  }
  return 100.0 * within / layers.size();
}

int index_of(const Strategies& kinds, std::string_view name) {
  for (std::size_t k = 0; k < kinds.size(); ++k)
    if (kinds[k]->name == name) return static_cast<int>(k);
  return -1;
}

// x with its sign and `decimals` decimals, but a value that rounds to zero as plain zero
// ("0.0", never "-0.0" or "+0.0").
std::string signed_text(double x, int decimals) {
  const std::string text = fmt::format("{:+.{}f}", x, decimals);
  return text.find_first_not_of("+-0.") == std::string::npos ? text.substr(1) : text;
}

// How `value` compares with `base`: in percent of the baseline, or where the baseline is at
// most `negligible` (a distance error of 1e-15 mm on a part of vertical walls, whose lower
// contour is exact) as the absolute difference in `unit`, since a percentage of rounding noise
// says nothing.
std::string change_text(double value, double base, double negligible, const char* unit,
                        int decimals) {
  if (!(std::abs(base) > negligible)) {
    return fmt::format("{} {}", signed_text(value - base, decimals), unit);
  }
  return signed_text(100.0 * (value - base) / base, 1) + "%";
}

// The change in percent for the JSON, or null where change_text gives the absolute difference.
nlohmann::json percent_or_null(double value, double base, double negligible) {
  if (!(std::abs(base) > negligible)) return nullptr;
  return 100 * (value - base) / base;
}

// How strategy k compares with baseline b: one line of text and its figures.
nlohmann::json compare(const std::vector<LayerAnalysis>& layers,
                       const std::vector<StrategySummary>& summaries, std::size_t k,
                       std::size_t b) {
  double per_layer = 0, lowest = 0, highest = 0;
  std::size_t counted = 0, better = 0, worse = 0;
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
    if (m.distance > base.distance + tolerance) ++worse;
  }
  const StrategySummary& s = summaries[k];
  const StrategySummary& base = summaries[b];
  nlohmann::json j;
  j["strategy"] = name_of(s.strategy);
  j["baseline"] = name_of(base.strategy);
  // Below the distance metric's tolerance a D is zero; below a 10 um cube per layer a ΔV is.
  const double no_distance = tolerance;
  const double no_volume = geometry::kNegligibleVolume * static_cast<double>(layers.size());
  j["mean_distance_change_percent"] = percent_or_null(s.mean_distance, base.mean_distance, no_distance);
  j["max_distance_change_percent"] = percent_or_null(s.max_distance, base.max_distance, no_distance);
  j["total_deviation_change_percent"] =
      percent_or_null(s.total_deviation, base.total_deviation, no_volume);
  j["mean_distance_change"] = s.mean_distance - base.mean_distance;
  j["max_distance_change"] = s.max_distance - base.max_distance;
  j["total_deviation_change"] = s.total_deviation - base.total_deviation;
  j["per_layer_deviation_change_percent"] = counted ? 100 * per_layer / counted : 0.0;
  j["layers_compared_for_deviation"] = counted;
  j["per_layer_deviation_change_min_percent"] = 100 * lowest;
  j["per_layer_deviation_change_max_percent"] = 100 * highest;
  j["layers_distance_better"] = better;
  j["layers_distance_worse"] = worse;
  const std::string per_layer_text =
      counted ? fmt::format("ΔV per layer {}% on average ({}% to {}%)",
                            signed_text(100 * per_layer / counted, 1), signed_text(100 * lowest, 0),
                            signed_text(100 * highest, 0))
              : std::string("ΔV per layer: n/a (the baseline's is negligible)");
  fmt::print("{} vs {}: mean D {}, max D {}, total ΔV {}, {}; D better on {}, worse on {} of {} "
             "layers\n",
             name_of(s.strategy), name_of(base.strategy),
             change_text(s.mean_distance, base.mean_distance, no_distance, "mm", 4),
             change_text(s.max_distance, base.max_distance, no_distance, "mm", 4),
             change_text(s.total_deviation, base.total_deviation, no_volume, "mm³", 3),
             per_layer_text, better, worse, layers.size());
  return j;
}

Series per_layer_series(const std::vector<LayerAnalysis>& layers, std::size_t k, bool distance,
                        const std::string& title) {
  Series series;
  series.title = title;
  if (!layers.empty()) series.colour = layers[0].strategies[k].strategy->colour;
  for (const LayerAnalysis& layer : layers) {
    series.x.push_back(layer.layer.z_mid());
    const auto& m = layer.strategies[k].metrics;
    series.y.push_back(distance ? m.distance : m.volume_deviation);
  }
  return series;
}

// A few layers can be far off the rest (the bunny's hole-filled base: D up to 18 mm against
// 0.2 mm elsewhere) and squash every other point onto the axis: the y axis then stops at 1.5
// times the 98th percentile and the title says how many points it leaves out.
void fit_y_axis(Chart& chart) {
  std::vector<double> values;
  for (const Series& s : chart.series)
    for (double y : s.y)
      if (std::isfinite(y)) values.push_back(y);
  if (values.size() < 50) return;
  std::sort(values.begin(), values.end());
  const double cap = 1.5 * values[values.size() * 98 / 100];
  const auto above = static_cast<std::size_t>(
      values.end() - std::upper_bound(values.begin(), values.end(), cap));
  if (above == 0 || !(cap > 0)) return;
  chart.y_max = cap;
  chart.title += fmt::format(" ({} point{} above {:.3g} not shown)", above, above == 1 ? "" : "s", cap);
}

void draw_layer(const geometry::LayerStack& stack, std::size_t index,
                const Strategies& kinds, const std::string& path) {
  geometry::AnalysisOptions options;
  const LayerAnalysis analysis = geometry::analyze_layer(stack, index, kinds, options);
  const geometry::Slab slab = geometry::slab_of(stack, index);
  const geometry::Region footprint = geometry::slab_footprint(slab);
  std::vector<Outline> outlines;
  Outline pair{"boundary pair (slab footprint)", footprint.loops, "#888888", 4.0, false};
  outlines.push_back(pair);
  const geometry::Layer layer = stack.layers()[index];
  fmt::print("layer {} [{:.3f}, {:.3f}] mm: {} island(s)\n", index, layer.z_lo, layer.z_hi,
             geometry::boundary_pairs(footprint).size());
  for (const geometry::StrategyLayer& s : analysis.strategies) {
    Outline o{fmt::format("{} (D {:.3f} mm, ΔV {:.4f} mm³)", name_of(s.strategy),
                          s.metrics.distance, s.metrics.volume_deviation),
              s.region.loops, std::string(s.strategy->colour), 1.6, s.strategy->name == "lower"};
    outlines.push_back(o);
    fmt::print("  {:<15} area {:9.3f} mm²  ΔV {:8.4f} mm³ (limit {:.4f})  D {:.4f} mm  reverse "
               "{:.4f} mm  missed {}\n",
               name_of(s.strategy), s.metrics.area, s.metrics.volume_deviation,
               s.metrics.volume_limit, s.metrics.distance, s.metrics.reverse_distance,
               s.metrics.missed_features);
  }
  write_outlines_svg(path,
                     fmt::format("layer {} (z {:.3f} to {:.3f} mm): contours", index, layer.z_lo,
                                 layer.z_hi),
                     outlines);
  fmt::print("wrote {}\n", path);
}

// An adaptive plan beside uniform layers of the printer's thinnest thickness and of about as
// many layers: each layer's thickness against height (adaptive-thickness.svg) and the printed
// contour's D against height with the tolerance (adaptive-distance.svg).
template <typename PathOf>
void write_plan_charts(const app::LayerChoice& plan, const std::vector<LayerAnalysis>& layers,
                       const Strategies& kinds, const ContourStrategy& printed,
                       const std::string& printer_name, const geometry::Mesh& mesh, double height,
                       const PathOf& path_of) {
  const printer::PrinterProfile profile =
      printer::load_printer_profile(printer_name, app::profile_search_path());
  const geometry::AllowedThicknesses allowed = app::allowed_thicknesses(profile);
  const std::size_t count = plan.layers.size();
  double same = allowed.thinnest();
  if (count > 1) {
    // The allowed thickness nearest to the plan's mean after the first layer.
    const double mean = (plan.layers.back().z_hi - plan.layers.front().z_hi) / static_cast<double>(count - 1);
    for (double t = allowed.thinnest(); t <= allowed.thickest() + 1e-9;
         t += allowed.step > 0 ? allowed.step : 0.01) {
      if (allowed.allows(t) && std::abs(t - mean) < std::abs(same - mean)) same = t;
    }
  }
  const auto flats = geometry::flat_levels(mesh);
  const Strategies printed_only{&printed};
  Chart thickness{"Layer thickness: adaptive against uniform", "height, mm", "thickness, mm", {}};
  Chart distance{fmt::format("Distance error of {}: adaptive (D within {:.3g} mm) against uniform",
                             printed.name, plan.plan.tolerance),
                 "height, mm", "distance error D, mm", {}};
  const auto add = [&](const std::vector<LayerAnalysis>& judged, std::size_t k,
                       const std::string& title, const std::string& style,
                       const std::string& colour) {
    Series t{title, {}, {}, style == "points" ? "steps lw 2" : "lines lw 1", colour};
    for (const LayerAnalysis& layer : judged) {
      t.x.push_back(layer.layer.z_lo);
      t.y.push_back(layer.layer.thickness());
    }
    thickness.series.push_back(t);
    Series d = per_layer_series(judged, k, true, title);
    d.colour = colour;
    if (style != "points") d.style = "points pt 6 ps 0.4";
    distance.series.push_back(d);
  };
  add(layers, static_cast<std::size_t>(index_of(kinds, printed.name)),
      fmt::format("adaptive, {} layers", count), "points", "#d62728");
  const char* colours[] = {"#1f77b4", "#2ca02c"};
  int c = 0;
  for (double t : {allowed.thinnest(), same}) {
    if (c == 1 && std::abs(t - allowed.thinnest()) < 1e-9) break;
    const geometry::LayerStack uniform(mesh, geometry::uniform_plan(height, t, allowed, flats).layers);
    const auto judged = run_analysis(uniform, printed_only, false,
                                     fmt::format("{} at {:g} mm", printed.name, t), true);
    add(judged, 0, fmt::format("uniform {:g} mm, {} layers", t, uniform.size()), "lines", colours[c++]);
  }
  Series limit{fmt::format("tolerance {:.3g} mm", plan.plan.tolerance), {0, height},
               {plan.plan.tolerance, plan.plan.tolerance}, "lines lw 1 dt 2", "#000000"};
  distance.series.push_back(limit);
  fit_y_axis(distance);
  write_chart_svg(path_of("adaptive-thickness.svg"), thickness);
  write_chart_svg(path_of("adaptive-distance.svg"), distance);
  fmt::print("wrote {}, {}\n", path_of("adaptive-thickness.svg"), path_of("adaptive-distance.svg"));
}

// The strategies --contours names, each once.
Strategies listed_strategies(const AnalyzeOptions& options) {
  Strategies kinds;
  for (const std::string& name : split_list(options.contours)) {
    const ContourStrategy& kind = app::contour_strategy_option(name, "--contours");
    if (index_of(kinds, kind.name) < 0) kinds.push_back(&kind);
  }
  if (kinds.empty()) {
    throw geometry::InputError(
        fmt::format("--contours: give at least one of {}", geometry::contour_names()));
  }
  return kinds;
}

void make_plots_folder(const std::string& plots) {
  std::error_code error;
  std::filesystem::create_directories(plots, error);
  if (error || !std::filesystem::is_directory(plots)) {
    throw geometry::InputError(fmt::format(
        "--plots {}: cannot create this directory ({}); give one you can write to", plots,
        error ? error.message() : "not a directory"));
  }
}

// The least ΔV any extruded layers can have, mm³: the layers' volume limits summed.
double total_volume_limit(const std::vector<LayerAnalysis>& layers) {
  double total = 0;
  for (const LayerAnalysis& layer : layers)
    if (!layer.strategies.empty()) total += layer.strategies[0].metrics.volume_limit;
  return total;
}

double ms_per_layer(const StrategySummary& s) {
  return 1e3 * s.contour_seconds / std::max<std::size_t>(s.layers, 1);
}

// The table of the strategies' summaries, its legend, and optimal-height's time per slice.
void print_summary_table(const std::vector<StrategySummary>& summaries, const Strategies& kinds,
                         const geometry::ZRange& excluded) {
  fmt::print("{:<15} {:>8} {:>8} {:>8} {:>8} {:>10} {:>9} {:>9} {:>7} {:>7} {:>5} {:>10}\n",
             "strategy", "mean D", "max D", "P95h D", "mean H", "total ΔV", "mean ΔV", "ΔV>limit",
             "missed", ">lower", ">mid", "ms/layer");
  const int lower = index_of(kinds, "lower"), mid = index_of(kinds, "mid");
  for (const StrategySummary& s : summaries) {
    fmt::print("{:<15} {:8.4f} {:8.4f} {:8.4f} {:8.4f} {:10.3f} {:9.5f} {:>9} {:7} {:>7} {:>5} "
               "{:10.2f}\n",
               name_of(s.strategy), s.mean_distance, s.max_distance, s.p95_distance_by_height,
               s.mean_hausdorff,
               s.total_deviation, s.mean_deviation,
               std::isnan(s.above_limit_percent) ? std::string("n/a")
                                                 : fmt::format("{:.1f}%", s.above_limit_percent),
               s.missed_features,
               lower >= 0 ? std::to_string(s.worse_than_lower) : "-",
               mid >= 0 ? std::to_string(s.worse_than_mid) : "-",
               ms_per_layer(s));
  }
  fmt::print("(D: distance error surface to walls, H: Hausdorff, mm; P95h D: the D within which "
             "layers covering 95% of the height stay{}; ΔV mm³; >lower, >mid: layers whose D "
             "exceeds that strategy's; ms/layer: CPU time to make the contour)\n",
             excluded.empty() ? std::string()
                              : fmt::format(", z {:g} to {:g} mm left out", excluded.lo, excluded.hi));
}

// Each strategy against lower, and against mid (but lower and mid themselves), as compare()
// prints and returns them.
nlohmann::json comparisons_of(const std::vector<LayerAnalysis>& layers,
                              const std::vector<StrategySummary>& summaries, const Strategies& kinds) {
  const int lower = index_of(kinds, "lower"), mid = index_of(kinds, "mid");
  nlohmann::json comparisons = nlohmann::json::array();
  for (std::size_t k = 0; k < kinds.size(); ++k) {
    if (lower >= 0 && static_cast<int>(k) != lower)
      comparisons.push_back(compare(layers, summaries, k, static_cast<std::size_t>(lower)));
    if (mid >= 0 && static_cast<int>(k) != mid && static_cast<int>(k) != lower)
      comparisons.push_back(compare(layers, summaries, k, static_cast<std::size_t>(mid)));
  }
  const int optimal = index_of(kinds, "optimal-height");
  if (optimal >= 0) {
    fmt::print("optimal-height: {:.1f} ms per slice on one core (the paper's CATIA search: about "
               "90 s per slice)\n",
               ms_per_layer(summaries[optimal]));
  }
  return comparisons;
}

void write_layers_csv(const std::string& path, const std::vector<LayerAnalysis>& layers,
                      std::size_t strategies) {
  std::ofstream out = open_output(path, "--csv");
  out << "layer,strategy,z_lo,thickness,height,area,volume_deviation,volume_limit,distance,"
         "reverse_distance,hausdorff,missed_features,contour_ms\n";
  for (std::size_t i = 0; i < layers.size(); ++i) {
    for (const geometry::StrategyLayer& s : layers[i].strategies) {
      const auto& m = s.metrics;
      out << fmt::format("{},{},{:.6f},{:.6f},{:.6f},{:.6f},{:.12g},{:.12g},{:.6f},{:.6f},{:.6f},{},{:.3f}\n",
                         i, name_of(s.strategy), m.z_lo, m.thickness, s.height, m.area,
                         m.volume_deviation, m.volume_limit, m.distance, m.reverse_distance,
                         m.hausdorff, m.missed_features, 1e3 * s.contour_seconds);
    }
  }
  if (!out) throw geometry::InputError(fmt::format("--csv {}: writing failed", path));
  fmt::print("wrote {}: {} rows\n", path, layers.size() * strategies);
}

// Fig. 24-25: the medial-axis contour at thicker layers against lower at this thickness, a
// line and a chart each.
nlohmann::json thicker_ma(const AnalyzeOptions& options, const std::vector<double>& thick,
                          const geometry::Mesh& mesh, double height,
                          const std::vector<LayerAnalysis>& layers, std::size_t lower) {
  nlohmann::json thicker = nlohmann::json::array();
  const Strategies ma_only{&geometry::contour_strategy("ma")};
  for (double t : thick) {
    if (std::abs(t - options.layer) < 1e-9) continue;
    const geometry::LayerStack thick_stack(mesh, geometry::uniform_layers(height, t));
    const auto thick_layers =
        run_analysis(thick_stack, ma_only, false, fmt::format("ma at {:g} mm", t), true);
    std::vector<double> limits;
    const double share = share_within(thick_layers, 0, layers, lower,
                                      geometry::DistanceOptions{}.tolerance, &limits);
    const auto thick_summary = geometry::summarize(thick_layers);
    fmt::print("ma at {:g} mm: {} layers, mean D {:.4f} mm, max D {:.4f} mm; D within lower's at "
               "{:g} mm on {:.1f}% of layers\n",
               t, thick_stack.size(), thick_summary[0].mean_distance,
               thick_summary[0].max_distance, options.layer, share);
    thicker.push_back({{"thickness", t},
                       {"layers", thick_stack.size()},
                       {"mean_distance", thick_summary[0].mean_distance},
                       {"max_distance", thick_summary[0].max_distance},
                       {"within_benchmark_percent", share}});
    Chart chart{fmt::format("Distance error: lower ({:g} mm) vs MA ({:g} mm)", options.layer, t),
                "height, mm", "distance error D, mm", {}};
    chart.series.push_back(per_layer_series(layers, lower, true,
                                            fmt::format("lower, {:g} mm", options.layer)));
    chart.series.push_back(per_layer_series(thick_layers, 0, true, fmt::format("ma, {:g} mm", t)));
    const std::string path = (std::filesystem::path(options.plots) /
                              fmt::format("distance-lower-{:g}-vs-ma-{:g}.svg", options.layer, t))
                                 .string();
    fit_y_axis(chart);
    write_chart_svg(path, chart);
    fmt::print("wrote {}\n", path);
  }
  return thicker;
}

// The charts of --plots: D and ΔV per layer of every strategy, the plan's, and Fig. 22's pairs
// (lower and mid each against the medial-axis contour).
void write_layer_charts(const AnalyzeOptions& options, const std::vector<LayerAnalysis>& layers,
                        const Strategies& kinds, const std::optional<app::LayerChoice>& plan,
                        const ContourStrategy& export_kind, const geometry::Mesh& mesh, double height) {
  const auto path_of = [&](const std::string& name) {
    return (std::filesystem::path(options.plots) / name).string();
  };
  const std::string at =
      plan ? std::string("of the adaptive plan") : fmt::format("at {:g} mm", options.layer);
  Chart all{fmt::format("Distance error per layer {}", at), "height, mm",
            "distance error D, mm", {}};
  Chart volume{fmt::format("Volume deviation per layer {}", at), "height, mm",
               "volume deviation, mm³", {}};
  for (std::size_t k = 0; k < kinds.size(); ++k) {
    all.series.push_back(per_layer_series(layers, k, true, name_of(kinds[k])));
    volume.series.push_back(per_layer_series(layers, k, false, name_of(kinds[k])));
  }
  Series limit{"volume limit", {}, {}, "lines lw 1", "#000000"};
  for (const LayerAnalysis& layer : layers) {
    limit.x.push_back(layer.layer.z_mid());
    limit.y.push_back(layer.strategies[0].metrics.volume_limit);
  }
  volume.series.push_back(limit);
  fit_y_axis(all);
  fit_y_axis(volume);
  write_chart_svg(path_of("distance.svg"), all);
  write_chart_svg(path_of("volume.svg"), volume);
  fmt::print("wrote {}, {}\n", path_of("distance.svg"), path_of("volume.svg"));
  if (plan) write_plan_charts(*plan, layers, kinds, export_kind, options.printer, mesh, height, path_of);
  const int lower = index_of(kinds, "lower"), mid = index_of(kinds, "mid");
  const int ma = index_of(kinds, "ma");
  for (int base : {lower, mid}) {
    if (base < 0 || ma < 0) continue;
    Chart pair{fmt::format("Distance error: {} vs ma at {:g} mm", name_of(kinds[base]), options.layer),
               "height, mm", "distance error D, mm", {}};
    pair.series.push_back(per_layer_series(layers, static_cast<std::size_t>(base), true, name_of(kinds[base])));
    pair.series.push_back(per_layer_series(layers, static_cast<std::size_t>(ma), true, "ma"));
    const std::string path = path_of(fmt::format("distance-{}-vs-ma.svg", name_of(kinds[base])));
    fit_y_axis(pair);
    write_chart_svg(path, pair);
    fmt::print("wrote {}\n", path);
  }
}

// --export-layers: the regions of `export_kind` extruded between their layers' planes, as STL.
void export_layered_part(const AnalyzeOptions& options, const geometry::LayerStack& stack,
                         const std::vector<LayerAnalysis>& layers, const Strategies& kinds,
                         const ContourStrategy& export_kind, const geometry::Mesh& mesh) {
  const std::size_t k = static_cast<std::size_t>(index_of(kinds, export_kind.name));
  std::vector<geometry::Region> regions;
  regions.reserve(layers.size());
  for (const LayerAnalysis& layer : layers) regions.push_back(layer.strategies[k].region);
  const geometry::Mesh extruded = geometry::extruded_layers(stack.layers(), regions);
  geometry::write_stl_binary(options.export_layers, extruded);
  fmt::print("wrote {}: the layered part of {} ({} layers, {} triangles, {:.2f} mm³; model "
             "{:.2f} mm³)\n",
             options.export_layers, export_kind.name, layers.size(), extruded.faces.size(),
             geometry::signed_volume(extruded), geometry::signed_volume(mesh));
}

// What --json writes: the part, its layers, the summaries, comparisons and thicker MA.
struct AnalysisReport {
  double height = 0;
  std::size_t layer_count = 0;
  geometry::ZRange excluded;
  double volume_limit = 0;
  nlohmann::json comparisons, thicker;
};

void write_analysis_json(const AnalyzeOptions& options, const AnalysisReport& report,
                         const std::vector<LayerAnalysis>& layers,
                         const std::vector<StrategySummary>& summaries) {
  nlohmann::json j;
  j["model"] = options.model.path;
  j["height"] = report.height;
  j["layer_thickness"] = options.boundaries.empty() ? nlohmann::json(options.layer)
                                                    : nlohmann::json(nullptr);
  if (!options.boundaries.empty()) j["boundaries"] = options.boundaries;
  j["layers"] = report.layer_count;
  double thinnest = layers.front().layer.thickness(), thickest = thinnest;
  for (const LayerAnalysis& layer : layers) {
    thinnest = std::min(thinnest, layer.layer.thickness());
    thickest = std::max(thickest, layer.layer.thickness());
  }
  j["layer_thickness_min"] = thinnest;
  j["layer_thickness_max"] = thickest;
  j["layers_top"] = layers.empty() ? 0.0 : layers.back().layer.z_hi;
  j["percentile_excluded_z"] = report.excluded.empty()
                                   ? nlohmann::json(nullptr)
                                   : nlohmann::json::array({report.excluded.lo, report.excluded.hi});
  j["volume_limit"] = report.volume_limit;
  j["strategies"] = nlohmann::json::array();
  const auto number_or_null = [](double v) {
    return std::isnan(v) ? nlohmann::json(nullptr) : nlohmann::json(v);
  };
  for (const StrategySummary& s : summaries) {
    j["strategies"].push_back({{"strategy", name_of(s.strategy)},
                               {"mean_distance", s.mean_distance},
                               {"max_distance", s.max_distance},
                               {"p95_distance_by_height", number_or_null(s.p95_distance_by_height)},
                               {"mean_hausdorff", s.mean_hausdorff},
                               {"max_hausdorff", s.max_hausdorff},
                               {"total_volume_deviation", s.total_deviation},
                               {"mean_volume_deviation", s.mean_deviation},
                               {"above_limit_percent", number_or_null(s.above_limit_percent)},
                               {"missed_features", s.missed_features},
                               {"layers_worse_than_lower", s.worse_than_lower},
                               {"layers_worse_than_mid", s.worse_than_mid},
                               {"contour_ms_per_layer", ms_per_layer(s)}});
  }
  j["comparisons"] = report.comparisons;
  j["thicker_ma"] = report.thicker;
  std::ofstream out = open_output(options.json, "--json");
  out << j.dump(2) << "\n";
  if (!out) throw geometry::InputError(fmt::format("--json {}: writing failed", options.json));
  fmt::print("wrote {}\n", options.json);
}

void run_analyze(const AnalyzeOptions& options) {
  Strategies kinds = listed_strategies(options);
  // --contour's strategy is measured too where --export-layers or --adaptive needs it.
  const bool exporting = !options.export_layers.empty();
  const ContourStrategy& export_kind = app::contour_strategy_option(options.contour, "--contour");
  if ((exporting || options.adaptive.wanted()) && index_of(kinds, export_kind.name) < 0) {
    kinds.push_back(&export_kind);
  }
  const std::vector<double> thick = options.plots.empty() ? std::vector<double>{}
                                                          : thickness_list(options.thick, "--thick");
  if (!options.plots.empty()) make_plots_folder(options.plots);

  AnalysisReport report;
  report.excluded = options.exclude_z.empty() ? geometry::ZRange{} : parse_z_range(options.exclude_z);
  const geometry::Mesh mesh = load_model_noting(options.model);
  report.height = part_height(mesh);
  std::optional<app::LayerChoice> plan;
  if (options.adaptive.wanted()) {
    plan = adaptive_choice(options.adaptive, options.printer, mesh, report.height, export_kind);
  }
  const geometry::LayerStack stack(
      mesh, plan ? plan->layers
                 : analysis_layers(options.boundaries, options.layer, options.from_zero,
                                   options.printer, mesh, report.height));
  if (stack.size() == 0) {
    throw geometry::InputError(fmt::format("{}: the model has no height to slice",
                                           options.model.path));
  }
  report.layer_count = stack.size();
  const std::string layers_text = app::describe_layers(stack.layers());
  if (options.layer_index >= static_cast<int>(stack.size())) {
    throw geometry::InputError(fmt::format("--layer-index {}: the part has {} (indices 0 to {})",
                                           options.layer_index, layers_text, stack.size() - 1));
  }

  const std::vector<LayerAnalysis> layers = run_analysis(stack, kinds, exporting, "analyze");
  const std::vector<StrategySummary> summaries =
      geometry::summarize(layers, geometry::DistanceOptions{}.tolerance, report.excluded);
  report.volume_limit = total_volume_limit(layers);
  fmt::print("{}: {:.2f} mm tall, {}; volume limit {:.3f} mm³ (the least ΔV any extruded "
             "layers can have)\n",
             options.model.path, report.height, layers_text, report.volume_limit);
  if (plan) fmt::print("{}\n", app::describe_choice(*plan));
  print_summary_table(summaries, kinds, report.excluded);
  report.comparisons = comparisons_of(layers, summaries, kinds);
  if (!options.csv.empty()) write_layers_csv(options.csv, layers, kinds.size());
  report.thicker = nlohmann::json::array();
  const int lower = index_of(kinds, "lower");
  if (!thick.empty() && lower >= 0) {
    report.thicker = thicker_ma(options, thick, mesh, report.height, layers, static_cast<std::size_t>(lower));
  }
  if (!options.plots.empty()) {
    write_layer_charts(options, layers, kinds, plan, export_kind, mesh, report.height);
  }
  if (options.layer_index >= 0) {
    const std::string name = fmt::format("layer-{}.svg", options.layer_index);
    const std::string path = options.plots.empty()
                                 ? name
                                 : (std::filesystem::path(options.plots) / name).string();
    draw_layer(stack, static_cast<std::size_t>(options.layer_index), kinds, path);
  }
  if (exporting) export_layered_part(options, stack, layers, kinds, export_kind, mesh);
  if (!options.json.empty()) write_analysis_json(options, report, layers, summaries);
}

std::vector<double> allowed_thicknesses(const printer::PrinterProfile& profile) {
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

void run_advise(const AdviseOptions& options) {
  const ContourStrategy* kind = &app::contour_strategy_option(options.contour, "--contour");
  std::vector<double> thicknesses;
  std::string source;
  if (!options.thicknesses.empty()) {
    thicknesses = thickness_list(options.thicknesses, "--thicknesses");
    source = "--thicknesses";
  } else {
    const printer::PrinterProfile profile = printer::load_printer_profile(
        options.printer, app::profile_search_path());
    thicknesses = allowed_thicknesses(profile);
    source = fmt::format("{} ({})", profile.name, profile.layer.describe());
  }
  if (thicknesses.empty()) throw geometry::InputError("--thicknesses: give at least one thickness");

  const geometry::Mesh mesh = load_model_noting(options.model);
  const double height = part_height(mesh);
  const double thinnest = thicknesses.front();
  const geometry::LayerStack bench_stack(mesh, geometry::uniform_layers(height, thinnest));
  const Strategies bench_kinds{&geometry::contour_strategy("lower")};
  const auto benchmark = run_analysis(bench_stack, bench_kinds, false,
                                      fmt::format("lower at {:g} mm", thinnest), true);
  const auto bench_summary = geometry::summarize(benchmark);
  fmt::print("{}: {:.2f} mm tall; thicknesses from {}\n", options.model.path, height, source);
  fmt::print("benchmark: lower at {:g} mm, {} layers, mean D {:.4f} mm, max D {:.4f} mm\n",
             thinnest, bench_stack.size(), bench_summary.empty() ? 0.0 : bench_summary[0].mean_distance,
             bench_summary.empty() ? 0.0 : bench_summary[0].max_distance);
  fmt::print("{:>9} {:>7} {:>8} {:>8} {:>8} {:>12}\n", "thickness", "layers", "mean D", "max D",
             "within", "fewer layers");
  nlohmann::json rows = nlohmann::json::array();
  double best = 0;
  const Strategies kinds{kind};
  for (double t : thicknesses) {
    const geometry::LayerStack stack(mesh, geometry::uniform_layers(height, t));
    const auto layers =
        run_analysis(stack, kinds, false, fmt::format("{} at {:g} mm", name_of(kind), t), true);
    const auto summary = geometry::summarize(layers);
    const double share = share_within(layers, 0, benchmark, 0, geometry::DistanceOptions{}.tolerance);
    const double saving = 100.0 * (1.0 - static_cast<double>(stack.size()) / bench_stack.size());
    fmt::print("{:>7.3g}mm {:7} {:8.4f} {:8.4f} {:7.1f}% {:11.1f}%\n", t, stack.size(),
               summary.empty() ? 0.0 : summary[0].mean_distance,
               summary.empty() ? 0.0 : summary[0].max_distance, share, saving);
    if (share >= options.share) best = std::max(best, t);
    rows.push_back({{"thickness", t},
                    {"layers", stack.size()},
                    {"mean_distance", summary.empty() ? 0.0 : summary[0].mean_distance},
                    {"max_distance", summary.empty() ? 0.0 : summary[0].max_distance},
                    {"within_benchmark_percent", share},
                    {"fewer_layers_percent", saving}});
  }
  // A layer plan (--boundaries) is judged as one more row, against the same benchmark.
  nlohmann::json plan_row(nullptr);
  const bool adaptive = options.adaptive.wanted();
  if (!options.boundaries.empty() || adaptive) {
    std::optional<app::LayerChoice> plan;
    if (adaptive) plan = adaptive_choice(options.adaptive, options.printer, mesh, height, *kind);
    const geometry::LayerStack stack(
        mesh, plan ? plan->layers : analysis_layers(options.boundaries, 0, true, options.printer, mesh, height));
    const auto layers = run_analysis(stack, kinds, false,
                                     fmt::format("{} at the boundaries", name_of(kind)), true);
    const auto summary = geometry::summarize(layers);
    const double share = share_within(layers, 0, benchmark, 0, geometry::DistanceOptions{}.tolerance);
    const double saving = 100.0 * (1.0 - static_cast<double>(stack.size()) / bench_stack.size());
    fmt::print("{:>9} {:7} {:8.4f} {:8.4f} {:7.1f}% {:11.1f}%   ({})\n",
               plan ? "adaptive" : "plan", stack.size(),
               summary.empty() ? 0.0 : summary[0].mean_distance,
               summary.empty() ? 0.0 : summary[0].max_distance, share, saving,
               app::describe_layers(stack.layers()));
    if (plan) fmt::print("          {}\n", app::describe_choice(*plan));
    plan_row = {{"boundaries", plan ? std::string("adaptive") : options.boundaries},
                {"tolerance", plan ? nlohmann::json(plan->plan.tolerance) : nlohmann::json(nullptr)},
                {"layers", stack.size()},
                {"mean_distance", summary.empty() ? 0.0 : summary[0].mean_distance},
                {"max_distance", summary.empty() ? 0.0 : summary[0].max_distance},
                {"within_benchmark_percent", share},
                {"fewer_layers_percent", saving}};
  }
  if (best > 0) {
    fmt::print("advice: {} at {:g} mm keeps at least {:g}% of layers within lower's distance error "
               "at {:g} mm\n",
               name_of(kind), best, options.share, thinnest);
  } else {
    fmt::print("advice: no thickness keeps {:g}% of {}'s layers within lower's distance error at "
               "{:g} mm; print at {:g} mm\n",
               options.share, name_of(kind), thinnest, thinnest);
  }
  if (!options.json.empty()) {
    nlohmann::json j{{"model", options.model.path},
                     {"contour", name_of(kind)},
                     {"benchmark_thickness", thinnest},
                     {"share_required_percent", options.share},
                     {"thicknesses", rows},
                     {"plan", plan_row},
                     {"advised_thickness", best > 0 ? nlohmann::json(best) : nlohmann::json(nullptr)}};
    std::ofstream out = open_output(options.json, "--json");
    out << j.dump(2) << "\n";
    if (!out) throw geometry::InputError(fmt::format("--json {}: writing failed", options.json));
  }
}

}  // namespace

void add_analyze_command(CLI::App& app) {
  auto options = std::make_shared<AnalyzeOptions>();
  CLI::App* analyze = app.add_subcommand(
      "analyze",
      "Compare contour strategies layer by layer: exact volume deviation, distance error "
      "(the paper's D, to 1 um; reverse and Hausdorff, sampled at 5 heights a layer), the "
      "volume limit, missed features; CSV, JSON, SVG plots, a layer's contours, the layered "
      "part as STL.");
  add_model_options(*analyze, options->model);
  CLI::Option* layer = analyze->add_option("--layer", options->layer, "layer thickness, mm")
                           ->check(positive_number())
                           ->capture_default_str();
  CLI::Option* from_zero = analyze->add_flag(
      "--from-zero", options->from_zero,
      "uniform layers from the bed, every one --layer thick, with no first layer of the "
      "printer's and no flat level landed (the paper's comparison; default: the layers `slice` "
      "prints at --layer on --printer)");
  analyze->add_option("--boundaries", options->boundaries,
                      "judge these layers instead of --layer: layer tops as a comma list in mm "
                      "(0.3,0.5,...), a file with one top per line (# comments), or a G-code file "
                      "of CuraEngine, PrusaSlicer, Slic3r or mahost, whose layer heights are "
                      "used; any thicknesses (no printer is checked)")
      ->excludes(layer);
  analyze->add_option("--exclude-z", options->exclude_z,
                      "leave this height range out of the by-height 95th percentile of D "
                      "(P95h D), LO:HI in mm, e.g. 0:2.25 for the bunny's hole-filled base "
                      "(default: none)");
  analyze->add_option("--contours", options->contours,
                      fmt::format("strategies to compare, comma-separated: {}",
                                  app::contour_strategies_help()))
      ->capture_default_str();
  analyze->add_option("--csv", options->csv, "write one row per layer and strategy to this CSV file");
  analyze->add_option("--json", options->json, "write the summary to this JSON file");
  analyze->add_option("--plots", options->plots,
                      "write SVG charts (needs gnuplot) into this directory: D and ΔV per layer, "
                      "lower and mid against ma, ma at the --thick layers against lower");
  analyze->add_option("--thick", options->thick,
                      "with --plots: thicker layers for ma to compare with lower at --layer, mm")
      ->capture_default_str();
  analyze->add_option("--layer-index", options->layer_index,
                      "draw this layer's footprint and contours as layer-N.svg (in --plots, or "
                      "here) and print its metrics")
      ->check(non_negative_number());
  analyze->add_option("--export-layers", options->export_layers,
                      "write the layered part (each layer's region extruded) as an STL file");
  from_zero->excludes("--boundaries");
  for (CLI::Option* option : add_adaptive_options(*analyze, options->adaptive)) {
    option->excludes("--layer")->excludes("--boundaries")->excludes(from_zero);
  }
  analyze->add_option("--printer", options->printer,
                      fmt::format("the printer whose first layer and thicknesses the layers "
                                  "use, uniform or --adaptive (default: {})",
                                  printer::kDefaultPrinter));
  analyze->add_option("--contour", options->contour,
                      fmt::format("with --export-layers: which strategy's layers; with "
                                  "--adaptive: the contour the plan is made for ({})",
                                  geometry::contour_names()))
      ->capture_default_str();
  analyze->callback([options] { run_analyze(*options); });

  auto advise_options = std::make_shared<AdviseOptions>();
  CLI::App* advise = app.add_subcommand(
      "advise",
      "Which layer thickness can the contour strategy print while its distance error stays "
      "within lower's at the printer's thinnest layer (paper §4)?");
  add_model_options(*advise, advise_options->model);
  advise->add_option("--boundaries", advise_options->boundaries,
                     "also judge this layer plan against the benchmark, as one more row "
                     "(\"plan\"): layer tops as a comma list in mm, a file with one top per "
                     "line, or a G-code file of CuraEngine, PrusaSlicer, Slic3r or mahost "
                     "(default: none)");
  for (CLI::Option* option : add_adaptive_options(*advise, advise_options->adaptive)) {
    option->excludes("--boundaries");
  }
  advise->add_option("--printer", advise_options->printer,
                     "printer profile whose layer thicknesses to try (a name or a .toml path)")
      ->capture_default_str();
  advise->add_option("--contour", advise_options->contour,
                     fmt::format("strategy for the thicker layers: {}", geometry::contour_names()))
      ->capture_default_str();
  advise->add_option("--thicknesses", advise_options->thicknesses,
                     "thicknesses to try instead of the printer's, mm, comma-separated; the "
                     "thinnest is the benchmark");
  advise->add_option("--share", advise_options->share,
                     "percent of layers that must stay within the benchmark")
      ->check(number_in(0.0, 100.0))
      ->capture_default_str();
  advise->add_option("--json", advise_options->json, "write the table to this JSON file");
  advise->callback([advise_options] { run_advise(*advise_options); });
}

}  // namespace host
