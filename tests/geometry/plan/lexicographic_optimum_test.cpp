// The layer plan's optimum against brute force: on a part 2 mm tall every sequence of the
// UP Plus 2's thicknesses (0.15 to 0.4 mm in 0.05 steps over a 0.3 mm first layer) ending at
// or a step above the top is enumerated, each layer's D measured exactly (slab_error.h, as the
// plan measures it) and its swept volume taken (swept_volume.h), and the best by the plan's
// order (layer_plan.h: flat levels crossed, thicker layers over the tolerance and their
// thickness, the height of thinnest ones over it, layers, swept volume) or, under a layer
// budget, by the flat levels and the thicker layers over the cap, the lowest end, the most
// layers, the height of the thinnest over the cap, their D past it times their thickness and
// the swept volume, must cost what the plan found costs. The lazy search
// measures a fraction of the candidates; this checks that what it leaves unmeasured could not
// have won.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <tuple>
#include <vector>

#include "geometry/plan/flat_levels.h"
#include "geometry/plan/layer_plan.h"
#include "geometry/plan/slab_error.h"
#include "geometry/plan/swept_volume.h"
#include "geometry/slicing/layer_stack.h"
#include "support/solids.h"

namespace lexicographic_optimum_test {

using geometry::Layer;

namespace {

const geometry::AllowedThicknesses kUpPlus2{.listed = {}, .min = 0.15, .max = 0.4, .step = 0.05, .first = 0.3};

// Heights in units of 0.05 mm: the first layer ends at 6, the top at 40.
constexpr int kFirst = 6, kTop = 40;
double height(int units) { return units * 0.05; }

// A vertical wall to 0.6 mm, a cone leaning in 0.3 mm over 0.5 mm to a flat ring at 1.1 mm, a
// steeper one, 1 mm over 0.9 mm, to a flat top at 2 mm: D = 0.3 t and 0.56 t for mid.
solids::Solid part() {
  return solids::revolve({{0, 0}, {4, 0}, {4, 0.6}, {3.7, 1.1}, {3.2, 1.1}, {2.2, 2.0}, {0, 2.0}}, 48);
}

struct Cost {
  int flats = 0, landing = 0;
  double landing_thickness = 0;
  double unmet = 0;   // height, mm
  double excess = 0;  // of those layers, D past the tolerance times thickness, mm^2
  int layers = 0;
  double swept = 0;
  int end = 0;  // units
  // Swept volumes summed in another order differ in the last bits: equal within 1e-9 mm^3;
  // the plan sums excesses in whole nm x mm (1e-6 mm^2): equal within 1e-5 mm^2. Under a budget
  // (count_layers false) the lower end and the more layers come before the thinnest layers over
  // the cap, and their excess before the swept volume; else the fewer layers after the
  // thinnest layers over the tolerance, and the excess is not compared.
  bool operator<(const Cost& o) const {
    const auto key = [](const Cost& c, bool budget) {
      return std::make_tuple(c.flats, c.landing, std::round(c.landing_thickness * 1e6), budget ? c.end : 0,
                             budget ? -c.layers : 0, std::round(c.unmet * 1e6), budget ? 0 : c.layers);
    };
    if (key(*this, !count_layers) != key(o, !count_layers)) return key(*this, !count_layers) < key(o, !count_layers);
    if (!count_layers && std::abs(excess - o.excess) > 1e-5) return excess < o.excess;
    return swept < o.swept - 1e-9;
  }
  bool count_layers = true;
};

class BruteForce {
 public:
  explicit BruteForce(const geometry::Mesh& mesh)
      : stack_(mesh, {}), swept_(mesh), flats_(geometry::flat_levels(mesh)) {}

  // One layer [a, b] (in units) added to a path's cost at `tolerance`.
  void add(Cost& c, int a, int b, double tolerance) {
    const Slab& slab = slab_of(a, b);
    const bool thinnest = a == 0 || b - a == 3;
    c.flats += slab.flats;
    if (slab.distance > tolerance && !thinnest) ++c.landing, c.landing_thickness += height(b) - height(a);
    if (slab.distance > tolerance && thinnest) {
      c.unmet += height(b) - height(a);
      c.excess += (slab.distance - tolerance) * (height(b) - height(a));
    }
    ++c.layers;
    c.swept += slab.swept;
    c.end = b;
  }

  Cost cost_of(const std::vector<Layer>& layers, double tolerance, bool count_layers) {
    Cost c;
    c.count_layers = count_layers;
    for (const Layer& l : layers) {
      add(c, static_cast<int>(std::lround(l.z_lo / 0.05)), static_cast<int>(std::lround(l.z_hi / 0.05)), tolerance);
    }
    return c;
  }

  // The least cost over every sequence from the first layer to the top or a step above it,
  // of at most `budget` layers (0: any), with no layer above the first over `ceiling`.
  Cost best(double tolerance, std::size_t budget, bool count_layers, double ceiling = INFINITY) {
    Cost least;
    bool found = false;
    std::vector<int> path{0, kFirst};
    std::vector<Cost> costs(1);
    costs[0].count_layers = count_layers;
    add(costs[0], 0, kFirst, tolerance);
    std::function<void()> walk = [&] {
      const int z = path.back();
      if (z >= kTop) {
        if (!found || costs.back() < least) least = costs.back(), found = true;
        return;
      }
      if (budget > 0 && path.size() - 1 >= budget) return;
      for (int t = 3; t <= 8 && z + t <= kTop + 1; ++t) {
        if (slab_of(z, z + t).distance > ceiling) continue;
        costs.push_back(costs.back());
        add(costs.back(), z, z + t, tolerance);
        path.push_back(z + t);
        walk();
        path.pop_back();
        costs.pop_back();
      }
    };
    walk();
    return least;
  }

 private:
  struct Slab {
    double distance = 0;  // mid's D, mm
    double swept = 0;     // mm^3
    int flats = 0;        // flat levels strictly inside
  };
  const Slab& slab_of(int a, int b) {
    const auto key = std::make_pair(a, b);
    if (const auto it = slabs_.find(key); it != slabs_.end()) return it->second;
    const geometry::ContourStrategy* mid[] = {&geometry::contour_strategy("mid")};
    Slab slab;
    slab.distance = geometry::slab_error(stack_, height(a), height(b), mid).distance();
    slab.swept = swept_(height(a), height(b));
    for (const geometry::FlatLevel& flat : flats_) {
      if (flat.z > height(a) + 1e-6 && flat.z < height(b) - 1e-6) ++slab.flats;
    }
    return slabs_[key] = slab;
  }

  geometry::LayerStack stack_;
  geometry::SweptVolume swept_;
  std::vector<geometry::FlatLevel> flats_;
  std::map<std::pair<int, int>, Slab> slabs_;
};

geometry::AdaptivePlan plan_for(const geometry::Mesh& mesh, double tolerance, std::size_t budget) {
  const geometry::LayerStack stack(mesh, {});
  geometry::AdaptiveOptions options;
  options.tolerance = tolerance;
  options.max_layers = budget;
  return geometry::adaptive_plan(stack, 2.0, kUpPlus2, geometry::flat_levels(mesh), options);
}

}  // namespace

TEST_CASE("the_plan_at_a_tolerance_is_the_lexicographic_optimum_of_every_thickness_sequence") {
  const solids::Solid solid = part();
  BruteForce brute(solid.mesh);
  for (double tolerance : {0.04, 0.07, 0.1, 0.15}) {
    CAPTURE(tolerance);
    const geometry::AdaptivePlan plan = plan_for(solid.mesh, tolerance, 0);
    const Cost found = brute.cost_of(plan.layers, tolerance, true);
    const Cost least = brute.best(tolerance, 0, true);
    CHECK_FALSE(least < found);
    CHECK(found.layers == least.layers);
    CHECK(found.swept == doctest::Approx(least.swept).epsilon(1e-9));
  }
}

TEST_CASE("the_plan_within_a_layer_budget_is_the_least_swept_of_every_sequence_that_fits") {
  const solids::Solid solid = part();
  BruteForce brute(solid.mesh);
  for (std::size_t budget : {6, 7, 9}) {
    CAPTURE(budget);
    const geometry::AdaptivePlan plan = plan_for(solid.mesh, 0, budget);
    REQUIRE(plan.layers.size() <= budget);
    REQUIRE(plan.cap >= plan.tolerance);
    REQUIRE(plan.ceiling >= plan.cap);
    // No sequence of at most as many layers, none over the ceiling, is better (by the order
    // above: the lowest end and the most layers before the thinnest layers over the cap).
    const Cost found = brute.cost_of(plan.layers, plan.cap, false);
    const Cost least = brute.best(plan.cap, budget, false, plan.ceiling);
    CHECK_FALSE(least < found);
    CHECK(found.end == least.end);
    CHECK(found.layers == least.layers);
    CHECK(found.swept == doctest::Approx(least.swept).epsilon(1e-9));
    // Layers are said against the cap the least error was found within, not the tolerance.
    for (std::size_t i = 1; i < plan.layers.size(); ++i) {
      CHECK(plan.distance[i] <= plan.ceiling);
      CHECK(static_cast<bool>(plan.met[i]) == (plan.distance[i] <= plan.cap));
    }
  }
}

}  // namespace lexicographic_optimum_test
