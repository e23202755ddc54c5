// The layer plan (issue 11; DESIGN.md §2): where a part's layer boundaries go,
// z_0 = 0 < z_1 < ... < z_n, each thickness z_i - z_{i-1} one the printer allows and the last
// boundary at or above the part's top.
//
// Uniform: every layer `thickness` (the first its own), except that a flat level
// (flat_levels.h: a horizontal top, floor or step) lands on a boundary wherever the allowed
// thicknesses reach it: the layers just below it are made a step thicker or thinner (with any
// thickness allowed and thinner: every layer of the segment a little), so an 8.00 mm part
// prints 8.00 mm tall. Whichever is the nearer count of layers; half way, thinner ones (a
// layer no thicker than asked follows a slope as closely and keeps an overhang within its
// reach: a 20 mm part on the UP Plus 2 at 0.2 mm ends in two 0.15 mm layers, not 0.25). With no flat level above the first layer this is
// uniform_layers() exactly.
//
// Adaptive, by the exact error of the contour printed: the fewest layers such that every
// layer's distance error D (slab_error.h: the D `mahost analyze` reports for that layer and
// contour) is within `tolerance`; where no allowed thickness meets it (a nearly flat surface),
// that layer is the thinnest and counted as unmet. Flat levels land on boundaries first of all
// (a plan crossing fewer of them always wins), then fewest unmet layers, then fewest layers.
// Or, with max_layers, the least tolerance whose plan has at most that many layers; or, with
// `fits` (a print-time budget, say), the least one whose plan it accepts, to within 2%.
// The optimum over all allowed thickness sequences is a shortest path over the grid of
// reachable heights (Alexa, Hildebrand, Lefebvre, "Optimal Discrete Slicing", ACM TOG 2017).
// Measuring every candidate slab exactly costs a few ms each, thousands of them, so the path
// is found lazily: each candidate's D is first taken as a cheap estimate (slab_bound.h), the
// shortest path is found, the slabs on it not yet measured are measured (in parallel: only
// until each is seen to be within the tolerance or past it, since that is all a path's cost
// asks; with a budget, exactly), and the search runs again until every layer of the path is
// measured. Every layer of the result is then measured exactly; the path is the optimum among paths whose unmeasured slabs are
// at least as good as estimated, which is the true optimum wherever the estimate does not
// exceed the exact D (tests/bench/bench_plan.cpp compares with measuring every candidate).
//
// Units mm. A part of no height gets no layers. Total: any options give a plan (a tolerance of
// 0 gives the thinnest layers everywhere, all unmet where D > 0).
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
  // Set (and max_layers 0): the least tolerance whose plan this accepts instead. Called only
  // from the calling thread; the search takes a plan it accepts for one with more tolerance.
  std::function<bool(const std::vector<Layer>& layers)> fits;
  // The contours a layer may print; a layer meets the tolerance when one of them does (one
  // kind for a plain strategy; mid, ma and optimal-height for `best`). Cheapest first.
  std::vector<const ContourStrategy*> contours{&contour_strategy("mid")};
  // With supports (overhang_angle > 0): a layer thicker than the thinnest is refused where it
  // would have more than min_area mm^2 of overhang only for being thick (slab_bound.h's
  // ThickOverhangEstimate), so that supports go where the part's slopes need them and not
  // where the plan's thick layers step out past half a bead.
  struct ThickOverhangs {
    double overhang_angle = 0;  // degrees from vertical; 0: no such limit
    double bead_width = 0.45;   // mm
    double min_area = 0.2;      // mm^2
  } thick_overhangs;
  double grid = 0.02;           // planning resolution when the printer's step is 0, mm
  bool measure_all = false;     // measure every candidate first (to check the lazy search)
  SlabErrorOptions error;
};

struct AdaptivePlan {
  std::vector<Layer> layers;
  // Per layer, measured exactly: D of the first of `contours` that meets the tolerance, or the
  // least of them where none does (mm).
  std::vector<double> distance;
  std::vector<char> met;             // per layer: D within the tolerance
  double tolerance = 0;              // asked, or for max_layers the least one reached
  std::size_t unmet = 0;             // layers whose D exceeds it (each the thinnest)
  std::vector<FlatPlacement> flats;
  // The search: candidate slabs (edges of the height grid), how many were measured (exactly,
  // or until seen to be within the tolerance or past it), and how many times the shortest
  // path was found.
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
