#include "geometry/contour/best_contour.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <vector>

#include "geometry/contour/ma_contour.h"
#include "geometry/contour/optimal_height.h"
#include "geometry/contour/section_contours.h"
#include "geometry/core/boundary_grid.h"
#include "geometry/metrics/missed_features.h"
#include "geometry/metrics/volume_deviation.h"
#include "geometry/slab/slab_columns.h"

namespace geometry {

namespace {

// `region` with, in each island of the slab's footprint it misses, the model's section at the
// middle of that island's own height range inside the slab: a tip between a section's plane
// and the slab's end printed as its middle, as mid prints a whole layer. Disjoint from the
// region (a missed island does not touch it).
Region with_features(const ContourInput& input, const LayerReference& reference,
                     const Region& region, const std::vector<BoundaryPair>& missed) {
  Region patched = region;
  for (const BoundaryPair& island : missed) {
    const BoundaryGrid outline(Region{{island.outer}});
    double low = INFINITY, high = -INFINITY;
    for (const auto& facet : reference.slab.facets) {
      Vec2 centre{0, 0};
      for (const Vec3& v : facet) centre = centre + (1.0 / facet.size()) * Vec2{v.x, v.y};
      if (outline.winding_number(centre) == 0) continue;
      for (const Vec3& v : facet) low = std::min(low, v.z), high = std::max(high, v.z);
    }
    if (!(high > low)) continue;
    for (const Loop& loop : input.stack.cross_section(0.5 * (low + high)).loops) {
      if (!loop.empty() && outline.winding_number(loop.front()) != 0) patched.loops.push_back(loop);
    }
  }
  return patched;
}

}  // namespace

BestChoice best_choice(const ContourInput& input) {
  std::optional<LayerReference> own;
  if (!input.reference) {
    MetricOptions metrics;
    metrics.volumes = false;
    own = layer_reference(input.stack, input.layer, metrics);
  }
  const LayerReference& reference = own ? *own : *input.reference;
  const ContourInput candidate_input{input.stack, input.layer, input.options, &reference};
  DistanceOptions distance_options;
  distance_options.reverse = false;

  struct Candidate {
    std::string_view name;
    ContourResult result;
    std::size_t missed = 0;
    double distance = 0;
    double deviation = -1;  // ΔV, once a tie needs it
  };
  std::vector<Candidate> candidates;
  const auto add = [&](std::string_view name, ContourResult result) {
    const std::vector<BoundaryPair> missed = missed_features(reference.islands, result.region);
    const double d =
        distance_error(reference.surface, BoundaryGrid(result.region), missed, distance_options)
            .forward;
    candidates.push_back({name, std::move(result), missed.size(), d});
    return missed;
  };
  BestChoice choice{};
  const std::array<std::vector<BoundaryPair>, 2> section_missed{
      add("mid", mid_strategy(candidate_input)),
      add("optimal-height", optimal_height_strategy(candidate_input))};
  add("ma", ma_strategy(candidate_input));
  for (std::size_t k = 0; k < 3; ++k) choice.candidate_distance[k] = candidates[k].distance;
  // A section that misses a feature (a tip or a bump between its plane and the slab's ends)
  // competes once more with the feature's own middle section added.
  for (std::size_t k = 0; k < section_missed.size(); ++k) {
    if (section_missed[k].empty()) continue;
    ContourResult patched{with_features(input, reference, candidates[k].result.region,
                                        section_missed[k]),
                          candidates[k].result.height};
    if (patched.region.loops.size() == candidates[k].result.region.loops.size()) continue;
    add(k == 0 ? "mid+features" : "optimal-height+features", std::move(patched));
  }

  // ΔV only where a tie needs it, with the slab's columns built then if the reference has none.
  const SlabColumns* columns = reference.volumes ? &reference.columns : nullptr;
  SlabColumns built;
  const auto volume_of = [&](Candidate& c) {
    if (c.deviation < 0) {
      if (!columns) {
        built = slab_columns(reference.slab, input.stack.lower(input.layer));
        columns = &built;
      }
      c.deviation = volume_deviation(*columns, c.result.region, BoundaryGrid(c.result.region));
    }
    return c.deviation;
  };
  // Fewest missed features, then least D, then least ΔV.
  std::size_t best = 0;
  for (std::size_t k = 1; k < candidates.size(); ++k) {
    Candidate& c = candidates[k];
    Candidate& b = candidates[best];
    if (c.missed != b.missed) {
      if (c.missed < b.missed) best = k;
      continue;
    }
    if (c.distance < b.distance - kDistanceTie ||
        (c.distance <= b.distance + kDistanceTie && volume_of(c) < volume_of(b))) {
      best = k;
    }
  }
  choice.chosen = candidates[best].name;
  choice.distance = candidates[best].distance;
  choice.missed_features = candidates[best].missed;
  choice.result = std::move(candidates[best].result);
  return choice;
}

ContourResult best_strategy(const ContourInput& input) { return best_choice(input).result; }

}  // namespace geometry
