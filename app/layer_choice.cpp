#include "app/layer_choice.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <chrono>
#include <cmath>

#include <fmt/format.h>

#include "app/stage_options.h"
#include "geometry/plan/flat_levels.h"
#include "geometry/toolpaths/toolpath_plan.h"
#include "printer/gcode_writer.h"

namespace app {

std::optional<double> parse_duration(std::string_view text) {
  double seconds = 0;
  int last_unit = -1;  // h, min, s in this order, each at most once
  std::size_t at = 0;
  if (text.empty()) return std::nullopt;
  while (at < text.size()) {
    std::size_t end = at;
    while (end < text.size() && (std::isdigit(static_cast<unsigned char>(text[end])) || text[end] == '.')) ++end;
    if (end == at || end == text.size()) return std::nullopt;  // no number, or no unit
    double value = 0;
    const auto [ptr, error] = std::from_chars(text.data() + at, text.data() + end, value);
    if (error != std::errc{} || ptr != text.data() + end || !(value >= 0)) return std::nullopt;
    const std::string_view rest = text.substr(end);
    int unit = -1;
    std::size_t length = 1;
    if (rest.starts_with("min")) unit = 1, length = 3;
    else if (rest.front() == 'h') unit = 0;
    else if (rest.front() == 'm') unit = 1;
    else if (rest.front() == 's') unit = 2;
    if (unit <= last_unit) return std::nullopt;
    seconds += value * (unit == 0 ? 3600 : unit == 1 ? 60 : 1);
    last_unit = unit;
    at = end + length;
  }
  return seconds;
}

geometry::AllowedThicknesses allowed_thicknesses(const printer::PrinterProfile& machine) {
  geometry::AllowedThicknesses allowed;
  allowed.listed = machine.layer.allowed;
  allowed.min = machine.layer.min;
  allowed.max = machine.layer.max;
  allowed.step = machine.layer.step;
  allowed.first = machine.first_layer_height;
  return allowed;
}

std::vector<const geometry::ContourStrategy*> planning_strategies(
    const geometry::ContourStrategy& printed) {
  if (printed.name == "best") return {&geometry::contour_strategy("mid")};
  return {&printed};
}

namespace {

// Whether a layer of the part prints anything: its contour (the printed strategy's) gives a
// path as the toolpaths lay it (a region no bead fits in, the tip of a cone, gives none). The
// layer alone, laid as any layer above the first: no skirt or brim, the usual bead.
std::function<bool(const geometry::Layer&)> prints_anything(const printer::PrinterProfile& machine,
                                                            const geometry::LayerStack& stack,
                                                            const geometry::ContourStrategy& printed) {
  geometry::ToolpathOptions options = toolpath_options(machine);
  options.skirt_loops = 0;
  options.brim_width = 0;
  options.first_layer_width = options.extrusion_width;
  return [options, &stack, &printed](const geometry::Layer& layer) {
    const std::vector<geometry::Layer> layers{layer};
    const geometry::LayerStack one(stack, layers);
    const std::vector<geometry::Region> regions{geometry::layer_contour(one, 0, printed)};
    if (regions.front().loops.empty()) return false;
    for (const geometry::LayerToolpaths& paths : geometry::plan_toolpaths(regions, layers, options)) {
      if (!paths.paths.empty()) return true;
    }
    return false;
  };
}

}  // namespace

LayerChoice choose_layers(const AdaptiveRequest& request, const printer::PrinterProfile& machine,
                          const geometry::LayerStack& stack, double part_height, double thickness,
                          const geometry::ContourStrategy& printed,
                          const PlanningProgress& progress, const PrintEstimate& estimate) {
  const auto start = std::chrono::steady_clock::now();
  LayerChoice choice;
  const geometry::AllowedThicknesses allowed = allowed_thicknesses(machine);
  const std::vector<geometry::FlatLevel> flats = geometry::flat_levels(stack.mesh());
  choice.adaptive = request.wanted();
  if (!choice.adaptive) {
    geometry::UniformPlan uniform = geometry::uniform_plan(part_height, thickness, allowed, flats);
    choice.layers = std::move(uniform.layers);
    choice.flats = std::move(uniform.flats);
  } else {
    geometry::AdaptiveOptions options;
    options.tolerance = request.tolerance > 0 ? request.tolerance : kDefaultTolerance;
    options.max_layers = request.max_layers;
    choice.max_layers = request.max_layers;
    options.thick_overhangs = request.thick_overhangs;
    if (request.max_seconds > 0 && estimate) {
      choice.budget_seconds = request.max_seconds;
      options.overrun = [&](const std::vector<geometry::Layer>& layers) {
        return estimate(layers) - request.max_seconds;
      };
    }
    options.contours = planning_strategies(printed);
    options.printed = &printed;
    options.prints = prints_anything(machine, stack, printed);
    choice.planned_by = std::string(options.contours.front()->name);
    choice.printed = std::string(printed.name);
    choice.thinnest_allowed = allowed.thinnest();
    choice.plan = geometry::adaptive_plan(stack, part_height, allowed, flats, options, progress);
    choice.layers = choice.plan.layers;
    choice.flats = choice.plan.flats;
    if (choice.budget_seconds > 0) choice.estimated_seconds = estimate(choice.layers);
  }
  choice.seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return choice;
}

namespace {

// "0.15", "0.15-0.4": thicknesses equal to a nanometre are one.
std::string thickness_range(double thinnest, double thickest) {
  const auto mm = [](double v) { return std::round(v * 1e6) / 1e6; };
  return mm(thinnest) == mm(thickest) ? fmt::format("{:g}", mm(thinnest))
                                      : fmt::format("{:g}-{:g}", mm(thinnest), mm(thickest));
}

// The layers above the first over the tolerance, as runs of one reason, each with its worst
// D: "z 30.10-31.90 (slopes down to 4° from horizontal: up to 0.61 mm), z 13.00-13.20 (0.2 mm
// to land the flat level at 13.5 mm: 0.045 mm)"; at most four, then a count.
std::string over_tolerance_runs(const geometry::AdaptivePlan& plan) {
  std::vector<std::string> runs;
  for (std::size_t i = 0; i < plan.layers.size();) {
    const geometry::OverTolerance why = plan.why[i];
    if (why == geometry::OverTolerance::none || why == geometry::OverTolerance::first_layer) {
      ++i;
      continue;
    }
    std::size_t j = i;
    double lean = plan.lean[i], worst = plan.distance[i];
    while (j + 1 < plan.layers.size() && plan.why[j + 1] == why && why != geometry::OverTolerance::landing) {
      ++j;
      lean = std::min(lean, plan.lean[j]);
      worst = std::max(worst, plan.distance[j]);
    }
    std::string reason;
    switch (why) {
      case geometry::OverTolerance::flat_level:
        reason = "across a flat level no allowed layer lands";
        break;
      case geometry::OverTolerance::landing: {
        // What it lands: the first flat level at or above its top, or the top.
        double landed = plan.layers.back().z_hi;
        for (const geometry::FlatPlacement& flat : plan.flats) {
          if (flat.on_boundary() && flat.z >= plan.layers[i].z_hi - 1e-6) {
            landed = flat.z;
            break;
          }
        }
        reason = fmt::format("{:g} mm to land the {} at {:.2f} mm", std::round(plan.layers[i].thickness() * 1e6) / 1e6,
                             landed == plan.layers.back().z_hi ? "top" : "flat level", landed);
        break;
      }
      case geometry::OverTolerance::height_share:
        reason = "thicker than the thinnest, in the 5% of the height the by-height cap leaves out";
        break;
      case geometry::OverTolerance::missed_feature:
        reason = "a tip or bump smaller than a layer, which the contour leaves out";
        break;
      default: reason = fmt::format("slopes down to {:.0f}° from horizontal", lean); break;
    }
    runs.push_back(fmt::format("z {:.2f}-{:.2f} ({}: {}{:.3g} mm)", plan.layers[i].z_lo,
                               plan.layers[j].z_hi, reason, j > i ? "up to " : "", worst));
    i = j + 1;
  }
  const std::size_t shown = std::min<std::size_t>(runs.size(), 4);
  std::string text;
  for (std::size_t k = 0; k < shown; ++k) text += (k ? ", " : "") + runs[k];
  if (runs.size() > shown) text += fmt::format(" and {} more", runs.size() - shown);
  return text;
}

// The layers' thicknesses, "0.15-0.4": the range leaves out the first layer (its own
// thickness) unless it is the only one.
std::string layer_thicknesses(const std::vector<geometry::Layer>& layers) {
  double thinnest = 0, thickest = 0;
  const std::size_t from = layers.size() > 1 ? 1 : 0;
  for (std::size_t i = from; i < layers.size(); ++i) {
    const double t = layers[i].thickness();
    thinnest = i == from ? t : std::min(thinnest, t);
    thickest = i == from ? t : std::max(thickest, t);
  }
  return thickness_range(thinnest, thickest);
}

// "adaptive: 211 layers of 0.1-0.4 mm for D within 0.4 mm (best's D, ...; planned in ...)".
std::string adaptive_headline(const LayerChoice& choice) {
  const geometry::AdaptivePlan& plan = choice.plan;
  // Whose D: the printed contour's, or for best mid's, which best's is not above on a
  // layer where mid leaves nothing out (best_contour.h).
  const std::string whose =
      choice.planned_by == choice.printed
          ? fmt::format("{}'s D", choice.printed)
          : fmt::format("{}'s D, planned by {}'s, which {}'s does not exceed", choice.printed,
                        choice.planned_by, choice.printed);
  // With a budget met, the least total error was found within a cap (layer_plan.h): the
  // layers are said against it, and the least tolerance the budget allows beside it.
  const bool capped = plan.cap > 0;
  return fmt::format("adaptive: {} layer{} of {} mm for {}D within {:.3g} mm ({}; planned in "
                     "{:.1f} s: {} of {} candidate layers measured)",
                     choice.layers.size(), choice.layers.size() == 1 ? "" : "s",
                     layer_thicknesses(choice.layers), capped ? "the least total error with " : "",
                     capped ? plan.cap : plan.tolerance, whose, choice.seconds, plan.measured,
                     plan.candidates);
}

// What the budget (--max-time or --max-layers) made of the plan: the least tolerance it
// allows (and for --max-time the layers it holds), or that no plan fits it.
std::string budget_outcome(const LayerChoice& choice) {
  const geometry::AdaptivePlan& plan = choice.plan;
  const std::string budget =
      choice.budget_seconds > 0
          ? fmt::format("whose print fits --max-time {} (estimated {})",
                        printer::format_duration(choice.budget_seconds),
                        printer::format_duration(choice.estimated_seconds))
          : fmt::format("within --max-layers {}", choice.max_layers);
  std::string text;
  if (plan.cap > 0) {
    text += choice.budget_seconds > 0
                ? fmt::format("; the most layers {} are {}, at the least tolerance within as many, {:.3g} mm",
                              budget, choice.layers.size(), plan.tolerance)
                : fmt::format("; the least tolerance {} is {:.3g} mm", budget, plan.tolerance);
    if (plan.cap_by_height) {
      text += fmt::format(": layers up to {:.3g} mm but for the 5% of the height a by-height 95th "
                          "percentile leaves out, at any thickness (the least such cap), where they "
                          "take off more volume", plan.cap);
    } else if (plan.cap > plan.tolerance) {
      text += fmt::format(": layers up to {:.3g} mm (that plan's P95h D less its thinnest layers "
                          "above it) where they take off more volume", plan.cap);
    }
    text += fmt::format(", none over that plan's largest D, {:.3g} mm", plan.ceiling);
  } else if (choice.budget_seconds > 0) {
    text += choice.estimated_seconds <= choice.budget_seconds
                ? fmt::format(", the least tolerance {}", budget)
                : fmt::format("; no plan fits --max-time {}: the thickest layers take {}",
                              printer::format_duration(choice.budget_seconds),
                              printer::format_duration(choice.estimated_seconds));
  }
  if (choice.max_layers > 0 && choice.layers.size() > choice.max_layers) {
    text += fmt::format("; no plan has at most --max-layers {}: the thickest layers the "
                        "printer allows make {}",
                        choice.max_layers, choice.layers.size());
  }
  return text;
}

// The layers the plan could not keep within the tolerance: those above the first, then the
// first layer, then the candidates refused for overhangs.
std::string layers_over_tolerance(const LayerChoice& choice) {
  const geometry::AdaptivePlan& plan = choice.plan;
  std::string text;
  if (plan.unmet > 0) {
    double worst = 0;
    for (std::size_t i = 1; i < plan.layers.size(); ++i) {
      if (!plan.met[i]) worst = std::max(worst, plan.distance[i]);
    }
    text += fmt::format("; {} layer{} over it (up to {:.3g} mm), the thinnest the printer has "
                        "({:g} mm) unless said: {}",
                        plan.unmet, plan.unmet == 1 ? "" : "s", worst,
                        std::round(choice.thinnest_allowed * 1e6) / 1e6, over_tolerance_runs(plan));
  }
  if (!plan.why.empty() && plan.why.front() == geometry::OverTolerance::first_layer) {
    text += fmt::format("; the first layer, the printer's {:g} mm, has D {:.3g} mm",
                        std::round(plan.layers.front().thickness() * 1e6) / 1e6,
                        plan.distance.front());
  }
  if (plan.refused_for_overhangs > 0) {
    text += fmt::format("; with supports on, {} candidate layer{} refused as too thick for the "
                        "slopes under {} (each would step out past half a bead, and need support "
                        "a thinner one does not)",
                        plan.refused_for_overhangs, plan.refused_for_overhangs == 1 ? "" : "s",
                        plan.refused_for_overhangs == 1 ? "it" : "them");
  }
  return text;
}

// "flat levels between the heights the layers can reach: 6.285 on 6.300, ... mm", or "".
std::string missed_flats(const std::vector<geometry::FlatPlacement>& flats) {
  std::vector<std::string> missed;
  for (const geometry::FlatPlacement& flat : flats) {
    if (!flat.on_boundary()) missed.push_back(fmt::format("{:.3f} on {:.3f}", flat.z, flat.boundary));
  }
  if (missed.empty()) return "";
  std::string text = fmt::format("flat level{} between the heights the layers can reach: ",
                                 missed.size() == 1 ? "" : "s");
  for (std::size_t k = 0; k < missed.size(); ++k) text += (k ? ", " : "") + missed[k];
  return text + " mm";
}

}  // namespace

std::string describe_choice(const LayerChoice& choice) {
  std::string text;
  if (choice.adaptive) text = adaptive_headline(choice) + budget_outcome(choice) + layers_over_tolerance(choice);
  const std::string flats = missed_flats(choice.flats);
  if (!flats.empty()) text += (text.empty() ? "" : "; ") + flats;
  return text;
}

}  // namespace app
