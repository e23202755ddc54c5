// Support and raft toolpaths: lines that stack, interfaces that reach their edges.
#include "geometry/toolpaths/support_paths.h"

#include <doctest/doctest.h>

#include <cmath>

#include "geometry/core/clipper.h"
#include "geometry/toolpaths/toolpath_shapes.h"

namespace support_paths_test {

using namespace geometry;
using namespace toolpath_shapes;

namespace {

constexpr double w = 0.45;

// Whether every point of the path lies within the rectangle (mm, with a tolerance).
bool within(const ExtrusionPath& path, double x0, double y0, double x1, double y1, double tol) {
  for (Vec2 p : path.points) {
    if (p.x < x0 - tol || p.x > x1 + tol || p.y < y0 - tol || p.y > y1 + tol) return false;
  }
  return true;
}

}  // namespace

TEST_CASE("body_lines_lie_on_a_grid_fixed_in_the_part_so_layers_stack") {
  SupportPathOptions o;
  o.spacing = 2.5;
  // Two regions, as two layers' support might be: the lines along x lie at the same heights.
  for (const Region& body : {Region{{rectangle(0.3, 0.7, 20.1, 10.9)}}, Region{{rectangle(-3, -1, 12, 14)}}}) {
    const auto paths = support_body_paths(body, w, o);
    REQUIRE_FALSE(paths.empty());
    for (const ExtrusionPath& path : paths) {
      CHECK(path.role == PathRole::support);
      CHECK(path.width == w);
      CHECK(within(path, -3 + w / 2 - 1e-6, -1, 20.1, 14, 1e-6));
      for (std::size_t i = 1; i < path.points.size(); ++i) {
        const Vec2 a = path.points[i - 1], b = path.points[i];
        if (std::abs(a.y - b.y) < 1e-9 && std::abs(a.x - b.x) > 1) {  // a line, not a connector
          const bool sheath = std::abs(a.y - (body.loops[0][0].y + w / 2)) < 1e-6 ||
                              std::abs(a.y - (body.loops[0][2].y - w / 2)) < 1e-6;
          CHECK((sheath || std::abs(a.y / 2.5 - std::round(a.y / 2.5)) < 1e-6));
        }
      }
    }
  }
}

TEST_CASE("sheath_runs_only_along_the_lines_off_them") {
  SupportPathOptions o;
  o.spacing = 2.5;
  // The sheath of a body whose edges along the lines (along x, at y = 2.5 k) lie off every
  // line: those two sides, half a bead in; none across the lines (x = 0, 10), where what
  // stands on the edge bridges from line to line. Off by 0.675 and 0.925 mm here.
  auto sheath_length = [&](const Region& body, double y_lo, double y_hi) {
    double along = 0;
    for (const ExtrusionPath& path : support_sheath(to_clipper(body), body, w, o).paths) {
      for (Vec2 p : path.points) {
        CHECK((std::abs(p.y - y_lo) < 1e-6 || std::abs(p.y - y_hi) < 1e-6));
      }
      along += length(path.points);
    }
    return along;
  };
  CHECK(sheath_length(Region{{rectangle(0, 0.7, 10, 10.9)}}, 0.7 + w / 2, 10.9 - w / 2) ==
        doctest::Approx(2 * (10 - w)).epsilon(1e-6));
  // Its sides on the lines at y = 0 and 5 (a body widened to them, half a bead past):
  // no sheath; the lines, half a bead in from every edge, carry what stands on it.
  const Region on_lines{{rectangle(0, -w / 2 - 0.01, 10, 5 + w / 2 + 0.01)}};
  CHECK(sheath_length(on_lines, 0, 0) == 0);
  bool lines[3] = {false, false, false};
  for (const ExtrusionPath& path : support_body_paths(on_lines, w, o)) {
    for (std::size_t i = 1; i < path.points.size(); ++i) {
      const Vec2 a = path.points[i - 1], b = path.points[i];
      if (std::abs(a.y - b.y) > 1e-9) continue;
      for (int k = 0; k < 3; ++k) {
        if (std::abs(a.y - 2.5 * k) < 1e-6 && std::min(a.x, b.x) < w / 2 + 1e-6 &&
            std::max(a.x, b.x) > 10 - w / 2 - 1e-6) {
          lines[k] = true;
        }
      }
    }
  }
  CHECK(lines[0]);
  CHECK(lines[1]);
  CHECK(lines[2]);
  // Beside an interface, none: the interface has its own loop.
  const Region body{{rectangle(0, 0.7, 10, 5.6)}};
  clipper::Paths support = to_clipper(body);
  const clipper::Paths interface = to_clipper(Region{{rectangle(0, 5.6, 10, 10.9)}});
  support = clipper::union_nonzero(support, interface);
  double beside = 0;
  for (const ExtrusionPath& path : support_sheath(support, body, w, o).paths) {
    for (Vec2 p : path.points) CHECK(p.y < 5.6 + 1e-6);
    beside += length(path.points);
  }
  CHECK(beside == doctest::Approx(10 - w).epsilon(1e-6));  // the bottom side alone
}

TEST_CASE("sheath_is_laid_only_where_the_layer_below_carries_it") {
  SupportPathOptions o;
  const Region body{{rectangle(0, 0.7, 10, 10.9)}};
  // Below: the same island: the whole sheath. Below: only its left half: the sheath's left
  // halves.
  const Region all{{rectangle(-1, -1, 11, 12)}}, left{{rectangle(-1, -1, 5, 12)}};
  auto on_sheath = [&](const ExtrusionPath& path) {
    bool sheath = !path.points.empty();
    for (Vec2 p : path.points) {
      sheath = sheath && (std::abs(p.y - (0.7 + w / 2)) < 1e-6 || std::abs(p.y - (10.9 - w / 2)) < 1e-6);
    }
    return sheath;
  };
  double full = 0, kept = 0;
  for (const ExtrusionPath& path : support_body_paths(body, w, o, &all)) {
    if (on_sheath(path)) full += length(path.points);
  }
  for (const ExtrusionPath& path : support_body_paths(body, w, o, &left)) {
    CHECK(within(path, 0, 0.7, 10, 10.9, 1e-6));
    if (!on_sheath(path)) continue;
    for (Vec2 p : path.points) CHECK(p.x <= 5 + 1e-6);
    kept += length(path.points);
  }
  CHECK(full == doctest::Approx(2 * (10 - w)).epsilon(1e-6));
  CHECK(kept == doctest::Approx(2 * (5 - w / 2)).epsilon(1e-6));
  o.sheath = false;
  for (const ExtrusionPath& path : support_body_paths(body, w, o)) CHECK_FALSE(on_sheath(path));
}

TEST_CASE("body_lines_are_joined_along_the_edge_up_to_two_spacings") {
  SupportPathOptions o;
  o.spacing = 2.5;
  o.sheath = false;
  // A parallelogram 20 mm along x, its slanted sides rising at `degrees` to the lines: the
  // ends of neighbouring lines (2.5 mm apart across them) lie 2.5 / sin(degrees) apart along
  // those sides, 3.5 mm at 45 degrees (joined), 5.9 mm at 25 (not: more than two spacings).
  for (const double degrees : {45.0, 25.0}) {
    CAPTURE(degrees);
    const double run = 10 / std::tan(degrees * M_PI / 180);
    const Region body{{{{0, 0.3}, {20, 0.3}, {20 + run, 10.3}, {run, 10.3}}}};
    std::size_t lines = 0, paths = 0;
    for (const ExtrusionPath& path : support_body_paths(body, w, o)) {
      ++paths;
      for (std::size_t i = 1; i < path.points.size(); ++i) {
        if (std::abs(path.points[i].y - path.points[i - 1].y) < 1e-9) ++lines;
      }
    }
    CHECK(lines == 4);  // y = 2.5, 5, 7.5, 10
    CHECK(paths == (degrees > 30 ? 1u : 4u));
  }
}

TEST_CASE("grid_body_lays_lines_both_ways") {
  SupportPathOptions o;
  o.pattern = SupportPattern::grid;
  const auto paths = support_body_paths(Region{{rectangle(0, 0, 20, 20)}}, w, o);
  bool along_x = false, along_y = false;
  for (const ExtrusionPath& path : paths) {
    for (std::size_t i = 1; i < path.points.size(); ++i) {
      const Vec2 d = path.points[i] - path.points[i - 1];
      along_x = along_x || (std::abs(d.y) < 1e-9 && std::abs(d.x) > 10);
      along_y = along_y || (std::abs(d.x) < 1e-9 && std::abs(d.y) > 10);
    }
  }
  CHECK(along_x);
  CHECK(along_y);
}

TEST_CASE("interface_is_a_loop_round_its_edge_and_lines_across_the_body") {
  SupportPathOptions o;
  o.interface_density = 80;
  const auto paths = support_interface_paths(Region{{rectangle(0, 0, 10, 6)}}, w, 0.2, o);
  REQUIRE_FALSE(paths.empty());
  std::size_t loops = 0, lines = 0;
  for (const ExtrusionPath& path : paths) {
    CHECK(path.role == PathRole::support_interface);
    CHECK(within(path, w / 2, w / 2, 10 - w / 2, 6 - w / 2, 1e-6));
    if (is_closed(path)) {
      ++loops;
    } else {
      ++lines;
      // Across the body's lines (90 degrees), from the loop's centre line to its centre line.
      CHECK(path.points.size() == 2);
      CHECK(std::abs(path.points[0].x - path.points[1].x) < 1e-9);
      CHECK(std::abs(path.points[0].y - path.points[1].y) == doctest::Approx(6 - w).epsilon(1e-6));
    }
  }
  CHECK(loops == 1);
  // At 80% of solid: lines about (0.45 - 0.2 (1 - pi/4)) / 0.8 = 0.509 mm apart over the 9.55
  // mm between the loop's sides.
  CHECK(lines >= 17);
  CHECK(lines <= 20);
}

TEST_CASE("raft_base_is_wide_lines_in_a_loop_and_the_surface_is_solid") {
  SupportPathOptions o;
  o.raft_base_width = 0.8;
  o.raft_base_spacing = 2;
  const Region area{{rectangle(0, 0, 20, 20)}};
  const auto base = raft_paths(area, RaftPart::base, 0, 0.5, 0.3, o);
  REQUIRE_FALSE(base.empty());
  double base_length = 0;
  for (const ExtrusionPath& path : base) {
    CHECK(path.role == PathRole::raft);
    CHECK(path.width == 0.8);
    base_length += length(path.points);
  }
  // A loop (4 x 19.2) and lines 2 mm apart across the 18.4 mm inside it: about 9 x 19.2.
  CHECK(base_length == doctest::Approx(4 * 19.2 + 9 * 19.2).epsilon(0.1));
  const auto surface = raft_paths(area, RaftPart::surface, 3, w, 0.2, o);
  double surface_length = 0;
  for (const ExtrusionPath& path : surface) surface_length += length(path.points) * path.width;
  // Solid: bead width times length about the area's... beads of share 0.407 fill 400 mm^2.
  CHECK(surface_length == doctest::Approx(400.0 * w / 0.407).epsilon(0.1));
}

TEST_CASE("nothing_gives_no_support_paths") {
  SupportPathOptions o;
  CHECK(support_body_paths(Region{}, w, o).empty());
  CHECK(support_interface_paths(Region{}, w, 0.2, o).empty());
  CHECK(raft_paths(Region{}, RaftPart::base, 0, w, 0.3, o).empty());
  o.spacing = 0;
  CHECK(support_body_paths(Region{{rectangle(0, 0, 5, 5)}}, w, o).empty());
}

}  // namespace support_paths_test
