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

// Indices of the candidates, in best_candidates' order; the +features ones follow, mid's first
// where mid misses a feature.
constexpr std::size_t kMid = 0, kOptimal = 1, kMa = 2, kMidFeatures = 3;

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
  // ma's pockets' decisions index the middle section's walls (mid's, where ma's middle is
  // mid's section) and ma's region's own: kept for measuring mid and ma (walls()).
  std::vector<BestCandidate> first() {
    std::vector<BestCandidate> candidates;
    add(candidates, "mid", {mid_section_, middle_});
    candidates.push_back({"optimal-height", {}, {}});
    MaGrids grids;
    grids.shared = [&](const Region& region) -> const BoundaryGrid* {
      if (region.loops != mid_section_.loops) return nullptr;
      if (!mid_walls_) mid_walls_.emplace(mid_section_);
      return &*mid_walls_;
    };
    add(candidates, "ma",
        {ma_contour(reference_.slab, reference_.islands,
                    [&](double z) { return section_at(z); }, input_.options.ma, nullptr, &grids),
         middle_});
    ma_walls_ = std::move(grids.walls);
    add_features(candidates, kMid, "mid+features");
    return candidates;
  }

  // The grid over candidate k's region built while making it (mid's and ma's, see first()),
  // handed over once; else empty.
  std::optional<BoundaryGrid> walls(std::size_t k) {
    if (k == kMid) return std::move(mid_walls_);
    if (k == kMa) return std::move(ma_walls_);
    return std::nullopt;
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
  std::optional<BoundaryGrid> mid_walls_, ma_walls_;
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
                              SlabColumns& built) {
  if (reference.volumes) return reference.columns;
  slab_columns(reference.slab, input.stack.lower(input.layer), built);
  return built;
}

// mid's section on a prism, unmeasured: its D is 0 (so is optimal-height's, whose search
// could only end at a section equal to it); ma is not made.
BestChoice prism_choice(const ContourInput& input) {
  BestChoice choice{};
  choice.result = mid_strategy(input);
  choice.chosen = "mid";
  choice.candidate_distance[kMid] = choice.candidate_distance[kOptimal] = 0;  // optimal-height's: mid's
  choice.candidate_distance[kMa] = kNotMeasured;
  return choice;
}

constexpr std::size_t kNone = std::numeric_limits<std::size_t>::max();
constexpr std::size_t kNotMade = std::numeric_limits<std::size_t>::max();

// How many of the surface points farthest from the first candidate's walls the others are
// measured at first (on the bunny at 0.15 mm, 8 to 64 save alike).
constexpr std::size_t kFarthestPoints = 16;

// A candidate as best_choice weighs it: made or not yet, its D and ΔV once measured.
struct Contender : BestCandidate {
  bool made = true;
  double distance = kNotMeasured;
  double deviation = -1;  // ΔV, once a tie needs it
  std::size_t same_as = kNone;  // a candidate measured before with this very region
  std::optional<BoundaryGrid> walls;  // the region's boundary, for D and ΔV
  bool refuted = false;  // measured only until more than a tie above the least: D a lower bound
  std::size_t missed_count() const { return made ? missed.size() : kNotMade; }
  const BoundaryGrid& grid() {
    if (!walls) walls.emplace(result.region);
    return *walls;
  }
};

// One layer's contest (best_contour.h): the candidates, which of them are measured, the fewest
// features missed and the least D so far.
//
// Fewest missed features first: only those candidates are measured. Then the least D, ma
// first (it wins most layers, so its D refutes the others early) unless its corners show mid
// likely to beat it (open_with_ma_or_mid): a candidate is measured only until its D is known
// to be more than a tie above the least so far. So every candidate within a tie of the least
// D is measured in full, whatever the order, and the choice does not depend on the order;
// only a refuted candidate's figure, a lower bound, does. A candidate whose
// region is one already measured (optimal-height's search often ends at mid's height: 142
// of a sphere's 150 layers) takes that one's D: exact if it was, else a lower bound above a
// threshold at least this one's.
class Contest {
 public:
  Contest(const ContourInput& input, const LayerReference& reference)
      : input_(input), reference_(reference), maker_(input, reference) {
    made_ = maker_.first();
    take_made();
    candidates_[kMid].walls = maker_.walls(kMid);
    candidates_[kMa].walls = maker_.walls(kMa);
    candidates_[kOptimal].made = false;
    distance_options_.reverse = false;
    // mid's D known (the layer plan's): taken as measured, first, so that ma is measured only
    // until it is seen to lose by more than a tie. The same choice as measuring it: the least
    // D and the candidates within a tie of it do not depend on the order.
    ma_corners_.clear();
    mid_known_ = !std::isnan(input.mid_distance);
    if (mid_known_) candidates_[kMid].distance = input.mid_distance;
  }

  // Measures the made candidates of fewest missed features not measured yet, in `order`
  // (indices past the candidates skipped).
  void measure(const std::vector<std::size_t>& order) {
    settle_fewest();
    if (!order.empty() && order.front() == kMa) open_with_ma_or_mid();
    for (std::size_t k : order) {
      if (k >= candidates_.size()) continue;
      if (candidates_[k].missed_count() != fewest_ || was_measured(k)) continue;
      measure_one(k);
    }
  }

  // optimal-height minimises ΔV, not D: it is searched only where a section is within a tie
  // of the least D (mid or mid+features, whose height it is free to leave), or where no
  // section misses as few features as ma (a height that catches the tip may); the header
  // says what that leaves out.
  bool optimal_in_the_running() const {
    const bool section_of_fewest =
        candidates_[kMid].missed_count() == fewest_ ||
        (candidates_.size() > kMidFeatures && candidates_[kMidFeatures].missed_count() == fewest_);
    return contends(kMid) || contends(kMidFeatures) || !section_of_fewest;
  }

  // optimal-height and optimal-height+features made, in their places.
  void add_optimal() {
    maker_.add_optimal(made_, columns());
    candidates_[kOptimal].made = true;
    static_cast<BestCandidate&>(candidates_[kOptimal]) = std::move(made_[kOptimal]);
    take_made();
  }

  // The winner: of those within a tie of the least D, the least ΔV.
  BestChoice choose() {
    BestChoice choice{};
    for (std::size_t k = 0; k < 3; ++k) {
      const Contender& c = candidates_[k];
      choice.candidate_distance[k] =
          c.missed_count() == fewest_ && was_measured(k) ? c.distance : kNotMeasured;
      choice.refuted[k] = choice.candidate_distance[k] != kNotMeasured && candidates_[root(k)].refuted;
    }
    const std::size_t best = least_deviation_of_the_tied();
    choice.chosen = candidates_[best].name;
    choice.distance = candidates_[best].distance;
    choice.missed_features = candidates_[best].missed.size();
    choice.result = std::move(candidates_[best].result);
    return choice;
  }

 private:
  // Moves the candidates the maker made since the last call into the contest.
  void take_made() {
    for (std::size_t k = candidates_.size(); k < made_.size(); ++k) {
      candidates_.emplace_back();
      static_cast<BestCandidate&>(candidates_.back()) = std::move(made_[k]);
    }
  }

  bool was_measured(std::size_t k) const {
    return std::find(measured_.begin(), measured_.end(), k) != measured_.end();
  }

  // The fewest features any made candidate misses, and the least D of those measured that
  // miss no more; mid's known D counts as measured.
  void settle_fewest() {
    for (const Contender& c : candidates_) fewest_ = std::min(fewest_, c.missed_count());
    least_ = std::numeric_limits<double>::infinity();
    for (std::size_t m : measured_) {
      if (candidates_[m].missed_count() == fewest_) least_ = std::min(least_, candidates_[m].distance);
    }
    if (mid_known_ && candidates_[kMid].missed_count() == fewest_ && !was_measured(kMid)) {
      measured_.insert(measured_.begin(), kMid);
      least_ = std::min(least_, candidates_[kMid].distance);
    }
  }

  // Candidate k's D, measured only until it is more than a tie above the least so far, or
  // taken from a candidate measured before with the same region.
  void measure_one(std::size_t k) {
    Contender& c = candidates_[k];
    const auto same = std::find_if(measured_.begin(), measured_.end(), [&](std::size_t m) {
      return candidates_[m].result.region.loops == c.result.region.loops;
    });
    if (same != measured_.end()) {
      c.distance = candidates_[*same].distance;
      c.same_as = *same;
    } else {
      distance_options_.stop_above = least_ + kDistanceTie;
      distance_options_.first_points = farthest_;
      distance_options_.farthest_count = farthest_.empty() ? kFarthestPoints : 0;
      distance_options_.state = k == kMa ? &ma_corners_ : nullptr;  // its corners, if measured
      DistanceError measured = distance_error(reference_.surface, c.grid(), c.missed, distance_options_);
      c.distance = measured.forward;
      c.refuted = c.distance > distance_options_.stop_above;
      if (farthest_.empty()) farthest_ = std::move(measured.farthest);
    }
    measured_.push_back(k);
    least_ = std::min(least_, c.distance);
  }

  // ma and mid, both of the fewest missed features and neither measured: which to measure in
  // full first. ma's corners are measured (kept in ma_corners_), which gives the surface points
  // farthest from its walls and the farthest one's distance, a lower bound on ma's D. Where mid
  // is nearer than that by more than a tie at all of those points, ma is likely to lose to
  // mid's section (or optimal-height's, near it): mid is measured in full first, and ma's
  // search then goes on from its corners only until it is refuted (more than a tie above the
  // least D) or finds its D. Either order gives the same choice and the same D for every
  // candidate within a tie of the least (Contest); only a refuted one's lower bound moves.
  // On the bunny at 0.15 mm this guesses 59 of the 60 layers where ma loses, and 12 of the
  // 189 where mid loses (mid is then measured in full rather than refuted).
  void open_with_ma_or_mid() {
    if (mid_known_ || candidates_.size() <= kMa) return;
    Contender& ma = candidates_[kMa];
    Contender& mid = candidates_[kMid];
    if (ma.missed_count() != fewest_ || mid.missed_count() != fewest_ || was_measured(kMa) ||
        was_measured(kMid) || ma.result.region.loops == mid.result.region.loops) {
      return;
    }
    DistanceOptions corners = distance_options_;
    corners.stop_above = std::numeric_limits<double>::infinity();
    corners.first_points = {};
    corners.farthest_count = kFarthestPoints;
    corners.state = &ma_corners_;
    corners.corners_only = true;
    DistanceError measured = distance_error(reference_.surface, ma.grid(), ma.missed, corners);
    farthest_ = std::move(measured.farthest);
    if (farthest_.empty()) return;  // corners measured to a missed island's outline
    const double ma_at_least = measured.forward;
    const BoundaryGrid& mid_walls = mid.grid();
    for (std::uint32_t p : farthest_) {
      if (!(mid_walls.nearest(reference_.surface.points[p]).distance < ma_at_least - kDistanceTie)) return;
    }
    measure_one(kMid);
  }

  bool contends(std::size_t k) const {
    return k < candidates_.size() && candidates_[k].missed_count() == fewest_ &&
           candidates_[k].distance <= least_ + kDistanceTie;
  }

  // Of those within a tie of the least D, the least ΔV, in the order ma, mid, optimal-height,
  // the +features ones (equal ΔV goes to the first).
  std::size_t least_deviation_of_the_tied() {
    std::vector<std::size_t> order{kMa, kMid, kOptimal}, tied;
    for (std::size_t k = kMidFeatures; k < candidates_.size(); ++k) order.push_back(k);
    for (std::size_t k : order) {
      if (contends(k)) tied.push_back(k);
    }
    std::size_t best = tied.front();
    for (std::size_t k : tied) {
      if (k != best && volume_of(k) < volume_of(best)) best = k;
    }
    return best;
  }

  std::size_t root(std::size_t k) const {
    return candidates_[k].same_as == kNone ? k : candidates_[k].same_as;
  }

  // ΔV only where a tie needs it: a section's as the search figured it, where it ran, else
  // the metric's; a region measured under two names has one figure.
  double volume_of(std::size_t k) {
    const std::size_t r = root(k);
    Contender& c = candidates_[r];
    if (c.deviation >= 0) return c.deviation;
    for (std::size_t m : measured_) {
      if (root(m) != r) continue;
      const double searched = maker_.section_deviation(m);  // mid's is evaluated: once
      if (!std::isnan(searched)) {
        c.deviation = searched;
        return c.deviation;
      }
    }
    c.deviation = volume_deviation(columns(), c.result.region, c.grid());
    return c.deviation;
  }

  // The slab's columns only for optimal-height's search or a ΔV: a layer ma wins by more than
  // a tie needs neither.
  const SlabColumns& columns() {
    if (!columns_) columns_ = &columns_of(input_, reference_, built_columns_);
    return *columns_;
  }

  const ContourInput& input_;
  const LayerReference& reference_;
  CandidateMaker maker_;
  std::vector<BestCandidate> made_;  // what the maker made, moved into candidates_
  std::vector<Contender> candidates_;
  std::vector<std::size_t> measured_;
  std::size_t fewest_ = kNotMade;
  double least_ = std::numeric_limits<double>::infinity();
  bool mid_known_ = false;
  DistanceOptions distance_options_;
  // The surface points farthest from the first walls measured in full: the next candidates'
  // corners are measured there first (DistanceOptions::first_points).
  std::vector<std::uint32_t> farthest_;
  const SlabColumns* columns_ = nullptr;
  // ma's corners, where they are measured before mid (open_with_ma_or_mid): one a thread,
  // reused from layer to layer.
  static thread_local ForwardState ma_corners_;
  // The slab's columns where the reference has none: one a thread, reused from layer to layer
  // (slab_columns keeps its facets' storage).
  static thread_local SlabColumns built_columns_;
};

thread_local ForwardState Contest::ma_corners_;
thread_local SlabColumns Contest::built_columns_;

}  // namespace

std::vector<BestCandidate> best_candidates(const ContourInput& input) {
  if (input.layer >= input.stack.size()) return {};
  std::optional<LayerReference> own;
  if (!input.reference) own = own_reference(input, slab_of(input.stack, input.layer));
  const LayerReference& reference = own ? *own : *input.reference;
  SlabColumns built;
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
  if (is_prism(input.reference ? input.reference->slab : *slab)) return prism_choice(input);
  std::optional<LayerReference> own;
  if (!input.reference) own = own_reference(input, std::move(*slab));
  const LayerReference& reference = own ? *own : *input.reference;
  Contest contest(input, reference);
  contest.measure({kMa, kMid, kMidFeatures});
  if (contest.optimal_in_the_running()) {
    contest.add_optimal();
    contest.measure({kOptimal, 3, 4});  // then the +features ones, where made
  }
  return contest.choose();
}

ContourResult best_strategy(const ContourInput& input) { return best_choice(input).result; }

}  // namespace geometry
