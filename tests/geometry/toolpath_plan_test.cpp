// plan_toolpaths: coverage of the region by the rebuilt beads, order, travel, determinism.
#include "geometry/toolpath_plan.h"

#include <doctest/doctest.h>
#include <tbb/task_arena.h>

#include <cmath>
#include <numbers>

#include "geometry/bead_coverage.h"
#include "geometry/toolpath_shapes.h"

using namespace geometry;
using namespace toolpath_shapes;

namespace {

// One layer 0.2 mm thick: every point is a bottom (and top) surface, so all of it is solid.
std::vector<LayerToolpaths> single_layer(const Region& region, ToolpathOptions options = {}) {
  options.skirt_loops = 0;
  options.first_layer_width = options.extrusion_width;
  return plan_toolpaths({region}, {Layer{0, 0.2}}, options);
}

void check_covered(const Region& region, const std::vector<ExtrusionPath>& paths) {
  const auto c = bead_coverage::coverage(region, paths);
  INFO("inside " << c.inside << " outside " << c.outside << " double " << c.double_coverage
               << " paths " << paths.size());
  CHECK(c.inside >= 0.98);
  CHECK(c.outside <= 0.02);
}

}  // namespace

TEST_CASE("solid_layer_covers_square") {
  const Region square{{rectangle(0, 0, 20, 20)}};
  const auto plan = single_layer(square);
  REQUIRE(plan.size() == 1);
  check_covered(square, plan[0].paths);
}

TEST_CASE("solid_layer_covers_disc") {
  const Region disc{{circle({5, 5}, 10)}};
  check_covered(disc, single_layer(disc)[0].paths);
}

TEST_CASE("solid_layer_covers_square_with_hole") {
  const Region holed{{rectangle(0, 0, 20, 20), reversed(circle({10, 10}, 4))}};
  check_covered(holed, single_layer(holed)[0].paths);
}

TEST_CASE("solid_layer_covers_strip_narrower_than_two_widths") {
  for (double w : {0.5, 0.6, 0.8, 0.85}) {
    CAPTURE(w);
    const Region strip{{rectangle(0, 0, 15, w)}};
    check_covered(strip, single_layer(strip)[0].paths);
  }
}

TEST_CASE("solid_layer_covers_region_thinner_than_one_width") {
  for (double w : {0.2, 0.3, 0.4}) {
    CAPTURE(w);
    const Region strip{{rectangle(0, 0, 15, w)}};
    const auto paths = single_layer(strip)[0].paths;
    REQUIRE(!paths.empty());
    for (const auto& p : paths) CHECK(p.role == PathRole::thin_wall);
    check_covered(strip, paths);
  }
}
