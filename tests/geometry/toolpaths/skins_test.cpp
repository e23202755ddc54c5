// skins: which part of each layer is solid (top, bottom, between) and which sparse.
#include "geometry/toolpaths/skins.h"

#include <doctest/doctest.h>

#include "geometry/toolpaths/toolpath_shapes.h"

namespace skins_test {

using namespace geometry;
using namespace toolpath_shapes;

namespace {

constexpr double w = 0.45;

// Layers 0-9 one square, layers 10-19 another, both with a corner at the origin.
std::vector<Region> two_steps(double lower_side, double upper_side) {
  std::vector<Region> regions(20);
  for (int i = 0; i < 20; ++i) {
    const double side = i < 10 ? lower_side : upper_side;
    regions[i] = Region{{rectangle(0, 0, side, side)}};
  }
  return regions;
}

Skins skins_of(const std::vector<Region>& regions,
               const std::vector<std::optional<Region>>& cores, std::size_t i) {
  const Region nothing;
  const Region* below = i > 0 ? &regions[i - 1] : &nothing;
  const Region* above = i + 1 < regions.size() ? &regions[i + 1] : &nothing;
  return split_skins(regions[i], cores[i] ? &*cores[i] : nullptr, below, above, w);
}

}  // namespace

TEST_CASE("top_of_lower_step_gets_top_skin_and_solid_below_it") {
  // 20 mm square under a 10 mm one, 3 top and 3 bottom layers: on layer 9 the 300 mm^2 not
  // under the upper step is top skin; layers 7 and 8 are solid there; layer 6 is sparse.
  const auto regions = two_steps(20, 10);
  const auto cores = sparse_cores(regions, 3, 3);
  REQUIRE(cores.size() == 20);
  const Skins l9 = skins_of(regions, cores, 9);
  CHECK(area(l9.top) == doctest::Approx(300));
  CHECK(area(l9.bottom) == doctest::Approx(0));
  CHECK(area(l9.solid) == doctest::Approx(0));
  CHECK(area(l9.sparse) == doctest::Approx(100));
  for (std::size_t i : {7u, 8u}) {
    const Skins s = skins_of(regions, cores, i);
    CHECK(area(s.top) == doctest::Approx(0));
    CHECK(area(s.solid) == doctest::Approx(300));
    CHECK(area(s.sparse) == doctest::Approx(100));
  }
  const Skins l6 = skins_of(regions, cores, 6);
  CHECK(area(l6.sparse) == doctest::Approx(400));
  CHECK(area(l6.solid) + area(l6.top) + area(l6.bottom) == doctest::Approx(0));
  // The upper step stands on the lower one: no bottom skin at its start, top skin at its end.
  const Skins l10 = skins_of(regions, cores, 10);
  CHECK(area(l10.bottom) == doctest::Approx(0));
  CHECK(area(l10.sparse) == doctest::Approx(100));
  CHECK(area(skins_of(regions, cores, 19).top) == doctest::Approx(100));
  CHECK(area(skins_of(regions, cores, 17).solid) == doctest::Approx(100));
}

TEST_CASE("layer_over_an_overhang_gets_bottom_skin_above_open_air") {
  // 10 mm square under a 20 mm one: layer 10's 300 mm^2 over nothing is bottom skin, and
  // layers 11 and 12 are solid there.
  const auto regions = two_steps(10, 20);
  const auto cores = sparse_cores(regions, 3, 3);
  const Skins l10 = skins_of(regions, cores, 10);
  CHECK(area(l10.bottom) == doctest::Approx(300));
  CHECK(area(l10.top) == doctest::Approx(0));
  CHECK(area(l10.sparse) == doctest::Approx(100));
  for (std::size_t i : {11u, 12u}) {
    const Skins s = skins_of(regions, cores, i);
    CHECK(area(s.bottom) == doctest::Approx(0));
    CHECK(area(s.solid) == doctest::Approx(300));
  }
  CHECK(area(skins_of(regions, cores, 13).sparse) == doctest::Approx(400));
  // Under the overhang the small column's top is covered: no top skin on layer 9.
  CHECK(area(skins_of(regions, cores, 9).top) == doctest::Approx(0));
}

TEST_CASE("first_and_last_layers_are_solid") {
  const auto regions = two_steps(10, 10);
  const auto cores = sparse_cores(regions, 2, 4);
  CHECK(area(skins_of(regions, cores, 0).bottom) == doctest::Approx(100));
  for (std::size_t i : {1u, 2u, 3u}) CHECK(area(skins_of(regions, cores, i).solid) == doctest::Approx(100));
  CHECK(area(skins_of(regions, cores, 4).sparse) == doctest::Approx(100));
  CHECK(area(skins_of(regions, cores, 17).sparse) == doctest::Approx(100));
  CHECK(area(skins_of(regions, cores, 18).solid) == doctest::Approx(100));
  CHECK(area(skins_of(regions, cores, 19).top) == doctest::Approx(100));
}

TEST_CASE("no_skin_layers_make_everything_sparse") {
  const auto regions = two_steps(20, 10);
  const auto cores = sparse_cores(regions, 0, 0);
  REQUIRE(cores.size() == 20);
  for (const auto& core : cores) CHECK(!core);
  const Skins s = split_skins(regions[9], nullptr, nullptr, nullptr, w);
  CHECK(area(s.sparse) == doctest::Approx(400));
}

TEST_CASE("wall_moving_by_microns_between_layers_makes_no_skin") {
  // A side drifting 1 um per layer (a slightly sloped wall) leaves slivers far narrower than
  // a bead: they stay sparse.
  std::vector<Region> regions;
  for (int i = 0; i < 12; ++i) regions.push_back(Region{{rectangle(0, 0, 20 - 0.001 * i, 20)}});
  const auto cores = sparse_cores(regions, 3, 3);
  const Skins s = skins_of(regions, cores, 6);
  CHECK(area(s.sparse) == doctest::Approx(area(regions[6])));
  CHECK(s.top.loops.empty());
  CHECK(s.solid.loops.empty());
}

TEST_CASE("skins_of_nothing_are_nothing") {
  CHECK(sparse_cores({}, 3, 3).empty());
  const Region square{{rectangle(0, 0, 5, 5)}};
  const Skins s = split_skins(Region{}, &square, &square, &square, w);
  CHECK(s.bottom.loops.empty());
  CHECK(s.top.loops.empty());
  CHECK(s.solid.loops.empty());
  CHECK(s.sparse.loops.empty());
}

// ---------------------------------------------------------------------------------------
// Skins by thickness on a stack of mixed layers.

namespace {

// The square block of two_steps, on layers of the given thicknesses.
std::vector<Layer> stack_of(const std::vector<double>& thicknesses) {
  std::vector<Layer> layers;
  double z = 0;
  for (double t : thicknesses) {
    layers.push_back({z, z + t});
    z += t;
  }
  return layers;
}

// Indices of the layers with no sparse core where the region is (solid throughout).
std::vector<std::size_t> solid_layers(const std::vector<std::optional<Region>>& cores) {
  std::vector<std::size_t> solid;
  for (std::size_t i = 0; i < cores.size(); ++i)
    if (cores[i] && area(*cores[i]) < 1e-9) solid.push_back(i);
  return solid;
}

}  // namespace

TEST_CASE("thin_layers_under_a_top_add_layers_until_the_skin_is_thick_enough") {
  // Ten 0.3 mm layers, then six of 0.15 mm: the top 0.6 mm is four thin layers, not three.
  std::vector<double> t(10, 0.3);
  t.insert(t.end(), 6, 0.15);
  const std::vector<Layer> layers = stack_of(t);
  const std::vector<Region> regions(layers.size(), Region{{rectangle(0, 0, 10, 10)}});
  // 3 layers alone: the top three (0.45 mm) and the bottom three (0.9 mm).
  const auto by_count = sparse_cores(regions, layers, {3, 3, 0, 0});
  CHECK(solid_layers(by_count) == std::vector<std::size_t>{0, 1, 2, 13, 14, 15});
  // 3 layers and at least 0.6 mm: the top four thin layers (0.6 mm), the bottom still three.
  const auto by_thickness = sparse_cores(regions, layers, {3, 3, 0.6, 0.6});
  CHECK(solid_layers(by_thickness) == std::vector<std::size_t>{0, 1, 2, 12, 13, 14, 15});
  // 1.0 mm at the bottom: 0.3 + 0.3 + 0.3 < 1.0, so four layers (1.2 mm).
  const auto thick_bottom = sparse_cores(regions, layers, {0, 0, 0, 1.0});
  CHECK(solid_layers(thick_bottom) == std::vector<std::size_t>{0, 1, 2, 3});
  // On uniform layers a thickness of N layers is N layers: the same as counting layers.
  const std::vector<Layer> uniform = stack_of(std::vector<double>(16, 0.2));
  CHECK(solid_layers(sparse_cores(regions, uniform, {0, 0, 0.6, 0.6})) ==
        solid_layers(sparse_cores(regions, 3, 3)));
}

TEST_CASE("a_step_top_on_thin_layers_gets_a_skin_of_its_thickness") {
  // two_steps(20, 10): the lower square's top at layer 9; layers 6-9 are 0.15 mm, the rest
  // 0.3 mm. With 3 layers and 0.6 mm the 300 mm^2 ring is solid on layers 6-9, sparse on 5.
  std::vector<double> t(20, 0.3);
  for (int i = 6; i <= 9; ++i) t[i] = 0.15;
  const std::vector<Layer> layers = stack_of(t);
  const auto regions = two_steps(20, 10);
  const auto cores = sparse_cores(regions, layers, {3, 3, 0.6, 0.6});
  for (std::size_t i : {6u, 7u, 8u}) CHECK(area(skins_of(regions, cores, i).solid) == doctest::Approx(300));
  CHECK(area(skins_of(regions, cores, 9).top) == doctest::Approx(300));
  CHECK(area(skins_of(regions, cores, 5).sparse) == doctest::Approx(400));
  // By count alone layer 6 would be sparse there: the skin would be 0.45 mm.
  const auto counted = sparse_cores(regions, layers, {3, 3, 0, 0});
  CHECK(area(skins_of(regions, counted, 6).sparse) == doctest::Approx(400));
}

}  // namespace skins_test

namespace skins_test {

TEST_CASE("cores_of_the_wanted_layers_only_are_those_of_every_layer") {
  // A cone of squares shrinking by 0.5 mm a layer (every core differs from its neighbours'),
  // on layers of mixed thickness, skins of 3 layers and 0.6 mm: the wanted layers (a sparse
  // sample, a run, both ends, and one past the flags' end) get the same core as when every
  // layer is wanted, the others an empty one.
  std::vector<Region> regions;
  std::vector<double> t;
  for (int i = 0; i < 40; ++i) {
    const double side = 30 - 0.5 * i;
    regions.push_back(Region{{rectangle(-side / 2, -side / 2, side / 2, side / 2)}});
    t.push_back(i % 3 == 0 ? 0.3 : 0.15);
  }
  const std::vector<Layer> layers = stack_of(t);
  const SkinDepth depth{3, 3, 0.6, 0.6};
  const auto every = sparse_cores(regions, layers, depth);
  std::vector<char> wanted(39, 0);  // layer 39 lies past the flags: wanted
  for (std::size_t i : {0, 1, 7, 8, 15, 16, 17, 18, 19, 30, 37, 38}) wanted[i] = 1;
  const auto some = sparse_cores(regions, layers, depth, wanted);
  REQUIRE(some.size() == every.size());
  int cores_with_area = 0;
  for (std::size_t i = 0; i < regions.size(); ++i) {
    CAPTURE(i);
    REQUIRE(some[i].has_value());
    if (i >= wanted.size() || wanted[i]) {
      CHECK(some[i]->loops == every[i]->loops);
      if (area(*every[i]) > 1) ++cores_with_area;
    } else {
      CHECK(some[i]->loops.empty());
    }
  }
  CHECK(cores_with_area >= 6);  // the middle ones have sparse cores to compare
}

}  // namespace skins_test
