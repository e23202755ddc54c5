// Missed features: an island of the slab's footprint that the region does not touch.
#include <doctest/doctest.h>

#include "geometry/contour/contour_strategy.h"
#include "geometry/slicing/layer_stack.h"
#include "geometry/metrics/missed_features.h"
#include "geometry/slab/slab.h"
#include "support/solids.h"

namespace missed_features_test {

using geometry::LayerStack;
using geometry::Region;

TEST_CASE("bump_inside_a_slab_is_missed_by_lower_and_mid_not_by_ma") {
  // A plate [0, 0.6] and, beside it, a small block from z = 0.32 to 0.40 (held up by nothing:
  // only its footprint matters). The slab [0.3, 0.6] holds all of the block: lower (0.3) and
  // mid (0.45) cut beside it; the medial-axis contour keeps it (a cap of the slab).
  const solids::Solid both = solids::combine(solids::box({0, 0, 0}, {10, 10, 0.6}),
                                             solids::box({14, 0, 0.32}, {16, 2, 0.40}));
  const LayerStack stack(both.mesh, geometry::uniform_layers(0.6, 0.3));
  const std::size_t layer = 1;
  const Region footprint = geometry::slab_footprint(geometry::slab_of(stack, layer));
  REQUIRE(geometry::boundary_pairs(footprint).size() == 2);
  CHECK(geometry::missed_features(footprint, stack.lower(layer)).size() == 1);
  CHECK(geometry::missed_features(footprint, stack.mid(layer)).size() == 1);
  CHECK(geometry::missed_features(footprint, geometry::layer_contour(stack, layer, geometry::contour_strategy("ma")))
            .empty());
  // Nothing printed misses everything; the section through the block (z = 0.35) nothing.
  CHECK(geometry::missed_features(footprint, Region{}).size() == 2);
  CHECK(geometry::missed_features(footprint, stack.cross_section(0.35)).empty());
}

TEST_CASE("missed_features_of_an_empty_footprint_are_none") {
  CHECK(geometry::missed_features(Region{}, Region{}).empty());
  const Region square{{{{0, 0}, {1, 0}, {1, 1}, {0, 1}}}};
  CHECK(geometry::missed_features(Region{}, square).empty());
  CHECK(geometry::missed_features(square, square).empty());
}

TEST_CASE("region_touching_an_island_only_at_its_edge_misses_it") {
  // Two squares sharing an edge overlap by no area: that is not touching.
  const Region island{{{{0, 0}, {1, 0}, {1, 1}, {0, 1}}}};
  const Region beside{{{{1, 0}, {2, 0}, {2, 1}, {1, 1}}}};
  const Region overlapping{{{{0.9, 0}, {2, 0}, {2, 1}, {0.9, 1}}}};
  CHECK(geometry::missed_features(island, beside).size() == 1);
  CHECK(geometry::missed_features(island, overlapping).empty());
}

}  // namespace missed_features_test
