// Which layers a part is printed in (DESIGN.md §1's layer plan): uniform at
// --layer, every flat top, floor and step of the model landing on a layer boundary where the
// printer's thicknesses reach it; or --adaptive, the fewest layers whose distance error D
// (what `analyze` reports, of the contour printed) is within --tolerance, or the least
// tolerance for at most --max-layers layers (geometry/plan/layer_plan.h). slice, print,
// analyze and advise share the request (its options are in app/slice_options.h's table) and
// the one-line report of the plan.
#pragma once

#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "geometry/contour/contour_strategy.h"
#include "geometry/plan/layer_plan.h"
#include "geometry/slicing/layer_stack.h"
#include "printer/profile.h"

namespace app {

struct AdaptiveRequest {
  bool adaptive = false;       // --adaptive (also set by --tolerance and --max-layers)
  double tolerance = 0;        // --tolerance, mm; 0: kDefaultTolerance
  std::size_t max_layers = 0;  // --max-layers; 0: none
  double max_seconds = 0;      // --max-time (slice and print only), s; 0: none
  // Not an option: with supports on, slice and print keep layers thin where thick ones would
  // step out past half a bead on slopes the material holds (the support's overhang angle and
  // bead); analyze and advise plan for D alone.
  geometry::AdaptiveOptions::ThickOverhangs thick_overhangs;
  // Is an adaptive plan asked for (by any of them)?
  bool wanted() const { return adaptive || tolerance > 0 || max_layers > 0 || max_seconds > 0; }
};

// The tolerance of a bare --adaptive, mm: about the bunny's D at PrusaSlicer's 0.15 mm layers.
inline constexpr double kDefaultTolerance = 0.3;

// "1h30m", "90m", "45m30s", "5400s", "2h" in seconds; nullopt for anything else (a bare
// number has no unit).
std::optional<double> parse_duration(std::string_view text);

// The printer's thicknesses as the planner takes them (the first layer its own).
geometry::AllowedThicknesses allowed_thicknesses(const printer::PrinterProfile& machine);

// What the plan measures to keep the printed contour within the tolerance: the printed
// strategy itself, except `best`, planned by mid's D (best's D is never above mid's on a
// layer, and mid is measured several times faster).
std::vector<const geometry::ContourStrategy*> planning_strategies(
    const geometry::ContourStrategy& printed);

struct LayerChoice {
  std::vector<geometry::Layer> layers;
  bool adaptive = false;
  geometry::AdaptivePlan plan;                    // adaptive only
  std::vector<geometry::FlatPlacement> flats;     // both
  std::string planned_by;                         // the strategy whose D the plan measured
  std::string printed;                            // the strategy the layers print
  double thinnest_allowed = 0;                    // the printer's thinnest layer, mm
  double seconds = 0;                             // wall time of the planning
  double budget_seconds = 0;                      // --max-time, s (0: none)
  double estimated_seconds = 0;                   // with a budget: the plan's estimate, s (after
                                                  // app::slice, its G-code's own)
  std::size_t max_layers = 0;                     // --max-layers (0: none)
  std::vector<std::string> notes;                 // --boundaries: the tops left out (BoundaryLayers)
};

// Called with the candidate slabs measured so far.
using PlanningProgress = std::function<void(std::size_t measured)>;

// The estimated print time of a part in these layers, s (for --max-time).
using PrintEstimate = std::function<double(const std::vector<geometry::Layer>& layers)>;

// Uniform at `thickness` (first layer the printer's), or the adaptive plan the request asks
// for, over `stack`'s mesh (its layers are not used). Thicknesses are the printer's. A print-
// time budget needs `estimate`.
LayerChoice choose_layers(const AdaptiveRequest& request, const printer::PrinterProfile& machine,
                          const geometry::LayerStack& stack, double part_height, double thickness,
                          const geometry::ContourStrategy& printed,
                          const PlanningProgress& progress = {},
                          const PrintEstimate& estimate = {});

// "adaptive: 187 layers of 0.15-0.4 mm for D within 0.3 mm (best's D, planned by mid's, which
// best's does not exceed; planned in 1.2 s: ...); 12 layers over it (up to 0.61 mm), the
// thinnest the printer has (0.15 mm) unless said: z 30.10-31.90 (slopes down to 4° from
// horizontal: up to 0.61 mm), ...", with a budget the least tolerance it allows and the cap
// the least total error was found within, the first layer's D where it is over, and the flat
// levels no layer could land.
std::string describe_choice(const LayerChoice& choice);

}  // namespace app
