// Contour strategies: which planar region R_i a layer extrudes (DESIGN.md §2).
//
// The printer deposits the prism R_i x [z_lo, z_hi]; a strategy picks R_i from the slab. Each
// is registered once, in the table of contour_strategy.cpp: its name, a one-line description,
// its colour in analyze's plots and the function that makes the region (contour_input.h).
// `--contour`, `--contours`, `--help`, `mahost slice`, `mahost analyze` and its plots all read
// the table, so adding a strategy is one table entry plus the file of its function.
//   lower           cross-section at z_lo (the paper's "traditional" baseline)
//   mid             cross-section at the layer's middle (PrusaSlicer, Slic3r, CuraEngine)
//   optimal-height  the cross-section at the height minimising the volume deviation (§3.1)
//   ma              the paper's medial-axis contour of the slab's boundary pair (§3.2-3.3)
//   best            per layer, whichever of mid, optimal-height and ma has the least distance
//                   error D (ties within 1 um broken by volume deviation): best_contour.h
// Every strategy returns a valid Region (no self-intersections); an empty slab gives an
// empty Region.
#pragma once

#include <cstddef>
#include <limits>
#include <span>
#include <string>
#include <string_view>

#include "geometry/contour/contour_input.h"
#include "geometry/contour/ma_contour.h"
#include "geometry/contour/optimal_height.h"
#include "geometry/core/polygon.h"
#include "geometry/slicing/layer_stack.h"

namespace geometry {

struct ContourOptions {
  MaOptions ma;
  OptimalHeightOptions optimal;
};

struct ContourStrategy {
  std::string_view name;         // --contour's value; the name in CSV, JSON, G-code headers
  std::string_view description;  // one line for --help: lower case, no full stop
  std::string_view colour;       // in analyze's plots and drawings, "#rrggbb"
  ContourFunction contour;       // makes the region (contour_input.h)
  // For a strategy that prints the model's section at one height (lower, mid): that height
  // for a layer; null for the others. The layer plan measures such regions more cheaply
  // (plan/slab_error.h).
  double (*cuts_at)(const Layer& layer) = nullptr;
};

// Every strategy, in the order --help lists them and analyze compares them by default.
std::span<const ContourStrategy> contour_strategies();

// The strategy of that name ('_' read as '-': "optimal_height" too), or null.
const ContourStrategy* find_contour_strategy(std::string_view name);

// A strategy the code names (analyze's baselines lower and mid, slice's default ma); throws
// std::logic_error if the table has none of that name.
const ContourStrategy& contour_strategy(std::string_view name);

// The strategies' names joined: "lower, mid, optimal-height, ma" (for help and errors).
std::string contour_names(std::string_view separator = ", ");

// The region of one layer; an out-of-range layer gives an empty one. mid_distance: mid's D on
// the layer where the caller has measured it (ContourInput::mid_distance), else NaN.
Region layer_contour(const LayerStack& stack, std::size_t layer, const ContourStrategy& strategy,
                     const ContourOptions& options = {},
                     double mid_distance = std::numeric_limits<double>::quiet_NaN());

}  // namespace geometry
