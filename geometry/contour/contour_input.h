// What a contour strategy is given and what it gives back. A strategy is one function,
//   ContourResult strategy(const ContourInput& input),
// in its own file, and one entry in the table of contour_strategy.cpp (name, description, plot
// colour, that function); contour_strategy.h is the table's interface.
#pragma once

#include <cstddef>
#include <limits>

#include "geometry/core/polygon.h"
#include "geometry/metrics/layer_metrics.h"
#include "geometry/slicing/layer_stack.h"

namespace geometry {

struct ContourOptions;  // every strategy's options (contour_strategy.h)

struct ContourInput {
  const LayerStack& stack;
  std::size_t layer;  // < stack.size(): layer_contour and analyze_layer check it
  const ContourOptions& options;
  // What the caller has prepared of this layer, or null. analyze measures every region
  // against it (layer_metrics.h), so a strategy takes the slab, its islands and (if
  // reference->volumes) its columns from here rather than building them again; a strategy
  // that measures candidate regions measures them against it, or builds one
  // (layer_reference) when it is null, as `mahost slice` leaves it.
  const LayerReference* reference = nullptr;
  // mid's D on this layer (distance_error.h, forward, as analyze measures it) when the caller
  // has it already: the layer plan measures it for every layer it plans by mid
  // (plan/layer_plan.h, AdaptivePlan::distance). best takes it instead of measuring mid
  // again. NaN: not known.
  double mid_distance = std::numeric_limits<double>::quiet_NaN();
};

struct ContourResult {
  Region region;      // valid (no self-intersections); empty for an empty slab
  double height = 0;  // the height the region stands for, mm: where a section was cut (the
                      // chosen height for optimal-height), the layer's middle for ma
};

using ContourFunction = ContourResult (*)(const ContourInput& input);

}  // namespace geometry
