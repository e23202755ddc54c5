// The layer plan (DESIGN.md §2): where a part's layer boundaries go,
// z_0 = 0 < z_1 < ... < z_n, each thickness z_i - z_{i-1} one the printer allows and the last
// boundary at or above the part's top.
//
// Uniform: every layer `thickness` (the first its own), except that a flat level
// (flat_levels.h: a horizontal top, floor or step) lands on a boundary wherever the allowed
// thicknesses reach it: the layers just below it are made a step thicker or thinner (with any
// thickness allowed and thinner: every layer of the segment a little), so an 8.00 mm part
// prints 8.00 mm tall. Whichever is the nearer count of layers; half way, thinner ones (a
// layer no thicker than asked follows a slope as closely and keeps an overhang within its
// reach: a 20 mm part on the UP Plus 2 at 0.2 mm ends in two 0.15 mm layers, not 0.25). With
// no flat level above the first layer this is uniform_layers() exactly.
//
// Adaptive, by the exact error of the contour printed. With a tolerance: every layer above the
// first within it (its distance error D, slab_error.h: the D `mahost analyze` reports for that
// layer and contour) or, where no allowed thickness meets it, the thinnest; among such plans,
// in this order: the fewest flat levels crossed (each lands on a boundary wherever an allowed
// layer reaches it), the layers holding a flat level no allowed layer reaches over the
// tolerance by the least height, then by the least D (Alexa et al.'s min-max objective for
// the layers a flat level forces over), the fewest layers over the tolerance, the fewest
// layers, and the least total error, the volume the layers' sections leave off the surface
// (swept_volume.h: the volume deviation of the mid contour, exact where the surface is one
// sheet over each point of a layer). A plan ends at the lowest height the layers reach at or
// above the part's top (with a printer of any thickness, at the top): never more than the
// printer's step above it; a last layer there that prints nothing (AdaptiveOptions::prints)
// is left out.
// With a budget of max_layers: the least tolerance whose plan has at most that many layers,
// then the least total error in at most as many layers (a dynamic program over heights and
// layers used) with none over that plan's largest D, in
// this order, against a cap: the terms of landing (flat levels crossed, the layers a flat
// level forces over the cap, those thicker than the thinnest over it); the lowest end (as
// above); the most layers (the budget is the user's: the bunny in 331 layers ends at its top
// in 331, not in 330 at 50.05 mm, which would leave 0.3 mm fewer of its thinnest layers over
// the cap); the thinnest layers over the cap, the least height of them, then the least far
// over (the sum of their D past it times their thickness); the least total error. The cap is
// the tolerance or, if higher, the by-height 95th percentile of D of that plan's layers less
// its thinnest ones above the 95th percentile of them all (no plan brings those under it;
// counted, they would lift the cap by their share of the height: the bunny's hole-filled
// base, 2 mm of 0.15 mm layers of D up to 4.7 mm, from 0.447 to 0.63 mm at 290 layers). Measured by
// tests/bench/plan_vs_peers.sh against the whole percentile, the swept volume alone over the
// thinnest and the most layers only among plans as good: the bunny's P95h D 0.442 to 0.467 mm
// at 207 to 332 layers, not 0.456 to 0.599 (290 layers: 0.483 -> 0.442, under Cura's 0.469),
// its ΔV up to 2.2% higher (207 layers: 130.8 -> 133.6 mm^3).
// With max_layers (and for each count a print-time budget, `fits`, tries), where that plan
// leaves more than 5% of its height (the fixed first layer counted) over its cap, the cap aims
// at the by-height 95th percentile itself: the least cap (bisected between the cap and that
// plan's own whole percentile, to 1% of the cap) at which the plan of the least height over it,
// at any thickness (no landing term, no excess ranked: the 5% a percentile leaves out may hold
// thicker layers, which spend fewer of the budget's layers there), leaves at most 5% of the
// height over it; taken if its percentile is lower, its largest D as printed
// (AdaptiveOptions::printed) and its swept volume no more. The planned D of a section contour
// bounds the printed one from above, loosely where the section fills a hole the printed
// contour keeps: the bottle's punt, mid's D 11 mm against best's 0.3,
// is no ceiling for a 0.25 mm layer on its shoulder, 1.1 mm planned and 0.795 printed, where
// the least tolerance's plan prints nothing over 0.6 mm. A sphere cap's top, where D grows
// without bound, is such a 5%: the cap 17 mm tall in 65 layers ends a 0.15 mm layer at 16.15
// mm and puts 0.25, 0.2 and 0.25 mm layers above it, under the top layer's D (1.3 mm, a flat
// level no allowed layer lands), P95h D 0.2568 -> 0.2336 mm and ΔV 70.55 -> 69.36 mm^3 by
// tests/bench/judge.py (CuraEngine 0.3's 65 layers: 0.2360, 72.45); in 95 layers the swept
// volume grows, so not. Alexa, Hildebrand and
// Lefebvre's min-max objective ("Optimal Discrete Slicing", ACM TOG 2017) for the tolerance,
// and their min-sum for the error, under it.
// The optimum over all allowed thickness sequences is a shortest path over the grid of
// reachable heights. Measuring every candidate slab exactly costs a few ms each, thousands of
// them, so the path is found lazily (LazySP): every candidate not yet measured counts at a
// lower bound of its D (0, or what measuring it or a slab inside it with the same section
// proved), the best path is found, the slabs on it not yet settled are measured (in parallel:
// with a tolerance, only until each is seen to be within it or past it, since that is all a
// path's cost asks; the next few first from their end sections alone, which refuses most
// candidates without cutting their surface), and the search runs again until every layer of
// the path is settled. The swept volume is exact for every candidate from the start. So the
// path is the optimum over every allowed sequence, not only over the slabs measured. Every
// layer of the result is then measured exactly.
//
// Units mm. A part of no height gets no layers. Total: any options give a plan (a tolerance of
// 0 gives the thinnest layers everywhere, all over it where D > 0).
#pragma once

#include <cstddef>
#include <functional>
#include <span>
#include <vector>

#include "geometry/contour/contour_strategy.h"
#include "geometry/plan/flat_levels.h"
#include "geometry/plan/slab_error.h"
#include "geometry/slicing/layer_stack.h"

namespace geometry {

// What the printer allows, mm: the thicknesses `listed`, or if none are listed min, min +
// step, ..., max (step 0: any in [min, max]); the first layer `first` thick (0: any allowed).
struct AllowedThicknesses {
  std::vector<double> listed;
  double min = 0.15, max = 0.4, step = 0.05;
  double first = 0;
  double thinnest() const;
  double thickest() const;
  bool allows(double thickness) const;  // within 0.1 nm
};

// Where a flat level ended up: on a boundary, or not (unreachable by the allowed thicknesses,
// or too close to another one), and then the nearest boundary.
struct FlatPlacement {
  double z = 0;         // the flat level, mm
  double boundary = 0;  // the nearest layer boundary, mm
  bool on_boundary() const { return boundary == z; }
};

struct UniformPlan {
  std::vector<Layer> layers;
  std::vector<FlatPlacement> flats;  // every flat level above z = 0 and not above the top
};

UniformPlan uniform_plan(double part_height, double thickness, const AllowedThicknesses& allowed,
                         std::span<const FlatLevel> flats);

struct AdaptiveOptions {
  double tolerance = 0.3;       // D within this, mm
  std::size_t max_layers = 0;   // > 0: the least tolerance with at most this many layers instead
  // Set (and max_layers 0): how far a plan is over a budget, a print time's seconds past it
  // (at most 0: within it); the max_layers plan of the most layers whose plan is within it
  // instead (a bisection on the count: a print time nearly grows with it). Called only from
  // the calling thread; the search takes a plan within it for one of fewer layers.
  std::function<double(const std::vector<Layer>& layers)> overrun;
  // The contours a layer may print; a layer meets the tolerance when one of them does (one
  // kind for a plain strategy; mid, ma and optimal-height for `best`). Cheapest first.
  std::vector<const ContourStrategy*> contours{&contour_strategy("mid")};
  // The contour the layers print, where the plan measures others in its place (best, planned
  // by mid's D, which best's does not exceed); null: the first of `contours`. A budget's
  // by-height plan is weighed against its base by the largest D as printed (budget_by_height).
  const ContourStrategy* printed = nullptr;
  // With supports (overhang_angle > 0): a layer thicker than the thinnest is refused where it
  // would have more than min_area mm^2 of overhang only for being thick (slab_bound.h's
  // ThickOverhangEstimate), so that supports go where the part's slopes need them and not
  // where the plan's thick layers step out past half a bead.
  struct ThickOverhangs {
    double overhang_angle = 0;  // degrees from vertical; 0: no such limit
    double bead_width = 0.45;   // mm
    double min_area = 0.2;      // mm^2
  } thick_overhangs;
  // Set: whether a layer prints anything (app: its contour's toolpaths; asked of the layers
  // into a plan's possible ends, a dozen or so). A last layer that prints nothing (a tip no
  // bead fits in: the tiers' pyramid above 24.2 mm, narrower than 0.3 mm) is not counted
  // against a budget, has no D of its own in the plan's terms, and is left out of the plan,
  // which then ends at the top of the layer below it: the tiers in a budget of 122 layers
  // print 122, not 121 and an empty one. Only the last layer: a tip taller than the thinnest
  // layer could leave an empty one below it counted.
  std::function<bool(const Layer& layer)> prints;
  double grid = 0.02;           // planning resolution when the printer's step is 0, mm
  bool measure_all = false;     // measure every candidate first (to check the lazy search)
  // Each round's search over the whole grid from the bed, none of its costs kept from the round
  // before, no node above the measured ones left to the untouched grid's best way on, each
  // candidate's step worked out again (to check that those savings are exact).
  bool search_afresh = false;
  SlabErrorOptions error;
};

// Why a layer's D is over the tolerance.
enum class OverTolerance : char {
  none,             // it is not
  first_layer,      // the printer's fixed first layer: the tolerance is for the layers above it
  flat_level,       // it crosses a flat level that no allowed layer lands
  landing,          // thicker than the thinnest, to land a flat level or the top that the
                    // thinnest layers (within the tolerance there are no others) miss
  height_share,     // thicker than the thinnest, in the share of the height a budget's
                    // by-height cap leaves out (AdaptivePlan::cap_by_height), where it spends
                    // fewer of the budget's layers
  missed_feature,   // its contour leaves out a tip or bump of the slab (missed_features.h)
  shallow_surface,  // the surface leans so little that even the thinnest layer steps too far
};

struct AdaptivePlan {
  std::vector<Layer> layers;
  // Per layer, measured exactly: D of the first of `contours` that meets the tolerance, or the
  // least of them where none does (mm).
  std::vector<double> distance;
  std::vector<double> swept;         // per layer: swept_volume.h's U, mm^3
  // Per layer: D within the tolerance (with a budget, within `cap`), and if not, why.
  std::vector<char> met;
  std::vector<OverTolerance> why;
  std::vector<double> lean;          // per layer over it for its surface: the least angle of
                                     // that surface from horizontal, degrees (else 90)
  double tolerance = 0;              // asked, or for a budget the least one reached
  // With a budget: the least swept volume was found with every layer above the first within
  // `cap` or counted over it, and none above `ceiling` (the least tolerance's plan's by-height
  // 95th percentile of D less its thinnest layers above it, or the tolerance if higher, and
  // its largest D), mm; else 0. `cap_by_height`: the cap is the least that leaves at most 5%
  // of the height over it, at any thickness (the plan's by-height 95th percentile).
  double cap = 0, ceiling = 0;
  bool cap_by_height = false;
  std::size_t unmet = 0;             // layers above the first not `met`
  std::vector<FlatPlacement> flats;
  // The search: candidate slabs (edges of the height grid), how many of them were measured
  // (exactly, or until seen to be within the tolerance or past it; each counted once), and how
  // many times the shortest path was found.
  std::size_t candidates = 0, measured = 0, rounds = 0;
  // Candidate slabs refused for the overhang a thick layer there would have (thick_overhangs).
  std::size_t refused_for_overhangs = 0;
};

// Called with the number of candidate slabs measured so far, from the calling thread.
using PlanProgress = std::function<void(std::size_t measured)>;

AdaptivePlan adaptive_plan(const LayerStack& stack, double part_height,
                           const AllowedThicknesses& allowed, std::span<const FlatLevel> flats,
                           const AdaptiveOptions& options, const PlanProgress& progress = {});

}  // namespace geometry
