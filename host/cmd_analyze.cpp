// `mahost analyze MODEL.stl [placement] [--layer 0.15 | --boundaries FILE|z1,z2,...]
//  [--contours lower,mid,optimal-height,ma] [--exclude-z LO:HI] [--csv F] [--json F]
//  [--plots DIR] [--thick 0.2,0.25] [--layer-index N] [--export-layers F.stl --contour K]`
// `mahost advise MODEL.stl [placement] [--printer up-plus-2] [--contour ma]
//  [--thicknesses 0.15,0.2,...] [--boundaries FILE|z1,z2,...] [--share 95] [--json F]`
//
// The command line of app/analyze.h's analyze and advise (paper §4, Fig. 22-26): their flags
// as a request, their result as a table on stdout (one summary row per strategy, then how
// every strategy compares with lower and with mid; advise's row per thickness and its advice)
// and in the files asked for: a CSV row per layer and strategy, a JSON summary, SVG charts (D
// per layer, ΔV per layer, the medial-axis contour at thicker layers against lower at this
// one, an adaptive plan against uniform layers), a drawing of one layer's contours, and the
// layered part as an STL.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <memory>
#include <mutex>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <fmt/core.h>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "app/analyze.h"
#include "app/error.h"
#include "app/layer_boundaries.h"
#include "app/layer_choice.h"
#include "app/model.h"
#include "app/slice_options.h"
#include "host/cli_checks.h"
#include "host/commands.h"
#include "host/plots.h"
#include "host/progress.h"
#include "host/slice_flags.h"
#include "printer/profile.h"

namespace host {
namespace {

using app::Strategies;
using geometry::ContourStrategy;
using geometry::LayerAnalysis;
using geometry::StrategySummary;

struct AnalyzeOptions {
  app::ModelOptions model;
  double layer = 0.15;
  std::string boundaries;  // explicit layer tops instead of --layer
  std::string exclude_z;   // "LO:HI", mm: left out of the by-height percentile
  std::string contours = app::contour_names(",");  // all of them
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
      throw app::InputError(fmt::format(
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
    throw app::InputError(fmt::format("{} {}: cannot write this file; give a path in a "
                                      "directory you can write to",
                                      flag, path));
  }
  return out;
}

void write_json(const nlohmann::json& j, const std::string& path) {
  std::ofstream out = open_output(path, "--json");
  out << j.dump(2) << "\n";
  if (!out) throw app::InputError(fmt::format("--json {}: writing failed", path));
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
    throw app::InputError(fmt::format(
        "--exclude-z {}: give a height range LO:HI in mm with LO below HI, e.g. 0:2.25", text));
  }
  return range;
}

// analyze and advise on a terminal: one progress bar at a time (a run's first call, done = 0
// on the calling thread, replaces the last run's bar, which clears its line), the model's
// notes on stderr as "mahost: LINE", --boundaries' as they are.
class TerminalEvents {
 public:
  app::AnalysisEvents events() {
    app::AnalysisEvents events;
    events.model_note = [](const std::string& line) { fmt::print(stderr, "mahost: {}\n", line); };
    events.layers_note = [](const std::string& line) { fmt::print(stderr, "{}\n", line); };
    events.progress = [this](const std::string& label, std::size_t done, std::size_t total) {
      std::lock_guard lock(mutex_);
      if (!bar_ || label != label_) {
        bar_.reset();
        bar_ = std::make_unique<Progress>(label, total);
        label_ = label;
      }
      // Planning has no total: the candidate layers measured so far.
      bar_->update(done, total == 0 ? fmt::format("{} candidate layers measured", done)
                                    : fmt::format("layer {}/{}", done, total));
    };
    return events;
  }
  // Clears the last bar's line, before the results are printed.
  void finish() {
    std::lock_guard lock(mutex_);
    bar_.reset();
  }

 private:
  std::mutex mutex_;
  std::unique_ptr<Progress> bar_;
  std::string label_;
};

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

// A comparison's line: "ma vs lower: mean D -12.3%, ...".
void print_comparison(const app::Comparison& c, const std::vector<StrategySummary>& summaries,
                      std::size_t layers) {
  const StrategySummary& s = summaries[c.strategy];
  const StrategySummary& base = summaries[c.baseline];
  const std::string per_layer_text =
      c.layers_compared ? fmt::format("ΔV per layer {}% on average ({}% to {}%)",
                                      signed_text(c.per_layer_change_percent, 1),
                                      signed_text(c.least_change_percent, 0),
                                      signed_text(c.greatest_change_percent, 0))
                        : std::string("ΔV per layer: n/a (the baseline's is negligible)");
  const std::string keeping_text =
      c.distance_worse_keeping_features
          ? fmt::format(" ({} of them where {} misses a feature {} prints)",
                        c.distance_worse_keeping_features, name_of(base.strategy),
                        name_of(s.strategy))
          : std::string();
  fmt::print("{} vs {}: mean D {}, max D {}, total ΔV {}, {}; D better on {}, worse on {} of {} "
             "layers{}\n",
             name_of(s.strategy), name_of(base.strategy),
             change_text(s.mean_distance, base.mean_distance, c.negligible_distance, "mm", 4),
             change_text(s.max_distance, base.max_distance, c.negligible_distance, "mm", 4),
             change_text(s.total_deviation, base.total_deviation, c.negligible_volume, "mm³", 3),
             per_layer_text, c.distance_better, c.distance_worse, layers, keeping_text);
}

nlohmann::json comparison_json(const app::Comparison& c, const std::vector<StrategySummary>& summaries) {
  const StrategySummary& s = summaries[c.strategy];
  const StrategySummary& base = summaries[c.baseline];
  nlohmann::json j;
  j["strategy"] = name_of(s.strategy);
  j["baseline"] = name_of(base.strategy);
  j["mean_distance_change_percent"] =
      percent_or_null(s.mean_distance, base.mean_distance, c.negligible_distance);
  j["max_distance_change_percent"] =
      percent_or_null(s.max_distance, base.max_distance, c.negligible_distance);
  j["total_deviation_change_percent"] =
      percent_or_null(s.total_deviation, base.total_deviation, c.negligible_volume);
  j["mean_distance_change"] = s.mean_distance - base.mean_distance;
  j["max_distance_change"] = s.max_distance - base.max_distance;
  j["total_deviation_change"] = s.total_deviation - base.total_deviation;
  j["per_layer_deviation_change_percent"] = c.per_layer_change_percent;
  j["layers_compared_for_deviation"] = c.layers_compared;
  j["per_layer_deviation_change_min_percent"] = c.least_change_percent;
  j["per_layer_deviation_change_max_percent"] = c.greatest_change_percent;
  j["layers_distance_better"] = c.distance_better;
  j["layers_distance_worse"] = c.distance_worse;
  j["layers_distance_worse_keeping_features"] = c.distance_worse_keeping_features;
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

void write_chart(const std::string& path, Chart chart) {
  fit_y_axis(chart);
  write_chart_svg(path, chart);
}

// --layer-index: the layer's footprint and contours drawn, and their metrics printed.
void draw_layer(const app::LayerDrawing& drawing, const std::string& path) {
  std::vector<Outline> outlines;
  Outline pair{"boundary pair (slab footprint)", drawing.footprint.loops, "#888888", 4.0, false};
  outlines.push_back(pair);
  const geometry::Layer& layer = drawing.layer;
  fmt::print("layer {} [{:.3f}, {:.3f}] mm: {} island(s)\n", drawing.index, layer.z_lo, layer.z_hi,
             drawing.islands);
  for (const geometry::StrategyLayer& s : drawing.analysis.strategies) {
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
                     fmt::format("layer {} (z {:.3f} to {:.3f} mm): contours", drawing.index,
                                 layer.z_lo, layer.z_hi),
                     outlines);
  fmt::print("wrote {}\n", path);
}

// An adaptive plan beside uniform layers of the printer's thinnest thickness and of about as
// many layers: each layer's thickness against height (adaptive-thickness.svg) and the printed
// contour's D against height with the tolerance (adaptive-distance.svg).
template <typename PathOf>
void write_plan_charts(const app::AnalyzeResult& result, const ContourStrategy& printed,
                       const PathOf& path_of) {
  const app::LayerChoice& plan = *result.plan;
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
  add(result.analysis, static_cast<std::size_t>(app::strategy_index(result.strategies, printed.name)),
      fmt::format("adaptive, {} layers", plan.layers.size()), "points", "#d62728");
  const char* colours[] = {"#1f77b4", "#2ca02c"};
  for (std::size_t c = 0; c < result.uniform.size(); ++c) {
    const app::UniformLayers& uniform = result.uniform[c];
    add(uniform.layers, 0, fmt::format("uniform {:g} mm, {} layers", uniform.thickness, uniform.layers.size()),
        "lines", colours[c]);
  }
  Series limit{fmt::format("tolerance {:.3g} mm", plan.plan.tolerance), {0, result.height},
               {plan.plan.tolerance, plan.plan.tolerance}, "lines lw 1 dt 2", "#000000"};
  distance.series.push_back(limit);
  fit_y_axis(distance);
  write_chart_svg(path_of("adaptive-thickness.svg"), thickness);
  write_chart_svg(path_of("adaptive-distance.svg"), distance);
  fmt::print("wrote {}, {}\n", path_of("adaptive-thickness.svg"), path_of("adaptive-distance.svg"));
}

void make_plots_folder(const std::string& plots) {
  std::error_code error;
  std::filesystem::create_directories(plots, error);
  if (error || !std::filesystem::is_directory(plots)) {
    throw app::InputError(fmt::format(
        "--plots {}: cannot create this directory ({}); give one you can write to", plots,
        error ? error.message() : "not a directory"));
  }
}

double ms_per_layer(const StrategySummary& s) {
  return 1e3 * s.contour_seconds / std::max<std::size_t>(s.layers, 1);
}

// The table of the strategies' summaries, its legend.
void print_summary_table(const std::vector<StrategySummary>& summaries, const Strategies& kinds,
                         const geometry::ZRange& excluded) {
  fmt::print("{:<15} {:>8} {:>8} {:>8} {:>8} {:>10} {:>9} {:>9} {:>7} {:>7} {:>5} {:>10}\n",
             "strategy", "mean D", "max D", "P95h D", "mean H", "total ΔV", "mean ΔV", "ΔV>limit",
             "missed", ">lower", ">mid", "ms/layer");
  const int lower = app::strategy_index(kinds, "lower"), mid = app::strategy_index(kinds, "mid");
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

// The comparisons' lines and optimal-height's time per slice.
void print_comparisons(const app::AnalyzeResult& result) {
  for (const app::Comparison& c : result.comparisons) {
    print_comparison(c, result.summaries, result.analysis.size());
  }
  const int optimal = app::strategy_index(result.strategies, "optimal-height");
  if (optimal >= 0) {
    fmt::print("optimal-height: {:.1f} ms per slice on one core (the paper's CATIA search: about "
               "90 s per slice)\n",
               ms_per_layer(result.summaries[optimal]));
  }
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
  if (!out) throw app::InputError(fmt::format("--csv {}: writing failed", path));
  fmt::print("wrote {}: {} rows\n", path, layers.size() * strategies);
}

// Fig. 24-25: the medial-axis contour at thicker layers against lower at this thickness, a
// line and a chart each.
void print_thicker_ma(const AnalyzeOptions& options, const app::AnalyzeResult& result) {
  const auto lower = static_cast<std::size_t>(app::strategy_index(result.strategies, "lower"));
  for (const app::ThickerLayers& thick : result.thicker) {
    fmt::print("ma at {:g} mm: {} layers, mean D {:.4f} mm, max D {:.4f} mm; D within lower's at "
               "{:g} mm on {:.1f}% of layers\n",
               thick.thickness, thick.layers.size(), thick.mean_distance, thick.max_distance,
               options.layer, thick.within_percent);
    Chart chart{fmt::format("Distance error: lower ({:g} mm) vs MA ({:g} mm)", options.layer, thick.thickness),
                "height, mm", "distance error D, mm", {}};
    chart.series.push_back(per_layer_series(result.analysis, lower, true,
                                            fmt::format("lower, {:g} mm", options.layer)));
    chart.series.push_back(per_layer_series(thick.layers, 0, true, fmt::format("ma, {:g} mm", thick.thickness)));
    const std::string path =
        (std::filesystem::path(options.plots) /
         fmt::format("distance-lower-{:g}-vs-ma-{:g}.svg", options.layer, thick.thickness))
            .string();
    write_chart(path, chart);
    fmt::print("wrote {}\n", path);
  }
}

nlohmann::json thicker_json(const app::AnalyzeResult& result) {
  nlohmann::json thicker = nlohmann::json::array();
  for (const app::ThickerLayers& thick : result.thicker) {
    thicker.push_back({{"thickness", thick.thickness},
                       {"layers", thick.layers.size()},
                       {"mean_distance", thick.mean_distance},
                       {"max_distance", thick.max_distance},
                       {"within_benchmark_percent", thick.within_percent}});
  }
  return thicker;
}

// The charts of --plots: D and ΔV per layer of every strategy, the plan's, and Fig. 22's pairs
// (lower and mid each against the medial-axis contour).
void write_layer_charts(const AnalyzeOptions& options, const app::AnalyzeResult& result,
                        const ContourStrategy& printed) {
  const std::vector<LayerAnalysis>& layers = result.analysis;
  const Strategies& kinds = result.strategies;
  const auto path_of = [&](const std::string& name) {
    return (std::filesystem::path(options.plots) / name).string();
  };
  const std::string at =
      result.plan ? std::string("of the adaptive plan") : fmt::format("at {:g} mm", options.layer);
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
  write_chart(path_of("distance.svg"), all);
  write_chart(path_of("volume.svg"), volume);
  fmt::print("wrote {}, {}\n", path_of("distance.svg"), path_of("volume.svg"));
  if (result.plan) write_plan_charts(result, printed, path_of);
  const int lower = app::strategy_index(kinds, "lower"), mid = app::strategy_index(kinds, "mid");
  const int ma = app::strategy_index(kinds, "ma");
  for (int base : {lower, mid}) {
    if (base < 0 || ma < 0) continue;
    Chart pair{fmt::format("Distance error: {} vs ma at {:g} mm", name_of(kinds[base]), options.layer),
               "height, mm", "distance error D, mm", {}};
    pair.series.push_back(per_layer_series(layers, static_cast<std::size_t>(base), true, name_of(kinds[base])));
    pair.series.push_back(per_layer_series(layers, static_cast<std::size_t>(ma), true, "ma"));
    const std::string path = path_of(fmt::format("distance-{}-vs-ma.svg", name_of(kinds[base])));
    write_chart(path, pair);
    fmt::print("wrote {}\n", path);
  }
}

// --export-layers: the layered part as STL.
void export_layered_part(const AnalyzeOptions& options, const app::AnalyzeResult& result,
                         const ContourStrategy& exported) {
  const geometry::Mesh& part = *result.layered_part;
  app::write_stl(part, options.export_layers);
  fmt::print("wrote {}: the layered part of {} ({} layers, {} triangles, {:.2f} mm³; model "
             "{:.2f} mm³)\n",
             options.export_layers, exported.name, result.analysis.size(), part.faces.size(),
             result.layered_part_volume, result.model_volume);
}

void write_analysis_json(const AnalyzeOptions& options, const geometry::ZRange& excluded,
                         const app::AnalyzeResult& result) {
  const std::vector<LayerAnalysis>& layers = result.analysis;
  nlohmann::json j;
  j["model"] = options.model.path;
  j["height"] = result.height;
  j["layer_thickness"] = options.boundaries.empty() ? nlohmann::json(options.layer)
                                                    : nlohmann::json(nullptr);
  if (!options.boundaries.empty()) j["boundaries"] = options.boundaries;
  j["layers"] = result.layers.size();
  double thinnest = layers.front().layer.thickness(), thickest = thinnest;
  for (const LayerAnalysis& layer : layers) {
    thinnest = std::min(thinnest, layer.layer.thickness());
    thickest = std::max(thickest, layer.layer.thickness());
  }
  j["layer_thickness_min"] = thinnest;
  j["layer_thickness_max"] = thickest;
  j["layers_top"] = layers.empty() ? 0.0 : layers.back().layer.z_hi;
  j["percentile_excluded_z"] = excluded.empty() ? nlohmann::json(nullptr)
                                                : nlohmann::json::array({excluded.lo, excluded.hi});
  j["volume_limit"] = result.volume_limit;
  j["strategies"] = nlohmann::json::array();
  const auto number_or_null = [](double v) {
    return std::isnan(v) ? nlohmann::json(nullptr) : nlohmann::json(v);
  };
  for (const StrategySummary& s : result.summaries) {
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
  j["comparisons"] = nlohmann::json::array();
  for (const app::Comparison& c : result.comparisons) j["comparisons"].push_back(comparison_json(c, result.summaries));
  j["thicker_ma"] = thicker_json(result);
  write_json(j, options.json);
  fmt::print("wrote {}\n", options.json);
}

// The request the flags make, checked in the order a user hears of them: --contours,
// --contour, --thick, --plots, --exclude-z.
app::AnalyzeRequest analyze_request(const AnalyzeOptions& options) {
  app::AnalyzeRequest request;
  request.strategies = app::strategy_list(split_list(options.contours), "--contours");
  request.contour = &app::contour_strategy_option(options.contour, "--contour");
  if (!options.plots.empty()) {
    request.thicker = thickness_list(options.thick, "--thick");
    make_plots_folder(options.plots);
    request.plan_beside_uniform = true;
  }
  if (!options.exclude_z.empty()) request.excluded = parse_z_range(options.exclude_z);
  request.model = options.model;
  request.layer = options.layer;
  request.boundaries = options.boundaries;
  request.from_zero = options.from_zero;
  request.adaptive = options.adaptive;
  request.printer = options.printer;
  if (options.layer_index >= 0) request.layer_index = static_cast<std::size_t>(options.layer_index);
  request.export_layers = !options.export_layers.empty();
  return request;
}

void run_analyze(const AnalyzeOptions& options) {
  const app::AnalyzeRequest request = analyze_request(options);
  TerminalEvents terminal;
  const app::AnalyzeResult result = app::analyze(request, terminal.events());
  terminal.finish();
  fmt::print("{}: {:.2f} mm tall, {}; volume limit {:.3f} mm³ (the least ΔV any extruded "
             "layers can have)\n",
             options.model.path, result.height, app::describe_layers(result.layers), result.volume_limit);
  if (result.plan) fmt::print("{}\n", app::describe_choice(*result.plan));
  print_summary_table(result.summaries, result.strategies, request.excluded);
  print_comparisons(result);
  if (!options.csv.empty()) write_layers_csv(options.csv, result.analysis, result.strategies.size());
  print_thicker_ma(options, result);
  if (!options.plots.empty()) write_layer_charts(options, result, *request.contour);
  if (result.drawing) {
    const std::string name = fmt::format("layer-{}.svg", options.layer_index);
    const std::string path = options.plots.empty()
                                 ? name
                                 : (std::filesystem::path(options.plots) / name).string();
    draw_layer(*result.drawing, path);
  }
  if (result.layered_part) export_layered_part(options, result, *request.contour);
  if (!options.json.empty()) write_analysis_json(options, request.excluded, result);
}

// The flags as a request: --contour, then --thicknesses.
app::AdviseRequest advise_request(const AdviseOptions& options) {
  app::AdviseRequest request;
  request.contour = &app::contour_strategy_option(options.contour, "--contour");
  if (!options.thicknesses.empty()) request.thicknesses = thickness_list(options.thicknesses, "--thicknesses");
  request.model = options.model;
  request.printer = options.printer;
  request.boundaries = options.boundaries;
  request.adaptive = options.adaptive;
  request.share = options.share;
  return request;
}

nlohmann::json advise_row_json(const app::AdviseRow& row) {
  return {{"layers", row.layers},
          {"mean_distance", row.mean_distance},
          {"max_distance", row.max_distance},
          {"within_benchmark_percent", row.within_percent},
          {"fewer_layers_percent", row.fewer_layers_percent}};
}

void print_advise_table(const app::AdviseResult& result) {
  fmt::print("{:>9} {:>7} {:>8} {:>8} {:>8} {:>12}\n", "thickness", "layers", "mean D", "max D",
             "within", "fewer layers");
  for (const app::AdviseRow& row : result.rows) {
    fmt::print("{:>7.3g}mm {:7} {:8.4f} {:8.4f} {:7.1f}% {:11.1f}%\n", row.thickness, row.layers,
               row.mean_distance, row.max_distance, row.within_percent, row.fewer_layers_percent);
  }
  if (result.plan) {
    const app::AdviseRow& row = *result.plan;
    fmt::print("{:>9} {:7} {:8.4f} {:8.4f} {:7.1f}% {:11.1f}%   ({})\n",
               result.adaptive ? "adaptive" : "plan", row.layers, row.mean_distance,
               row.max_distance, row.within_percent, row.fewer_layers_percent,
               app::describe_layers(result.plan_layers));
    if (result.adaptive) fmt::print("          {}\n", app::describe_choice(*result.adaptive));
  }
}

void write_advise_json(const AdviseOptions& options, const app::AdviseResult& result,
                       const std::string& contour) {
  nlohmann::json rows = nlohmann::json::array();
  for (const app::AdviseRow& row : result.rows) {
    nlohmann::json j = {{"thickness", row.thickness}};
    j.update(advise_row_json(row));
    rows.push_back(j);
  }
  nlohmann::json plan_row(nullptr);
  if (result.plan) {
    plan_row = {{"boundaries", result.adaptive ? std::string("adaptive") : options.boundaries},
                {"tolerance", result.adaptive ? nlohmann::json(result.adaptive->plan.tolerance)
                                              : nlohmann::json(nullptr)}};
    plan_row.update(advise_row_json(*result.plan));
  }
  nlohmann::json j{{"model", options.model.path},
                   {"contour", contour},
                   {"benchmark_thickness", result.benchmark_thickness},
                   {"share_required_percent", options.share},
                   {"thicknesses", rows},
                   {"plan", plan_row},
                   {"advised_thickness", result.advised ? nlohmann::json(*result.advised) : nlohmann::json(nullptr)}};
  write_json(j, options.json);
}

void run_advise(const AdviseOptions& options) {
  const app::AdviseRequest request = advise_request(options);
  TerminalEvents terminal;
  const app::AdviseResult result = app::advise(request, terminal.events());
  terminal.finish();
  const std::string contour = name_of(request.contour);
  const double thinnest = result.benchmark_thickness;
  fmt::print("{}: {:.2f} mm tall; thicknesses from {}\n", options.model.path, result.height,
             result.thicknesses_from);
  fmt::print("benchmark: lower at {:g} mm, {} layers, mean D {:.4f} mm, max D {:.4f} mm\n",
             thinnest, result.benchmark_layers, result.benchmark_mean_distance,
             result.benchmark_max_distance);
  print_advise_table(result);
  if (result.advised) {
    fmt::print("advice: {} at {:g} mm keeps at least {:g}% of layers within lower's distance error "
               "at {:g} mm\n",
               contour, *result.advised, options.share, thinnest);
  } else {
    fmt::print("advice: no thickness keeps {:g}% of {}'s layers within lower's distance error at "
               "{:g} mm; print at {:g} mm\n",
               options.share, contour, thinnest, thinnest);
  }
  if (!options.json.empty()) write_advise_json(options, result, contour);
}

// analyze's layers: --layer, --from-zero, --boundaries.
CLI::Option* add_layer_flags(CLI::App& analyze, AnalyzeOptions& options) {
  CLI::Option* layer = analyze.add_option("--layer", options.layer, "layer thickness, mm")
                           ->check(positive_number())
                           ->capture_default_str();
  CLI::Option* from_zero = analyze.add_flag(
      "--from-zero", options.from_zero,
      "uniform layers from the bed, every one --layer thick, with no first layer of the "
      "printer's and no flat level landed (the paper's comparison; default: the layers `slice` "
      "prints at --layer on --printer)");
  analyze.add_option("--boundaries", options.boundaries,
                     "judge these layers instead of --layer: layer tops as a comma list in mm "
                     "(0.3,0.5,...), a file with one top per line (# comments), or a G-code file "
                     "of CuraEngine, PrusaSlicer, Slic3r or mahost, whose layer heights are "
                     "used; any thicknesses (no printer is checked)")
      ->excludes(layer);
  from_zero->excludes("--boundaries");
  return from_zero;
}

// analyze's strategies and what it writes: --exclude-z, --contours, --csv, --json, --plots,
// --thick, --layer-index, --export-layers.
void add_output_flags(CLI::App& analyze, AnalyzeOptions& options) {
  analyze.add_option("--exclude-z", options.exclude_z,
                     "leave this height range out of the by-height 95th percentile of D "
                     "(P95h D), LO:HI in mm, e.g. 0:2.25 for the bunny's hole-filled base "
                     "(default: none)");
  analyze.add_option("--contours", options.contours,
                     fmt::format("strategies to compare, comma-separated: {}",
                                 app::contour_strategies_help()))
      ->capture_default_str();
  analyze.add_option("--csv", options.csv, "write one row per layer and strategy to this CSV file");
  analyze.add_option("--json", options.json, "write the summary to this JSON file");
  analyze.add_option("--plots", options.plots,
                     "write SVG charts (needs gnuplot) into this directory: D and ΔV per layer, "
                     "lower and mid against ma, ma at the --thick layers against lower");
  analyze.add_option("--thick", options.thick,
                     "with --plots: thicker layers for ma to compare with lower at --layer, mm")
      ->capture_default_str();
  analyze.add_option("--layer-index", options.layer_index,
                     "draw this layer's footprint and contours as layer-N.svg (in --plots, or "
                     "here) and print its metrics")
      ->check(non_negative_number());
  analyze.add_option("--export-layers", options.export_layers,
                     "write the layered part (each layer's region extruded) as an STL file");
}

void add_analyze(CLI::App& app) {
  auto options = std::make_shared<AnalyzeOptions>();
  CLI::App* analyze = app.add_subcommand(
      "analyze",
      "Compare contour strategies layer by layer: exact volume deviation, distance error "
      "(the paper's D, to 1 um; reverse and Hausdorff, sampled at 5 heights a layer), the "
      "volume limit, missed features; CSV, JSON, SVG plots, a layer's contours, the layered "
      "part as STL.");
  add_model_options(*analyze, options->model);
  CLI::Option* from_zero = add_layer_flags(*analyze, *options);
  add_output_flags(*analyze, *options);
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
                                  app::contour_names()))
      ->capture_default_str();
  analyze->callback([options] { run_analyze(*options); });
}

void add_advise(CLI::App& app) {
  auto options = std::make_shared<AdviseOptions>();
  CLI::App* advise = app.add_subcommand(
      "advise",
      "Which layer thickness can the contour strategy print while its distance error stays "
      "within lower's at the printer's thinnest layer (paper §4)?");
  add_model_options(*advise, options->model);
  advise->add_option("--boundaries", options->boundaries,
                     "also judge this layer plan against the benchmark, as one more row "
                     "(\"plan\"): layer tops as a comma list in mm, a file with one top per "
                     "line, or a G-code file of CuraEngine, PrusaSlicer, Slic3r or mahost "
                     "(default: none)");
  for (CLI::Option* option : add_adaptive_options(*advise, options->adaptive)) {
    option->excludes("--boundaries");
  }
  advise->add_option("--printer", options->printer,
                     "printer profile whose layer thicknesses to try (a name or a .toml path)")
      ->capture_default_str();
  advise->add_option("--contour", options->contour,
                     fmt::format("strategy for the thicker layers: {}", app::contour_names()))
      ->capture_default_str();
  advise->add_option("--thicknesses", options->thicknesses,
                     "thicknesses to try instead of the printer's, mm, comma-separated; the "
                     "thinnest is the benchmark");
  advise->add_option("--share", options->share,
                     "percent of layers that must stay within the benchmark")
      ->check(number_in(0.0, 100.0))
      ->capture_default_str();
  advise->add_option("--json", options->json, "write the table to this JSON file");
  advise->callback([options] { run_advise(*options); });
}

}  // namespace

void add_analyze_command(CLI::App& app) {
  add_analyze(app);
  add_advise(app);
}

}  // namespace host
