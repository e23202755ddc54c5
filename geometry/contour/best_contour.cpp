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

// Indices of the candidates, in best_candidates' order; the +features ones follow.
constexpr std::size_t kMid = 0, kOptimal = 1, kMa = 2;

// A layer's candidates as best makes them: mid's section (cut once: ma's contour takes it
// where it needs the middle section, and optimal-height's search often ends at that very
// height) and ma's contour first, optimal-height only when asked (add_optimal), each section
// that misses a feature once more with the feature's own middle section added.
class CandidateMaker {
 public:
  CandidateMaker(const ContourInput& input, const LayerReference& reference)
      : input_(input), reference_(reference),
        middle_(input.stack.layers()[input.layer].z_mid()),
        mid_section_(input.stack.cross_section(middle_)) {}

  // mid, an empty slot for optimal-height (no missed features counted: not made), ma, and
  // mid+features where mid misses a feature.
  std::vector<BestCandidate> first() {
    std::vector<BestCandidate> candidates;
    add(candidates, "mid", {mid_section_, middle_});
    candidates.push_back({"optimal-height", {}, {}});
    add(candidates, "ma",
        {ma_contour(reference_.slab, reference_.islands,
                    [&](double z) { return section_at(z); }, input_.options.ma),
         middle_});
    add_features(candidates, kMid, "mid+features");
    return candidates;
  }

  // optimal-height into its slot, and optimal-height+features where it misses a feature.
  // Keeps the search's SectionDeviation for section_deviation().
  void add_optimal(std::vector<BestCandidate>& candidates, const SlabColumns& columns) {
    deviation_at_.emplace(columns);
    const OptimalHeight found = optimal_height_search(input_.stack, input_.layer, columns,
                                                      *deviation_at_, input_.options.optimal);
    optimal_deviation_ = found.volume_deviation;
    ContourResult result{section_at(found.height), found.height};
    candidates[kOptimal].missed = missed_features(reference_.islands, result.region);
    candidates[kOptimal].result = std::move(result);
    add_features(candidates, kOptimal, "optimal-height+features");
  }

  // ΔV of mid's or optimal-height's section as the search figures it (optimal_height.h: the
  // metric's volume_deviation of the section to ~1e-8 relative), once the search has run;
  // NaN for any other candidate or before.
  double section_deviation(std::size_t k) const {
    if (!deviation_at_) return std::nan("");
    if (k == kMid) return (*deviation_at_)(middle_);
    if (k == kOptimal) return optimal_deviation_;
    return std::nan("");
  }

 private:
  Region section_at(double z) const {
    return z == middle_ ? mid_section_ : input_.stack.cross_section(z);
  }
  void add(std::vector<BestCandidate>& candidates, std::string_view name, ContourResult result) {
    std::vector<BoundaryPair> missed = missed_features(reference_.islands, result.region);
    candidates.push_back({name, std::move(result), std::move(missed)});
  }
  // A section that misses a feature (a tip or a bump between its plane and the slab's ends)
  // competes once more with the feature's own middle section added.
  void add_features(std::vector<BestCandidate>& candidates, std::size_t k, std::string_view name) {
    if (candidates[k].missed.empty()) return;
    ContourResult patched{with_features(input_, reference_, candidates[k].result.region,
                                        candidates[k].missed),
                          candidates[k].result.height};
    if (patched.region.loops.size() == candidates[k].result.region.loops.size()) return;
    add(candidates, name, std::move(patched));
  }

  const ContourInput& input_;
  const LayerReference& reference_;
  double middle_;
  Region mid_section_;
  std::optional<SectionDeviation> deviation_at_;
  double optimal_deviation_ = 0;
};

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
  CandidateMaker maker(input, reference);
  std::vector<BestCandidate> candidates = maker.first();
  maker.add_optimal(candidates, columns_of(input, reference, built));
  // In best_candidates' order: mid, optimal-height, ma, then the +features ones.
  return candidates;
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
    choice.candidate_distance[kMid] = choice.candidate_distance[kOptimal] = 0;  // optimal-height's: mid's
    choice.candidate_distance[kMa] = kNotMeasured;
    return choice;
  }
  std::optional<LayerReference> own;
  if (!input.reference) own = own_reference(input, std::move(*slab));
  const LayerReference& reference = own ? *own : *input.reference;
  // The slab's columns only for optimal-height's search or a ΔV: a layer ma wins by more than
  // a tie needs neither.
  std::optional<SlabColumns> built;
  const SlabColumns* columns_built = nullptr;
  const auto columns = [&]() -> const SlabColumns& {
    if (!columns_built) columns_built = &columns_of(input, reference, built);
    return *columns_built;
  };

  constexpr std::size_t kNone = std::numeric_limits<std::size_t>::max();
  constexpr std::size_t kNotMade = std::numeric_limits<std::size_t>::max();
  struct Candidate : BestCandidate {
    bool made = true;
    double distance = kNotMeasured;
    double deviation = -1;  // ΔV, once a tie needs it
    std::size_t same_as = kNone;  // a candidate measured before with this very region
    std::optional<BoundaryGrid> walls;  // the region's boundary, for D and ΔV
    std::size_t missed_count() const { return made ? missed.size() : kNotMade; }
    const BoundaryGrid& grid() {
      if (!walls) walls.emplace(result.region);
      return *walls;
    }
  };
  CandidateMaker maker(input, reference);
  std::vector<Candidate> candidates;
  const auto take = [&](std::vector<BestCandidate>& made) {
    for (std::size_t k = candidates.size(); k < made.size(); ++k) {
      candidates.emplace_back();
      static_cast<BestCandidate&>(candidates.back()) = std::move(made[k]);
    }
  };
  std::vector<BestCandidate> made = maker.first();
  take(made);
  candidates[kOptimal].made = false;
  DistanceOptions distance_options;
  distance_options.reverse = false;

  // Fewest missed features first: only those candidates are measured. Then the least D, ma
  // first (it wins most layers, so its D refutes the others early): a candidate is measured
  // only until its D is known to be more than a tie above the least so far. A candidate whose
  // region is one already measured (optimal-height's search often ends at mid's height: 142
  // of a sphere's 150 layers) takes that one's D: exact if it was, else a lower bound above a
  // threshold at least this one's.
  std::size_t fewest = kNotMade;
  double least = std::numeric_limits<double>::infinity();
  std::vector<std::size_t> measured;
  // mid's D known (the layer plan's): taken as measured, first, so that ma is measured only
  // until it is seen to lose by more than a tie. The same choice as measuring it: the least D
  // and the candidates within a tie of it do not depend on the order.
  const bool mid_known = !std::isnan(input.mid_distance);
  if (mid_known) candidates[kMid].distance = input.mid_distance;
  // Measures the made candidates of fewest missed features not measured yet, in `order`
  // (indices past the candidates skipped).
  const auto measure = [&](const std::vector<std::size_t>& order) {
    for (const Candidate& c : candidates) fewest = std::min(fewest, c.missed_count());
    least = std::numeric_limits<double>::infinity();
    for (std::size_t m : measured) {
      if (candidates[m].missed_count() == fewest) least = std::min(least, candidates[m].distance);
    }
    if (mid_known && candidates[kMid].missed_count() == fewest &&
        std::find(measured.begin(), measured.end(), kMid) == measured.end()) {
      measured.insert(measured.begin(), kMid);
      least = std::min(least, candidates[kMid].distance);
    }
    for (std::size_t k : order) {
      if (k >= candidates.size()) continue;
      Candidate& c = candidates[k];
      if (c.missed_count() != fewest) continue;
      if (std::find(measured.begin(), measured.end(), k) != measured.end()) continue;
      const auto same = std::find_if(measured.begin(), measured.end(), [&](std::size_t m) {
        return candidates[m].result.region.loops == c.result.region.loops;
      });
      if (same != measured.end()) {
        c.distance = candidates[*same].distance;
        c.same_as = *same;
      } else {
        distance_options.stop_above = least + kDistanceTie;
        c.distance = distance_error(reference.surface, c.grid(), c.missed, distance_options).forward;
      }
      measured.push_back(k);
      least = std::min(least, c.distance);
    }
  };
  measure({kMa, kMid, 3});
  // optimal-height minimises ΔV, not D: it is searched only where a section is within a tie
  // of the least D (mid or mid+features, whose height it is free to leave), or where no
  // section misses as few features as ma (a height that catches the tip may); the header
  // says what that leaves out.
  const auto section_contends = [&](std::size_t k) {
    return k < candidates.size() && candidates[k].missed_count() == fewest &&
           candidates[k].distance <= least + kDistanceTie;
  };
  const bool section_of_fewest = (candidates[kMid].missed_count() == fewest) ||
                                 (candidates.size() > 3 && candidates[3].missed_count() == fewest);
  if (section_contends(kMid) || section_contends(3) || !section_of_fewest) {
    maker.add_optimal(made, columns());
    candidates[kOptimal].made = true;
    static_cast<BestCandidate&>(candidates[kOptimal]) = std::move(made[kOptimal]);
    take(made);
    measure({kOptimal, 3, 4});
  }
  BestChoice choice{};
  for (std::size_t k = 0; k < 3; ++k) {
    const Candidate& c = candidates[k];
    choice.candidate_distance[k] =
        c.missed_count() == fewest && std::find(measured.begin(), measured.end(), k) != measured.end()
            ? c.distance
            : kNotMeasured;
  }

  // ΔV only where a tie needs it: a section's as the search figured it, where it ran, else
  // the metric's; a region measured under two names has one figure.
  const auto root = [&](std::size_t k) {
    return candidates[k].same_as == kNone ? k : candidates[k].same_as;
  };
  const auto volume_of = [&](std::size_t k) {
    const std::size_t r = root(k);
    Candidate& c = candidates[r];
    if (c.deviation >= 0) return c.deviation;
    for (std::size_t m : measured) {
      if (root(m) == r && !std::isnan(maker.section_deviation(m))) {
        c.deviation = maker.section_deviation(m);
        return c.deviation;
      }
    }
    c.deviation = volume_deviation(columns(), c.result.region, c.grid());
    return c.deviation;
  };
  // Of those within a tie of the least D, the least ΔV, in the order ma, mid, optimal-height,
  // the +features ones (equal ΔV goes to the first).
  std::vector<std::size_t> order{kMa, kMid, kOptimal}, tied;
  for (std::size_t k = 3; k < candidates.size(); ++k) order.push_back(k);
  for (std::size_t k : order) {
    if (candidates[k].missed_count() == fewest && candidates[k].distance <= least + kDistanceTie) tied.push_back(k);
  }
  std::size_t best = tied.front();
  for (std::size_t k : tied) {
    if (k != best && volume_of(k) < volume_of(best)) best = k;
  }
  choice.chosen = candidates[best].name;
  choice.distance = candidates[best].distance;
  choice.missed_features = candidates[best].missed.size();
  choice.result = std::move(candidates[best].result);
  return choice;
}

ContourResult best_strategy(const ContourInput& input) { return best_choice(input).result; }

}  // namespace geometry
