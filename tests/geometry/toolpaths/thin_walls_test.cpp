// thin_walls: centre lines of regions narrower than a bead.
#include "geometry/toolpaths/thin_walls.h"

#include <doctest/doctest.h>

#include <cmath>
#include <limits>

#include "geometry/toolpaths/bead_coverage.h"
#include "geometry/toolpaths/toolpath_shapes.h"

namespace thin_walls_test {

using namespace geometry;
using namespace toolpath_shapes;

TEST_CASE("strip_centre_line_ends_half_its_width_from_the_ends") {
  const Region strip{{rectangle(2, 1, 12, 1.3)}};
  const auto paths = thin_walls(strip, 0.1, 0.45);
  REQUIRE(paths.size() == 1);
  CHECK(paths[0].width == doctest::Approx(0.3).epsilon(1e-9));
  for (Vec2 v : paths[0].points) CHECK(v.y == doctest::Approx(1.15).epsilon(1e-9));
  const auto [lo, hi] = std::minmax(paths[0].points.front().x, paths[0].points.back().x);
  CHECK(lo == doctest::Approx(2.15).epsilon(1e-9));
  CHECK(hi == doctest::Approx(11.85).epsilon(1e-9));
}

TEST_CASE("thin_ring_gets_closed_centre_line") {
  // Annulus between regular 120-gons of circumradius 10 and 9.7: the centre line is the
  // 120-gon midway (circumradius 9.85; its points lie between its apothem and that), closed,
  // 0.3 cos(pi/120) wide (the distance between parallel edges).
  const int n = 120;
  const Region ring{{circle({0, 0}, 10, n), reversed(circle({0, 0}, 9.7, n))}};
  const auto paths = thin_walls(ring, 0.1, 0.45);
  REQUIRE(paths.size() == 1);
  CHECK(is_closed(paths[0]));
  CHECK(paths[0].width == doctest::Approx(0.3 * std::cos(std::numbers::pi / n)).epsilon(1e-6));
  for (Vec2 v : paths[0].points) {
    CHECK(std::hypot(v.x, v.y) <= 9.85 + 1e-6);
    CHECK(std::hypot(v.x, v.y) >= 9.85 * std::cos(std::numbers::pi / n) - 1e-6);
  }
  const auto c = bead_coverage::coverage(ring, paths);
  CHECK(c.inside >= 0.99);
  CHECK(c.outside <= 0.01);
}

TEST_CASE("thin_t_junction_is_covered_by_its_centre_lines") {
  // A T of two 0.3 mm strips: the medial axis branches; every branch is printed.
  const Region bar{{rectangle(0, 0, 10, 0.3)}}, stem{{rectangle(4.85, 0, 5.15, 6)}};
  const Region region =
      from_clipper(geometry::clipper::union_nonzero(to_clipper(bar), to_clipper(stem)));
  const auto paths = thin_walls(region, 0.1, 0.45);
  CHECK(paths.size() >= 3);
  const auto c = bead_coverage::coverage(region, paths);
  INFO("inside " << c.inside << " outside " << c.outside);
  CHECK(c.inside >= 0.98);
  CHECK(c.outside <= 0.02);
}

TEST_CASE("tapering_wedge_gets_narrowing_runs") {
  // A 0.4 mm wide base narrowing to a point over 10 mm: widths fall along the line. The tip
  // narrower than the 0.1 mm minimum bead (the last 2.5 mm, 6.25% of the area) is not
  // printed, and each run's constant width misses up to a tenth of its strip.
  const Region wedge{{Loop{{0, 0}, {10, 0.2}, {0, 0.4}}}};
  const auto paths = thin_walls(wedge, 0.1, 0.45);
  REQUIRE(paths.size() >= 2);
  for (const auto& p : paths) {
    CHECK(p.width >= 0.1);
    CHECK(p.width <= 0.4);
  }
  const auto c = bead_coverage::coverage(wedge, paths);
  INFO("inside " << c.inside << " outside " << c.outside);
  CHECK(c.inside >= 0.85);
  CHECK(c.outside <= 0.05);
  for (std::size_t i = 1; i < paths.size(); ++i) CHECK(paths[i].width != paths[0].width);
}

TEST_CASE("centre_lines_stay_inside_separate_sharp_pieces") {
  // Gaps from a bunny layer: a sharp triangle beside two strips. The Voronoi edges between
  // the pieces lie outside; a vertex cell's inside is the wedge at the vertex, not the half
  // plane of either edge, or those edges pass for centre lines running off to 300 mm.
  const Region gaps{{Loop{{0.777198, 7.889621}, {0.755278, 7.973255}, {0.632412, 7.973743},
                          {0.444288, 7.850199}, {0.322145, 7.749248}, {0.380678, 7.664360}},
                     Loop{{-1.222770, 4.792442}, {-1.078476, 4.944983}, {-0.914703, 5.185753},
                          {-0.794999, 5.388626}, {-0.666136, 5.572525}, {-0.588855, 5.703130},
                          {-0.276268, 6.144929}, {-0.253782, 6.192652}, {-0.067470, 6.468732},
                          {0.004425, 6.627414}, {0.084342, 6.773274}, {0.006292, 6.831791},
                          {-0.075124, 6.750382}, {-0.130185, 6.690423}, {-0.208398, 6.575436},
                          {-0.364020, 6.387079}, {-0.613304, 6.056709}, {-0.857049, 5.711446},
                          {-0.906732, 5.613074}, {-1.169199, 5.219279}, {-1.339939, 4.901734},
                          {-1.378683, 4.733492}, {-1.296103, 4.695035}},
                     Loop{{-1.538993, 3.954435}, {-1.872610, 4.060565}, {-1.778600, 3.748122}}}};
  const auto paths = thin_walls(gaps, 0.1125, 0.675);
  REQUIRE(!paths.empty());
  const ClipperLib::Paths region = to_clipper(gaps);
  for (const auto& p : paths) {
    for (Vec2 v : p.points) {
      int inside = 0;
      for (const auto& loop : region) inside += ClipperLib::PointInPolygon(to_clipper(v), loop) != 0;
      CHECK(inside == 1);
    }
  }
  const auto c = bead_coverage::coverage(gaps, paths);
  CHECK(c.outside <= 0.1);
}

TEST_CASE("compact_blob_gets_one_line_through_its_centre") {
  // A regular hexagon 0.6 mm across: its medial axis is six branches into blunt corners,
  // all pruned, yet a bead fits. It gets one line through its centre, as wide as its area
  // over its chord and shorter than the chord by that width (the bead's round ends), but at
  // least a quarter width long.
  const Region hexagon{{circle({3, 2}, 0.3, 6)}};
  const auto paths = thin_walls(hexagon, 0.1, 0.6);
  REQUIRE(paths.size() == 1);
  const ExtrusionPath& line = paths[0];
  const double chord = area(hexagon) / line.width;
  CHECK(length(line.points) ==
        doctest::Approx(std::max(chord - line.width, line.width / 4)).epsilon(1e-6));
  CHECK(chord >= 2 * 0.3 * std::cos(std::numbers::pi / 6) - 1e-5);  // at least across flats
  CHECK(chord <= 0.6 + 1e-5);  // at most corner to corner
  const Vec2 mid = 0.5 * (line.points.front() + line.points.back());
  CHECK(mid.x == doctest::Approx(3).epsilon(1e-9));
  CHECK(mid.y == doctest::Approx(2).epsilon(1e-9));
  const auto c = bead_coverage::coverage(hexagon, paths);
  INFO("inside " << c.inside << " outside " << c.outside);
  CHECK(c.inside >= 0.85);
  CHECK(c.outside <= 0.1);
}

TEST_CASE("strip_too_wide_for_one_bead_gets_two_side_by_side") {
  // A 0.8 x 10 mm strip with beads up to 0.9 mm, paired above 0.675: its centre line (0.8
  // wide) becomes one closed path 0.4 wide a quarter width (0.2) either side of it and
  // round its ends: two beads that tile the strip, neither overlapping nor leaving a gap
  // between them. (The strip's square corners, which the round ends leave, get a dab each.)
  const Region strip{{rectangle(0, 0, 10, 0.8)}};
  const auto paths = thin_walls(strip, 0.1125, 0.9, 0.675);
  REQUIRE(paths.size() == 5);
  CHECK(is_closed(paths[0]));
  CHECK(paths[0].width == doctest::Approx(0.4).epsilon(1e-6));
  for (Vec2 v : paths[0].points) {
    CHECK(v.y >= 0.2 - 1e-6);
    CHECK(v.y <= 0.6 + 1e-6);
  }
  for (std::size_t i = 1; i < paths.size(); ++i) CHECK(length(paths[i].points) < 0.15);
  const auto c = bead_coverage::coverage(strip, paths);
  INFO("inside " << c.inside << " outside " << c.outside << " double " << c.double_coverage);
  CHECK(c.inside >= 0.99);
  CHECK(c.outside <= 0.005);
  CHECK(c.double_coverage <= 0.005);
  // Without pairing it is one bead 0.8 wide.
  const auto single = thin_walls(strip, 0.1125, 0.9);
  REQUIRE(single.size() == 5);
  CHECK(single[0].width == doctest::Approx(0.8).epsilon(1e-6));
}

TEST_CASE("free_ends_reach_on_only_where_their_bead_stays_inside") {
  // A 0.3 mm gap across the middle of a 2 mm wide part (0.85 to 1.15): against walls on
  // either side the centre line runs on by half its width to the gap's ends; cut at the
  // part's edge (the gap reaching x = 0) its end stays half a width in.
  const Region gap{{rectangle(1, 0.85, 9, 1.15)}};
  const Region part{{rectangle(0, 0, 10, 2)}};
  const auto inside = thin_walls(gap, 0.1, 0.45, std::numeric_limits<double>::infinity(), &part);
  REQUIRE(inside.size() == 1);
  CHECK(length(inside[0].points) == doctest::Approx(8).epsilon(1e-6));
  const Region edge_gap{{rectangle(0, 0.85, 9, 1.15)}};
  const auto at_edge =
      thin_walls(edge_gap, 0.1, 0.45, std::numeric_limits<double>::infinity(), &part);
  REQUIRE(at_edge.size() == 1);
  const auto [lo, hi] = std::minmax(at_edge[0].points.front().x, at_edge[0].points.back().x);
  CHECK(lo == doctest::Approx(0.15).epsilon(1e-6));
  CHECK(hi == doctest::Approx(9).epsilon(1e-6));
}

TEST_CASE("thin_walls_of_nothing_is_nothing") {
  CHECK(thin_walls(Region{}, 0.1, 0.45).empty());
  CHECK(thin_walls(Region{{rectangle(0, 0, 1, 1)}}, 0, 0.45).empty());
  CHECK(thin_walls(Region{{Loop{{0, 0}, {1, 0}}}}, 0.1, 0.45).empty());
}

}  // namespace thin_walls_test
