// Boundary pairs of a footprint and which side of each loop is solid (boundary_pair.h).
#include <doctest/doctest.h>

#include <algorithm>
#include <vector>

#include "geometry/core/point_in_region.h"
#include "geometry/core/polygon.h"
#include "geometry/slab/boundary_pair.h"

namespace boundary_pair_test {

using namespace geometry;

namespace {

Loop square(double x0, double y0, double side, bool clockwise = false) {
  Loop loop{{x0, y0}, {x0 + side, y0}, {x0 + side, y0 + side}, {x0, y0 + side}};
  if (clockwise) std::reverse(loop.begin(), loop.end());
  return loop;
}

}  // namespace

TEST_CASE("ring_gives_one_pair_with_its_hole") {
  const Region ring{{square(0, 0, 10), square(2, 2, 6, true)}};
  const std::vector<BoundaryPair> pairs = boundary_pairs(ring);
  REQUIRE(pairs.size() == 1);
  CHECK(signed_area(pairs[0].outer) == doctest::Approx(100));
  REQUIRE(pairs[0].inner.size() == 1);
  CHECK(signed_area(pairs[0].inner[0]) == doctest::Approx(-36));
  CHECK(loops_of(pairs[0]).size() == 2);
  CHECK(loops_of(pairs[0])[0] == &pairs[0].outer);
}

TEST_CASE("island_in_a_hole_is_a_pair_of_its_own") {
  const Region nested{{square(0, 0, 10), square(2, 2, 6, true), square(4, 4, 2)}};
  const std::vector<BoundaryPair> pairs = boundary_pairs(nested);
  REQUIRE(pairs.size() == 2);
  const auto big = std::find_if(pairs.begin(), pairs.end(),
                                [](const BoundaryPair& p) { return signed_area(p.outer) > 50; });
  const auto small = std::find_if(pairs.begin(), pairs.end(),
                                  [](const BoundaryPair& p) { return signed_area(p.outer) < 5; });
  REQUIRE(big != pairs.end());
  REQUIRE(small != pairs.end());
  CHECK(big->inner.size() == 1);
  CHECK(small->inner.empty());
  CHECK(signed_area(small->outer) == doctest::Approx(4));
}

TEST_CASE("disc_is_a_pair_without_inner_boundary_whatever_its_orientation") {
  const std::vector<BoundaryPair> pairs = boundary_pairs(Region{{square(0, 0, 3, true)}});
  REQUIRE(pairs.size() == 1);
  CHECK(signed_area(pairs[0].outer) == doctest::Approx(9));
  CHECK(pairs[0].inner.empty());
}

TEST_CASE("empty_footprint_has_no_pairs") { CHECK(boundary_pairs(Region{}).empty()); }

TEST_CASE("solid_beside_reads_each_free_face_off_the_section") {
  const BoundaryPair pair = boundary_pairs(Region{{square(0, 0, 10), square(2, 2, 6, true)}})[0];
  // Section inside the hole only: solid in the hole, empty outside (a sphere's lower half).
  const Region inner_section{{square(1, 1, 8)}};
  CHECK(solid_beside(pair, inner_section) == std::vector<char>{0, 1});
  // Solid all round (a cavity ending inside the slab) and nowhere (a cap).
  CHECK(solid_beside(pair, Region{{square(-5, -5, 20)}}) == std::vector<char>{1, 1});
  CHECK(solid_beside(pair, Region{}) == std::vector<char>{0, 0});
  // A plate with a hole: solid outside, empty in the hole.
  const Region plate{{square(-5, -5, 20), square(1, 1, 8, true)}};
  CHECK(solid_beside(pair, plate) == std::vector<char>{1, 0});
}

TEST_CASE("point_in_region_follows_the_winding") {
  const Region ring{{square(0, 0, 10), square(2, 2, 6, true)}};
  CHECK(point_in_region(ring, {1, 1}));
  CHECK_FALSE(point_in_region(ring, {5, 5}));
  CHECK_FALSE(point_in_region(ring, {11, 5}));
  CHECK(point_in_region(ring, {0, 5}));  // on the boundary
  CHECK_FALSE(point_in_region(Region{}, {0, 0}));
}

}  // namespace boundary_pair_test
