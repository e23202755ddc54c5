// The best contour: per layer, whichever of mid, optimal-height and ma misses the
// fewest features of the slab (missed_features.h: islands of its footprint a region does not
// touch, a tip or a bump between a section's plane and the slab's ends), then has the least
// distance error D (distance_error.h, as analyze measures it: layer_metrics.h), ties within
// 1 um going to the least volume deviation ΔV. A section (mid, optimal-height) that misses a
// feature also competes with the feature's own middle section added. So best misses a
// feature only where every candidate does, and its D is above none of theirs but where one
// of them leaves a feature out (D measures a left-out feature to its own outline, which can
// be nearer than any wall that prints it: the bunny's first and last layer).
//
// optimal-height minimises ΔV, not D, so it takes part only where a section is in the running:
// where mid (or mid+features) is within a tie of the least D of mid, ma and mid+features, or
// where no section misses as few features as ma. Elsewhere ma is nearer than mid by more than
// a tie, and a section of the same slab at another height would have to come within a tie of
// it. On the bunny at 0.15 mm one did on 1 of 333 layers (optimal-height 0.96 um above ma's D,
// chosen for 0.7% less ΔV there: best's total ΔV is 0.004 mm³ more of 121 without it), and its
// search is left out on at least 189 layers (mid measured and more than a tie behind ma).
//
// Input: a layer of a stack (contour_input.h), with the layer's reference if the caller has
// one; without, it builds one (slab, footprint, surface), and the slab's columns only where
// optimal-height's search or a ΔV needs them.
// Among the candidates of fewest missed features, those within kDistanceTie of the least D
// tie, and the least ΔV of them wins (so the choice does not depend on the candidates' order).
// A section's ΔV is the figure optimal-height's search has for its height (SectionDeviation,
// which agrees with the metric's volume_deviation to ~1e-8 relative; mid's is evaluated at the
// middle), any other's the metric's; a region two candidates share has one figure.
//
// Output: the chosen region and the height of the candidate chosen; which one it was, and
// the candidates' D, in best_choice().
// Cost: none on a prism (slab.h: the walls straight up through the slab, so mid's section is exact,
// D 0 and ΔV 0; best takes it unmeasured: 75 of the mush's 135 layers at 0.2 mm, where the
// contours then take a third of the time). Elsewhere the candidates and their measurements, ma's
// corners first, then ma in full, or mid in full first where mid is nearer than ma's farthest
// corner at the corners farthest from ma's walls (ma then likely loses; bunny at 0.15 mm: the
// 59 of the 60 layers where it does and 12 where it wins; the slice 11.49 G -> 11.36 G
// instructions): a candidate is
// measured only until its D is more than a tie above the least so far (distance_error's
// stop_above; its corners first at the surface points farthest from ma's walls (mostly), where a
// loser is mostly far too), and one that misses more features than another is not measured, nor one whose region
// is one measured already (it takes that one's D and ΔV: optimal-height often ends at mid's
// height). Where the caller knows mid's D (ContourInput::mid_distance: the layer plan measured it
// on every layer it planned by mid) mid is not measured again, and ma is measured only until it
// loses to it by more than a tie. mid's section is cut once, for mid, for ma where it takes the
// middle section and for optimal-height where its search ends at the middle; each candidate's
// walls are indexed once, for D and ΔV, and mid's and ma's once with ma's own decisions (ma
// indexes the middle section's walls and, on a layer with pockets, its region's: MaGrids;
// 0.1 G of the bunny's 13.4 G instructions in bench_best --quick). About 1.75 times ma's time
// (tests/bench/bench_best.cpp: the bunny at 0.15 mm). Not done, for they take longer (the sphere at 0.2 mm with supports,
// median of 7): measuring the candidates in the order of a cheap lower bound of D (their
// surface corners' largest distance), 3% longer; a first pass to 10 um to refuse the far ones
// before the exact measure, 34% longer, as ma's and mid's D are within a tie of each other on
// 114 of the sphere's 149 layers (2% longer on the bunny, adaptive).
// Not done: skipping mid where no section can come within a tie of ma's D.
// A lower bound on every section's D, from the slab's facets cut to 32 height bands (a section's
// walls at a height lie in that height's band) and the facets' corners as witnesses, proves it
// on only 63 of the 195 bunny layers where the sections do lose: ma wins there by a few per cent.
// Not done: leaving ma's contour unmade (2.86 G of the bunny's 11.4 G) where a bound shows it
// cannot win. On the bunny at 0.15 mm ma loses on 60 layers, by 1% to 8% of D (43 to
// optimal-height, 17 to mid), and on 82 more it is within a tie and loses on ΔV; a layer it
// ties it may win, so a bound would have to put ma's own D more than a tie above the least,
// within a few per cent of it, without making ma. No bound over every region helps: forward D
// has none above 0 (walls weaving through the band the surface spans seen from above, or a
// region of many small holes, come as near to every surface point as they like; half the
// band's width bounds a section's walls, not these).
#pragma once

#include <limits>
#include <string_view>
#include <vector>

#include "geometry/contour/contour_input.h"
#include "geometry/slab/boundary_pair.h"

namespace geometry {

// D within this of each other is a tie, mm: the distance error's own tolerance.
inline constexpr double kDistanceTie = 1e-3;
// A candidate's D when it was not measured (it misses more features than another), mm.
inline constexpr double kNotMeasured = std::numeric_limits<double>::infinity();

ContourResult best_strategy(const ContourInput& input);

// The regions best may compare on a layer, as it makes them: "mid", "optimal-height" and "ma",
// then a section that misses a feature once more with the feature's own middle section added
// ("mid+features", "optimal-height+features"), each with the islands it misses
// (missed_features.h). For judging best's choice against measuring every candidate in full.
// All of them, though best makes the optimal-height ones only where a section is in the
// running, and on a prism takes mid without making the others. Out-of-range layer: none.
struct BestCandidate {
  std::string_view name;
  ContourResult result;
  std::vector<BoundaryPair> missed;
};
std::vector<BestCandidate> best_candidates(const ContourInput& input);

// The same, also saying which candidate won and the candidates' D, mm.
struct BestChoice {
  ContourResult result;
  std::string_view chosen;  // "mid", "optimal-height", "ma", "mid+features", "optimal-height+features"
  double distance = 0;           // the chosen one's D
  std::size_t missed_features = 0;
  // mid's, optimal-height's and ma's D: exact for the chosen one and any within a tie of it;
  // for one refuted early, a lower bound above the chosen one's; kNotMeasured for one that
  // misses more features, optimal-height where no section was in the running, and ma on a
  // prism (slab.h), where mid's D is 0.
  double candidate_distance[3];
  // Whether candidate_distance[k] is such a lower bound (the candidate refuted early) rather
  // than the candidate's D.
  bool refuted[3];
};
BestChoice best_choice(const ContourInput& input);

}  // namespace geometry
