#include "geometry/contour/best_contour.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>
#include <utility>
#include <vector>

#include "geometry/contour/contour_strategy.h"
#include "geometry/contour/ma_contour.h"
#include "geometry/contour/optimal_height.h"
#include "geometry/contour/section_contours.h"
#include "geometry/core/boundary_grid.h"
#include "geometry/metrics/missed_features.h"
#include "geometry/metrics/volume_deviation.h"
#include "geometry/slab/slab.h"
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

// What best compares on a layer (best_candidates), from the layer's reference and the slab's
// columns. mid's section is cut once: ma's contour takes it where it needs the middle section,
// and optimal-height's search often ends at that very height.
std::vector<BestCandidate> candidates_of(const ContourInput& input,
                                         const LayerReference& reference,
                                         const SlabColumns& columns) {
  const double middle = input.stack.layers()[input.layer].z_mid();
  const Region mid_section = input.stack.cross_section(middle);
  const auto section_at = [&](double z) {
    return z == middle ? mid_section : input.stack.cross_section(z);
  };
  std::vector<BestCandidate> candidates;
  const auto add = [&](std::string_view name, ContourResult result) {
    std::vector<BoundaryPair> missed = missed_features(reference.islands, result.region);
    candidates.push_back({name, std::move(result), std::move(missed)});
  };
  add("mid", {mid_section, middle});
  {
    const SectionDeviation deviation_at(columns);
    const OptimalHeight found = optimal_height_search(input.stack, input.layer, columns,
                                                      deviation_at, input.options.optimal);
    add("optimal-height", {section_at(found.height), found.height});
  }
  add("ma", {ma_contour(reference.slab, reference.islands, section_at, input.options.ma), middle});
  // A section that misses a feature (a tip or a bump between its plane and the slab's ends)
  // competes once more with the feature's own middle section added.
  for (std::size_t k = 0; k < 2; ++k) {
    if (candidates[k].missed.empty()) continue;
    ContourResult patched{with_features(input, reference, candidates[k].result.region,
                                        candidates[k].missed),
                          candidates[k].result.height};
    if (patched.region.loops.size() == candidates[k].result.region.loops.size()) continue;
    add(k == 0 ? "mid+features" : "optimal-height+features", std::move(patched));
  }
  return candidates;
}

// best's own reference of a layer, when the caller has none: slab, footprint, islands and
// surface, no reverse levels (best compares forward D only) and no volume figures.
LayerReference own_reference(const ContourInput& input, Slab slab) {
  MetricOptions metrics;
  metrics.volumes = false;
  metrics.distance.reverse = false;
  return layer_reference(input.stack, input.layer, std::move(slab), metrics);
}

// The reference's columns, or the slab's built here where it has none.
const SlabColumns& columns_of(const ContourInput& input, const LayerReference& reference,
                              std::optional<SlabColumns>& built) {
  if (reference.volumes) return reference.columns;
  built = slab_columns(reference.slab, input.stack.lower(input.layer));
  return *built;
}

}  // namespace

std::vector<BestCandidate> best_candidates(const ContourInput& input) {
  if (input.layer >= input.stack.size()) return {};
  std::optional<LayerReference> own;
  if (!input.reference) own = own_reference(input, slab_of(input.stack, input.layer));
  const LayerReference& reference = own ? *own : *input.reference;
  std::optional<SlabColumns> built;
  return candidates_of(input, reference, columns_of(input, reference, built));
}

BestChoice best_choice(const ContourInput& input) {
  // A prism (slab.h: the walls straight up through the slab, a part's stem or a table's legs,
  // half of many parts' layers) has the same section at every height: mid's is exact (D 0,
  // ΔV 0, every island touched), which no candidate can beat.
  std::optional<Slab> slab;
  if (!input.reference) slab = slab_of(input.stack, input.layer);
  if (is_prism(input.reference ? input.reference->slab : *slab)) {
    BestChoice choice{};
    choice.result = mid_strategy(input);
    choice.chosen = "mid";
    choice.candidate_distance[0] = choice.candidate_distance[1] = 0;  // optimal-height's: mid's
    choice.candidate_distance[2] = kNotMeasured;
    return choice;
  }
  std::optional<LayerReference> own;
  if (!input.reference) own = own_reference(input, std::move(*slab));
  const LayerReference& reference = own ? *own : *input.reference;
  std::optional<SlabColumns> built;
  const SlabColumns& columns = columns_of(input, reference, built);

  constexpr std::size_t kNone = std::numeric_limits<std::size_t>::max();
  struct Candidate : BestCandidate {
    double distance = kNotMeasured;
    double deviation = -1;  // ΔV, once a tie needs it
    std::size_t same_as = kNone;  // a candidate measured before with this very region
    std::optional<BoundaryGrid> walls;  // the region's boundary, for D and ΔV
    const BoundaryGrid& grid() {
      if (!walls) walls.emplace(result.region);
      return *walls;
    }
  };
  std::vector<Candidate> candidates;
  for (BestCandidate& c : candidates_of(input, reference, columns)) {
    candidates.emplace_back();
    static_cast<BestCandidate&>(candidates.back()) = std::move(c);
  }
  DistanceOptions distance_options;
  distance_options.reverse = false;

  // Fewest missed features first: only those candidates are measured. Then the least D, ma
  // first (it wins most layers, so its D refutes the others early): a candidate is measured
  // only until its D is known to be more than a tie above the least so far.
  std::size_t fewest = candidates.front().missed.size();
  for (const Candidate& c : candidates) fewest = std::min(fewest, c.missed.size());
  std::vector<std::size_t> order{2, 0, 1};
  for (std::size_t k = 3; k < candidates.size(); ++k) order.push_back(k);
  // A candidate whose region is one already measured (optimal-height's search often ends
  // at mid's height: 142 of a sphere's 150 layers) takes that one's D: exact if it was, else
  // a lower bound above a threshold at least this one's.
  double least = std::numeric_limits<double>::infinity();
  std::vector<std::size_t> measured;
  // mid's D known (the layer plan's): it stands first, so that ma is measured only until it is
  // seen to lose by more than a tie. The same choice as measuring it: the least D and the
  // candidates within a tie of it do not depend on the order.
  bool mid_known = false;
  if (!std::isnan(input.mid_distance) && candidates[0].missed.size() == fewest) {
    candidates[0].distance = input.mid_distance;
    least = input.mid_distance;
    measured.push_back(0);
    mid_known = true;
  }
  for (std::size_t k : order) {
    Candidate& c = candidates[k];
    if (c.missed.size() != fewest || (k == 0 && mid_known)) continue;
    const auto same = std::find_if(measured.begin(), measured.end(), [&](std::size_t m) {
      return candidates[m].result.region.loops == c.result.region.loops;
    });
    if (same != measured.end()) {
      c.distance = candidates[*same].distance;
      c.same_as = *same;
    } else {
      distance_options.stop_above = least + kDistanceTie;
      c.distance = distance_error(reference.surface, c.grid(), c.missed, distance_options).forward;
      measured.push_back(k);
    }
    least = std::min(least, c.distance);
  }
  BestChoice choice{};
  for (std::size_t k = 0; k < 3; ++k) choice.candidate_distance[k] = candidates[k].distance;

  // ΔV only where a tie needs it.
  const auto volume_of = [&](Candidate& c) {
    // A region measured already under another name has its ΔV too.
    if (c.deviation < 0 && c.same_as != kNone) c.deviation = candidates[c.same_as].deviation;
    if (c.deviation < 0) c.deviation = volume_deviation(columns, c.result.region, c.grid());
    return c.deviation;
  };
  // Of those within a tie of the least D, the least ΔV.
  std::vector<std::size_t> tied;
  for (std::size_t k : order) {
    if (candidates[k].distance <= least + kDistanceTie) tied.push_back(k);
  }
  std::size_t best = tied.front();
  for (std::size_t k : tied) {
    if (k != best && volume_of(candidates[k]) < volume_of(candidates[best])) best = k;
  }
  choice.chosen = candidates[best].name;
  choice.distance = candidates[best].distance;
  choice.missed_features = candidates[best].missed.size();
  choice.result = std::move(candidates[best].result);
  return choice;
}

ContourResult best_strategy(const ContourInput& input) { return best_choice(input).result; }

}  // namespace geometry
