// The optimal-height contour (paper §3.1, eq. 7): the cross-section at the height h in
// [z_lo, z_hi] whose prism has the least volume deviation ΔV(h) = vol(S_i △ C(h) x [z_lo, z_hi]).
//
// ΔV(h) need not be convex (the paper's CATIA experiment used simulated annealing for that
// reason, 90 s per slice), so the search first scans `coarse_samples` equally spaced heights
// (both ends included), then narrows the bracket around the best of them by golden-section
// search until it is shorter than `tolerance`. Each evaluation is one cross-section and one
// exact ΔV (volume_deviation.h). A minimum between two coarse samples that is not in the best
// sample's bracket can be missed; the coarse scan makes that a minimum narrower than t/8.
//
// Input: the layer stack, a layer index, and the slab's columns (slab_columns.h) for it.
// Output: the best height found, its ΔV (mm^3), its section, and how many heights were tried.
// Zero-thickness or out-of-range layer: h = z_lo, the section there, no search.
#pragma once

#include <cstddef>

#include "geometry/layer_stack.h"
#include "geometry/polygon.h"
#include "geometry/slab_columns.h"

namespace geometry {

struct OptimalHeightOptions {
  int coarse_samples = 9;    // heights scanned first, ends included (>= 3)
  double tolerance = 1e-4;   // mm: the final bracket's length
};

struct OptimalHeight {
  double height = 0;
  double volume_deviation = 0;
  Region section;
  int evaluations = 0;
};

OptimalHeight optimal_height(const LayerStack& stack, std::size_t layer,
                             const SlabColumns& columns, const OptimalHeightOptions& options = {});

// The same, building the slab's columns itself.
OptimalHeight optimal_height(const LayerStack& stack, std::size_t layer,
                             const OptimalHeightOptions& options = {});

}  // namespace geometry
