// zigzag: scan lines joined along the edge of the area into few paths.
#include "geometry/toolpaths/zigzag.h"

#include <doctest/doctest.h>

#include <cmath>

#include "geometry/toolpaths/toolpath_shapes.h"

namespace zigzag_test {

using namespace geometry;
using namespace toolpath_shapes;

namespace {

bool on_boundary(const Region& region, Vec2 p, double tolerance = 1e-7) {
  for (const Loop& loop : region.loops) {
    for (std::size_t i = 0; i < loop.size(); ++i) {
      if (distance_to_segment(p, loop[i], loop[(i + 1) % loop.size()]) <= tolerance) return true;
    }
  }
  return false;
}

// Length of the path's pieces that run along scan lines (horizontal, at y = offset + k s),
// and of the rest (connectors), which must lie on the area's edge.
struct Split {
  double along = 0, connectors = 0;
  int off_edge = 0;  // connector pieces not on the edge
};

Split split(const std::vector<ExtrusionPath>& paths, const Region& area, double offset,
            double spacing) {
  Split s;
  for (const auto& path : paths) {
    for (std::size_t i = 0; i + 1 < path.points.size(); ++i) {
      const Vec2 a = path.points[i], b = path.points[i + 1];
      const double length = std::hypot(b.x - a.x, b.y - a.y);
      const double k = (a.y - offset) / spacing;
      if (a.y == b.y && std::abs(k - std::round(k)) < 1e-9 && !on_boundary(area, 0.5 * (a + b))) {
        s.along += length;
      } else {
        s.connectors += length;
        s.off_edge += !on_boundary(area, a) || !on_boundary(area, b) ||
                      !on_boundary(area, 0.5 * (a + b));
      }
    }
  }
  return s;
}

}  // namespace

TEST_CASE("square_lines_join_into_one_zigzag_up_the_sides") {
  // Lines at y = 0.5, 1.5, ..., 9.5 across a 10 mm square, joined alternately at x = 10 and
  // x = 0 by 1 mm pieces of the sides: one path, starting at the lowest line.
  const Region square{{rectangle(0, 0, 10, 10)}};
  const auto paths = zigzag(square, {0, 1, 0.5}, 5, nullptr, PathRole::sparse_infill, 0.45);
  REQUIRE(paths.size() == 1);
  const auto& p = paths[0].points;
  REQUIRE(p.size() == 20);
  for (std::size_t k = 0; k < 10; ++k) {
    const double y = 0.5 + static_cast<double>(k);
    const double start = k % 2 ? 10 : 0;
    CHECK(p[2 * k] == Vec2{start, y});
    CHECK(p[2 * k + 1] == Vec2{10 - start, y});
  }
  CHECK(length(p) == doctest::Approx(10 * 10 + 9 * 1));
  CHECK(paths[0].role == PathRole::sparse_infill);
  CHECK(paths[0].width == 0.45);
}

TEST_CASE("free_ends_reach_on_along_their_line_to_the_area_to_fill") {
  const Region square{{rectangle(0, 0, 10, 10)}}, fill{{rectangle(-0.25, -0.25, 10.25, 10.25)}};
  const auto paths = zigzag(square, {0, 1, 0.5}, 5, &fill, PathRole::top_skin, 0.5);
  REQUIRE(paths.size() == 1);
  CHECK(paths[0].points.front() == Vec2{-0.25, 0.5});
  CHECK(paths[0].points.back() == Vec2{-0.25, 9.5});  // line 9 runs right to left
  CHECK(paths[0].points[1] == Vec2{10, 0.5});        // joined ends stay on the edge
}

TEST_CASE("connectors_longer_than_the_limit_leave_the_lines_apart") {
  const Region square{{rectangle(0, 0, 10, 10)}};
  const auto paths = zigzag(square, {0, 1, 0.5}, 0.9, nullptr, PathRole::sparse_infill, 0.45);
  CHECK(paths.size() == 10);
  for (const auto& path : paths) {
    REQUIRE(path.points.size() == 2);
    CHECK(length(path.points) == doctest::Approx(10));
  }
  CHECK(zigzag(square, {0, 1, 0.5}, 0, nullptr, PathRole::sparse_infill, 0.45).size() == 10);
}

TEST_CASE("lines_at_an_angle_keep_their_grid_and_connectors_follow_the_edge") {
  // A disc, lines at 30 degrees 0.7 mm apart through the origin: in the frame of the lines
  // every piece either lies on a scan line or on the (rotated) disc's edge; a convex area
  // gives a single zig-zag when connectors may be as long as it takes (near the top and
  // bottom of the disc the edge runs nearly along the lines: an arc between two lines there
  // is up to sqrt(2 r s) = 3.7 mm long).
  const Region disc{{circle({1, 2}, 10, 256)}};
  const auto paths = zigzag(disc, {30, 0.7, 0}, 4, nullptr, PathRole::sparse_infill, 0.45);
  REQUIRE(paths.size() == 1);
  CHECK(zigzag(disc, {30, 0.7, 0}, 3, nullptr, PathRole::sparse_infill, 0.45).size() > 1);
  const double c = std::cos(std::numbers::pi / 6), s = std::sin(std::numbers::pi / 6);
  auto into = [&](Vec2 p) { return Vec2{p.x * c + p.y * s, -p.x * s + p.y * c}; };
  Region rotated;
  rotated.loops.emplace_back();
  for (Vec2 p : disc.loops[0]) rotated.loops[0].push_back(into(p));
  std::vector<ExtrusionPath> in_frame = paths;
  for (auto& path : in_frame)
    for (Vec2& p : path.points) p = into(p);
  // Round-off of the rotation: compare within a nanometre.
  for (auto& path : in_frame)
    for (Vec2& p : path.points) p.y = std::round(p.y * 1e9) / 1e9;
  const Split pieces = split(in_frame, rotated, 0, 0.7);
  CHECK(pieces.off_edge == 0);
  // The lines are the disc's chords at heights 0.7 k: together about area / spacing.
  CHECK(pieces.along == doctest::Approx(area(disc) / 0.7).epsilon(0.01));
  // Each connector spans one spacing across the lines: about the edge's length, once.
  CHECK(pieces.connectors <= perimeter(disc));
}

TEST_CASE("a_hole_splits_lines_and_connectors_run_round_it") {
  // 10 mm square with a 2 mm hole in the middle; lines at y = 0.5 ... 9.5: the two through
  // the hole are cut in two. Lines total 8 * 10 + 2 * 8 mm; every other piece lies on an
  // edge, outer or hole.
  const Region holed{{rectangle(0, 0, 10, 10), reversed(rectangle(4, 4, 6, 6))}};
  const auto paths = zigzag(holed, {0, 1, 0.5}, 4, nullptr, PathRole::solid_infill, 0.45);
  const Split pieces = split(paths, holed, 0.5, 1);
  CHECK(pieces.along == doctest::Approx(96));
  CHECK(pieces.off_edge == 0);
  CHECK(paths.size() <= 3);
  for (const auto& path : paths) {
    for (std::size_t i = 0; i + 1 < path.points.size(); ++i) {
      const Vec2 mid = 0.5 * (path.points[i] + path.points[i + 1]);
      CHECK(!(mid.x > 4 && mid.x < 6 && mid.y > 4 && mid.y < 6));
    }
  }
}

TEST_CASE("a_scan_line_through_a_corner_alone_gives_no_line") {
  // A diamond with its bottom and top corners on scan lines 0 and 10: those lines touch it
  // in a point and are dropped; lines 1 to 9 zig-zag.
  const Region diamond{{Loop{{5, 0}, {10, 5}, {5, 10}, {0, 5}}}};
  const auto paths = zigzag(diamond, {0, 1, 0}, 3, nullptr, PathRole::sparse_infill, 0.45);
  REQUIRE(paths.size() == 1);
  const Split pieces = split(paths, diamond, 0, 1);
  // Chords of the diamond at y = 1..9: 2 * min(y, 10 - y) each.
  CHECK(pieces.along == doctest::Approx(2 * (1 + 2 + 3 + 4 + 5 + 4 + 3 + 2 + 1)));
  CHECK(pieces.off_edge == 0);
}

TEST_CASE("where_the_loop_starts_does_not_change_the_paths") {
  Loop a = circle({0, 0}, 6, 90);
  Loop b = a;
  std::rotate(b.begin(), b.begin() + 37, b.end());
  const Region fill{{circle({0, 0}, 6.2, 90)}};
  const auto pa = zigzag(Region{{a}}, {45, 0.9, 0.1}, 3, &fill, PathRole::sparse_infill, 0.45);
  const auto pb = zigzag(Region{{b}}, {45, 0.9, 0.1}, 3, &fill, PathRole::sparse_infill, 0.45);
  REQUIRE(pa.size() == pb.size());
  for (std::size_t i = 0; i < pa.size(); ++i) {
    REQUIRE(pa[i].points.size() == pb[i].points.size());
    for (std::size_t k = 0; k < pa[i].points.size(); ++k) {
      CHECK(pa[i].points[k].x == doctest::Approx(pb[i].points[k].x).epsilon(1e-12));
      CHECK(pa[i].points[k].y == doctest::Approx(pb[i].points[k].y).epsilon(1e-12));
    }
  }
}

TEST_CASE("nothing_to_scan_gives_no_paths") {
  const Region square{{rectangle(0, 0, 10, 10)}};
  CHECK(zigzag(Region{}, {0, 1, 0}, 3, nullptr, PathRole::sparse_infill, 0.45).empty());
  CHECK(zigzag(square, {0, 0, 0}, 3, nullptr, PathRole::sparse_infill, 0.45).empty());
  CHECK(zigzag(square, {0, -1, 0}, 3, nullptr, PathRole::sparse_infill, 0.45).empty());
  CHECK(zigzag(square, {0, 1e-9, 0}, 3, nullptr, PathRole::sparse_infill, 0.45).empty());
  CHECK(zigzag(square, {0, 1, NAN}, 3, nullptr, PathRole::sparse_infill, 0.45).empty());
}

}  // namespace zigzag_test
