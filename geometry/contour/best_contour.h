// The best contour (issue 11): per layer, whichever of mid, optimal-height and ma has the
// least distance error D (distance_error.h, as analyze measures it: layer_metrics.h); ties
// within 1 um go to the least volume deviation ΔV. So on no layer is its D above mid's or
// ma's, and it misses a feature only where all three do.
//
// Input: a layer of a stack (contour_input.h), with the layer's reference if the caller has
// one; without, it builds one (slab, footprint, surface; the columns only when a tie needs ΔV).
// Output: the chosen region and the height of the candidate chosen; which one it was in
// best_choice() for callers that report it.
// Cost: the three candidates and three measurements, about four times ma's time per layer.
#pragma once

#include <string_view>

#include "geometry/contour/contour_input.h"

namespace geometry {

// D within this of each other is a tie, mm: the distance error's own tolerance.
inline constexpr double kDistanceTie = 1e-3;

ContourResult best_strategy(const ContourInput& input);

// The same, also saying which candidate won and every candidate's D, mm.
struct BestChoice {
  ContourResult result;
  std::string_view chosen;       // "mid", "optimal-height" or "ma"
  double distance = 0;           // the chosen one's D
  double candidate_distance[3];  // mid, optimal-height, ma
};
BestChoice best_choice(const ContourInput& input);

}  // namespace geometry
