// The best contour: per layer never above mid's or ma's distance error, on closed-form solids
// whose layers favour different candidates, and the same D analyze measures for it.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "geometry/analysis/layer_analysis.h"
#include "geometry/contour/best_contour.h"
#include "geometry/contour/contour_strategy.h"
#include "geometry/contour/optimal_height.h"
#include "geometry/mesh/placement.h"
#include "geometry/mesh/repair.h"
#include "geometry/mesh/stl_io.h"
#include "geometry/core/boundary_grid.h"
#include "geometry/metrics/distance_error.h"
#include "geometry/metrics/layer_metrics.h"
#include "geometry/metrics/volume_deviation.h"
#include "geometry/slab/slab.h"
#include "support/solids.h"

namespace best_contour_test {

using geometry::ContourStrategy;

namespace {

const ContourStrategy* strategy(std::string_view name) { return &geometry::contour_strategy(name); }

// analyze's D of mid, ma and best on every layer of a stack.
void check_never_worse(const geometry::Mesh& mesh, double thickness) {
  const double top = geometry::bounding_box(mesh).max.z;
  const geometry::LayerStack stack(mesh, geometry::uniform_layers(top, thickness));
  const ContourStrategy* strategies[] = {strategy("mid"), strategy("ma"), strategy("best")};
  const auto layers = geometry::analyze_layers(stack, strategies);
  REQUIRE(!layers.empty());
  for (const auto& layer : layers) {
    CAPTURE(layer.layer.z_lo);
    const double mid = layer.strategies[0].metrics.distance;
    const double ma = layer.strategies[1].metrics.distance;
    const double best = layer.strategies[2].metrics.distance;
    CHECK(best <= std::min(mid, ma) + geometry::kDistanceTie);
    CHECK(layer.strategies[2].metrics.missed_features <=
          std::min(layer.strategies[0].metrics.missed_features,
                   layer.strategies[1].metrics.missed_features));
  }
}

// best's rule applied by measuring every candidate in full (best_contour.h): first mid, ma and
// mid+features, of the fewest missed features the least D; optimal-height (and its +features)
// joins only where a section is within a tie of that least, or no section misses as few
// features. Then, of the candidates of fewest missed features, those within a tie of the least
// D, of them the least ΔV (a section's as optimal-height's search figures it, SectionDeviation,
// at its height; others the metric's; one figure per region), equal ΔV going to the first in
// the order ma, mid, optimal-height, then the +features ones.
struct Choice {
  std::string name;
  geometry::Region region;
  double distance;  // the chosen one's D, measured in full
  // mid's, optimal-height's and ma's D measured in full where they are considered and miss
  // the fewest features, else infinity; and the least D of those.
  double candidate_distance[3];
  double least;
};
Choice exhaustive_choice(const geometry::LayerStack& stack, std::size_t layer) {
  const geometry::ContourOptions options;
  geometry::MetricOptions metrics;
  metrics.distance.reverse = false;
  const geometry::LayerReference reference = geometry::layer_reference(stack, layer, metrics);
  std::vector<geometry::BestCandidate> candidates =
      geometry::best_candidates({stack, layer, options, &reference});
  REQUIRE(candidates.size() >= 3);
  const auto is_optimal = [&](std::size_t k) { return candidates[k].name.starts_with("optimal-height"); };
  std::vector<double> distance(candidates.size(), std::numeric_limits<double>::infinity());
  geometry::DistanceOptions full;
  full.reverse = false;
  for (std::size_t k = 0; k < candidates.size(); ++k) {
    const geometry::BoundaryGrid walls(candidates[k].result.region);
    distance[k] = geometry::distance_error(reference.surface, walls, candidates[k].missed, full).forward;
  }
  // Of `among`, the fewest missed features and the least D of those.
  const auto fewest_and_least = [&](const std::vector<std::size_t>& among) {
    std::size_t fewest = std::numeric_limits<std::size_t>::max();
    for (std::size_t k : among) fewest = std::min(fewest, candidates[k].missed.size());
    double least = std::numeric_limits<double>::infinity();
    for (std::size_t k : among) {
      if (candidates[k].missed.size() == fewest) least = std::min(least, distance[k]);
    }
    return std::pair{fewest, least};
  };
  std::vector<std::size_t> first, all;
  for (std::size_t k = 0; k < candidates.size(); ++k) {
    all.push_back(k);
    if (!is_optimal(k)) first.push_back(k);
  }
  const auto [fewest_first, least_first] = fewest_and_least(first);
  bool section_of_fewest = false, section_within = false;
  for (std::size_t k : first) {
    if (candidates[k].name == "ma" || candidates[k].missed.size() != fewest_first) continue;
    section_of_fewest = true;
    section_within = section_within || distance[k] <= least_first + geometry::kDistanceTie;
  }
  const bool optimal_joins = section_within || !section_of_fewest;
  const std::vector<std::size_t>& considered = optimal_joins ? all : first;
  const auto [fewest, least] = fewest_and_least(considered);
  // ΔV: the search's figure for mid's and optimal-height's sections where it ran.
  const geometry::SectionDeviation section_deviation(reference.columns);
  const geometry::Layer bounds = stack.layers()[layer];
  const auto own_deviation = [&](std::size_t k) {
    const auto& c = candidates[k];
    const bool section = c.name == "mid" || c.name == "optimal-height";
    if (optimal_joins && section && c.result.height < bounds.z_hi) return section_deviation(c.result.height);
    if (optimal_joins && section) return geometry::optimal_height(stack, layer, reference.columns).volume_deviation;
    return std::numeric_limits<double>::quiet_NaN();
  };
  const auto deviation_of = [&](std::size_t k) {
    for (std::size_t m : considered) {
      if (candidates[m].result.region.loops == candidates[k].result.region.loops &&
          !std::isnan(own_deviation(m))) {
        return own_deviation(m);
      }
    }
    return geometry::volume_deviation(reference.columns, candidates[k].result.region);
  };
  std::vector<std::size_t> order{2, 0, 1};
  for (std::size_t k = 3; k < candidates.size(); ++k) order.push_back(k);
  std::size_t best = candidates.size();
  double best_deviation = 0;
  for (std::size_t k : order) {
    if (std::find(considered.begin(), considered.end(), k) == considered.end()) continue;
    if (candidates[k].missed.size() != fewest || !(distance[k] <= least + geometry::kDistanceTie)) continue;
    const double deviation = deviation_of(k);
    if (best == candidates.size() || deviation < best_deviation) {
      best = k;
      best_deviation = deviation;
    }
  }
  Choice choice{std::string(candidates[best].name), std::move(candidates[best].result.region),
                distance[best], {}, least};
  for (std::size_t k = 0; k < 3; ++k) {
    const bool in = std::find(considered.begin(), considered.end(), k) != considered.end() &&
                    candidates[k].missed.size() == fewest;
    choice.candidate_distance[k] = in ? distance[k] : std::numeric_limits<double>::infinity();
  }
  return choice;
}

// On every layer but the prisms (which take mid unmeasured), best_choice is that choice, to
// the bit, and so is the chosen one's D. A candidate best measured is either exact (its D
// measured in full) or refuted: its figure a lower bound of that D and more than a tie above
// the least. Returns how often each candidate was chosen, and in "ma refuted" how often ma
// was refuted (measured after a section that beat it).
std::map<std::string, int> check_exhaustive(const geometry::Mesh& mesh, double thickness) {
  const double top = geometry::bounding_box(mesh).max.z;
  const geometry::LayerStack stack(mesh, geometry::uniform_layers(top, thickness));
  const geometry::ContourOptions options;
  std::map<std::string, int> chosen;
  for (std::size_t i = 0; i < stack.size(); ++i) {
    CAPTURE(i);
    if (geometry::is_prism(geometry::slab_of(stack, i))) continue;
    const geometry::BestChoice choice = geometry::best_choice({stack, i, options});
    const Choice expected = exhaustive_choice(stack, i);
    CHECK(std::string(choice.chosen) == expected.name);
    CHECK(choice.result.region.loops == expected.region.loops);
    CHECK(choice.distance == expected.distance);
    for (std::size_t k = 0; k < 3; ++k) {
      CAPTURE(k);
      const double figure = choice.candidate_distance[k];
      if (figure == geometry::kNotMeasured) continue;
      if (choice.refuted[k]) {
        CHECK(figure <= expected.candidate_distance[k]);
        CHECK(figure > expected.least + geometry::kDistanceTie);
      } else {
        CHECK(figure == expected.candidate_distance[k]);
      }
    }
    ++chosen[expected.name];
    if (choice.refuted[2]) ++chosen["ma refuted"];
  }
  return chosen;
}

}  // namespace

TEST_CASE("best_choice_is_the_choice_of_measuring_every_candidate_in_full") {
  // Solids whose layers go to different candidates: a sphere and a torus (ma where the strip
  // curves, a section where it is straight, ties broken by ΔV), a bipyramid (its equator a
  // vertex ring inside a layer), a cone whose tip ends below a layer's middle (mid misses it:
  // mid+features), and a sphere beside a cylinder (two islands).
  std::map<std::string, int> chosen;
  const auto add = [&](const std::map<std::string, int>& counts) {
    for (const auto& [name, count] : counts) chosen[name] += count;
  };
  add(check_exhaustive(solids::sphere(10, 48, 24, {0, 0, 10}).mesh, 0.4));
  add(check_exhaustive(solids::torus(12, 5, 48, 24, {0, 0, 5}).mesh, 0.35));
  add(check_exhaustive(solids::bipyramid(10, 6, 0, 3.3, 10).mesh, 0.3));
  add(check_exhaustive(solids::cone(6, 9.9, 32).mesh, 0.3));
  add(check_exhaustive(solids::combine(solids::sphere(5, 32, 16, {-8, 0, 5}),
                                       solids::cylinder(3, 4, 24, {8, 0, 0}))
                           .mesh,
                       0.45));
  CAPTURE(chosen.size());
  CHECK(chosen["ma"] > 0);
  CHECK(chosen["ma refuted"] > 0);
  CHECK(chosen["mid"] + chosen["optimal-height"] > 0);
  CHECK(chosen["mid+features"] + chosen["optimal-height+features"] > 0);
}

TEST_CASE("best_is_never_worse_than_mid_or_ma_on_a_sphere") {
  check_never_worse(solids::sphere(10, 48, 24, {0, 0, 10}).mesh, 0.4);
}

TEST_CASE("best_is_never_worse_than_mid_or_ma_on_a_torus_and_a_bipyramid") {
  check_never_worse(solids::torus(12, 5, 48, 24, {0, 0, 5}).mesh, 0.35);
  check_never_worse(solids::bipyramid(10, 6, 0, 3.3, 10).mesh, 0.3);
}

TEST_CASE("best_on_a_prism_is_mid_exact_and_elsewhere_as_it_would_be_measured") {
  // A stepped block at 0.3 mm (the step at 4 mm and the top at 8, both off the grid): the
  // layers of straight walls take mid's section, exact, without measuring; the two holding
  // the step face or the top are measured, and are never worse than mid or ma there
  // (check_never_worse on the same stack).
  const solids::Solid steps = solids::stepped_box({20, 20}, 4, {10, 10}, 4);
  const geometry::LayerStack stack(steps.mesh, geometry::uniform_layers(8, 0.3));
  const geometry::ContourOptions options;
  std::size_t prisms = 0;
  for (std::size_t i = 0; i < stack.size(); ++i) {
    CAPTURE(i);
    const geometry::BestChoice choice = geometry::best_choice({stack, i, options});
    const geometry::LayerMetrics measured = geometry::layer_metrics(stack, i, choice.result.region);
    if (!geometry::is_prism(geometry::slab_of(stack, i))) {
      const geometry::Layer& bounds = stack.layers()[i];
      CHECK(((bounds.z_lo < 4 && bounds.z_hi > 4) || (bounds.z_lo < 8 && bounds.z_hi > 8)));
      continue;
    }
    ++prisms;
    CHECK(choice.chosen == "mid");
    CHECK(choice.distance == 0);
    CHECK(measured.distance < 1e-9);
    CHECK(measured.volume_deviation < 1e-6);
    CHECK(choice.result.region.loops == stack.mid(i).loops);
  }
  CHECK(prisms == stack.size() - 2);
  check_never_worse(steps.mesh, 0.3);
}

TEST_CASE("best_choice_takes_the_candidate_of_least_distance") {
  // A cone: mid's walls stand at the slab's middle, t/2 from both ends in the radial
  // direction (scaled by the slope); every candidate is within a hair of that, so best's D
  // is the least of the three and equal to the formula within the metric's tolerance.
  const solids::Solid cone = solids::cone(10, 20, 64);
  const geometry::LayerStack stack(cone.mesh, geometry::uniform_layers(20, 0.4));
  const geometry::ContourOptions options;
  for (std::size_t i = 0; i + 2 < stack.size(); i += 7) {
    const geometry::BestChoice choice = geometry::best_choice({stack, i, options});
    const double least = *std::min_element(std::begin(choice.candidate_distance),
                                           std::end(choice.candidate_distance));
    CHECK(choice.distance <= least + geometry::kDistanceTie);
    CHECK(choice.distance == doctest::Approx(0.4 / 2 * 10 / 20).epsilon(0.05));
    CHECK((choice.chosen == "mid" || choice.chosen == "ma" || choice.chosen == "optimal-height"));
  }
}

TEST_CASE("best_on_the_bunny_misses_no_feature_and_is_never_worse_than_ma") {
  // Every fourth layer at the paper's 0.15 mm, with the first and the last (the base, the ear
  // tip: where mid leaves features out).
  geometry::Placement placement;
  placement.units_to_mm = 1000;
  placement.up = geometry::Axis::y;
  placement.height = 50;
  const geometry::Mesh bunny = geometry::place(
      geometry::repair(geometry::read_stl(std::string(MAHOST_DATA_DIR) + "/bunny.stl")), placement);
  const double top = geometry::bounding_box(bunny).max.z;
  const geometry::LayerStack stack(bunny, geometry::uniform_layers(top, 0.15));
  const ContourStrategy* strategies[] = {strategy("mid"), strategy("ma"), strategy("best")};
  std::size_t worse_than_mid = 0, mid_missing = 0;
  std::vector<std::size_t> checked;
  for (std::size_t i = 0; i < stack.size(); i += 4) checked.push_back(i);
  checked.push_back(stack.size() - 1);
  for (std::size_t i : checked) {
    const auto layer = geometry::analyze_layer(stack, i, strategies);
    CAPTURE(i);
    const auto& mid = layer.strategies[0].metrics;
    const auto& ma = layer.strategies[1].metrics;
    const auto& best = layer.strategies[2].metrics;
    CHECK(best.missed_features == 0);
    CHECK(best.distance <= ma.distance + geometry::kDistanceTie);
    if (best.distance > mid.distance + geometry::kDistanceTie) {
      ++worse_than_mid;
      CHECK(mid.missed_features > 0);  // only where mid leaves a feature out
    }
    if (mid.missed_features > 0) ++mid_missing;
  }
  CHECK(mid_missing > 0);  // the layers this test is about are among those checked
  CHECK(worse_than_mid <= mid_missing);
}

}  // namespace best_contour_test
