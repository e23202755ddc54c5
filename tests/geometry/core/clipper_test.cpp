// The Clipper layer's offset (clipper.h): worked by hand, and against Clipper's own
// offsetter on clean, wavy regions.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "geometry/core/clipper_specks.h"
#include "geometry/core/polygon.h"

namespace clipper_test {

using geometry::Loop;
using geometry::Region;
using geometry::Vec2;
namespace clipper = geometry::clipper;

namespace {

// A loop of n vertices round (cx, cy) at radius r(angle), CCW (reverse it for a hole).
template <class Radius>
Loop round_loop(double cx, double cy, int n, Radius r) {
  Loop loop;
  for (int i = 0; i < n; ++i) {
    const double a = 2 * std::numbers::pi * i / n;
    loop.push_back({cx + r(a) * std::cos(a), cy + r(a) * std::sin(a)});
  }
  return loop;
}

// The axis-aligned square [x0, x1] x [y0, y1], CCW; hole(): the same, CW.
Loop square(double x0, double y0, double x1, double y1) {
  return Loop{{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}};
}
Loop hole(double x0, double y0, double x1, double y1) {
  Loop loop = square(x0, y0, x1, y1);
  std::reverse(loop.begin(), loop.end());
  return loop;
}

// Area of the symmetric difference, mm^2.
double difference_area(const clipper::Paths& a, const clipper::Paths& b) {
  return clipper::area_mm2(clipper::difference(a, b)) + clipper::area_mm2(clipper::difference(b, a));
}

// Clipper's own offsetter, the reference.
clipper::Paths clipper_offset(const clipper::Paths& region, double delta, ClipperLib::JoinType join,
                              double miter_limit) {
  return clipper::library_offset(region, delta, join, ClipperLib::etClosedPolygon, 0.005,
                                 miter_limit);
}

}  // namespace

// A regular 720-gon of circumradius 10: every vertex turns by half a degree, so a grown
// loop is mitred at each and a shrunk one meets its moved edges where they cross; either
// way the offset is the 720-gon whose apothem is d more or less, of area n a^2 tan(pi/n).
TEST_CASE("offset_of_a_fine_polygon_moves_every_edge_by_the_distance") {
  constexpr int n = 720;
  const Region circle{{round_loop(0, 0, n, [](double) { return 10.0; })}};
  const double apothem = 10 * std::cos(std::numbers::pi / n);
  for (double d : {-2.0, -0.2, 0.2, 2.0}) {
    CAPTURE(d);
    const clipper::Paths result = clipper::offset(geometry::to_clipper(circle), d);
    REQUIRE(result.size() == 1);
    CHECK(result[0].size() == n);
    const double a = apothem + d;
    CHECK(clipper::area_mm2(result) == doctest::Approx(n * a * a * std::tan(std::numbers::pi / n))
                                      .epsilon(1e-6));
  }
}

// A 10 mm square shrunk by 1 mm is the 8 mm square, also beside a speck of a hole that a
// simplification left outside it, past its largest y. (Clipper's offsetter takes the
// orientation of the loop with the vertex of largest y for every outer loop's: it turned
// this region inside out and shrank it to nothing.)
TEST_CASE("offset_takes_outer_loops_ccw_and_holes_cw_whatever_loop_is_lowest") {
  const Loop square{{0, 0}, {10, 0}, {10, 10}, {0, 10}};
  const Loop speck{{5, 10.5}, {5.1, 10.6}, {5.2, 10.5}};  // CW, 0.01 mm^2
  const clipper::Paths shrunk = clipper::offset(geometry::to_clipper(Region{{square, speck}}), -1);
  CHECK(clipper::area_mm2(shrunk) == doctest::Approx(64).epsilon(1e-9));
  // Growing closes the speck, a hole 0.2 mm across (turned inside out, it would add a speck
  // of its own).
  const clipper::Paths grown = clipper::offset(geometry::to_clipper(Region{{square, speck}}), 1);
  CHECK(clipper::area_mm2(grown) == doctest::Approx(144).epsilon(1e-9));
}

// Regions Clipper's offsetter is the reference for, every join, growing and shrinking:
// wavy islands with a wavy hole, some waves shorter than the distance (where the moved edges
// cross beyond their halves and the offset goes back through the vertex), some parts
// narrower than twice the distance (which a shrink removes); a thin ring, whose loops pass
// each other when shrunk without crossing (its hole's loop then holds the outer one); two
// discs that merge when grown. The same region to a few nanometres along the edges.
TEST_CASE("offset_gives_the_region_clippers_offsetter_gives") {
  const Loop outer = round_loop(0, 0, 400, [](double a) {
    return 10 + 1.5 * std::sin(7 * a) + 0.4 * std::sin(61 * a) + 0.05 * std::sin(173 * a);
  });
  Loop hole = round_loop(1, 0, 150, [](double a) { return 4 + 0.8 * std::sin(5 * a); });
  std::reverse(hole.begin(), hole.end());
  const Loop sliver{{20, 0}, {30, 0.3}, {30, 0.5}, {20, 1}, {19.5, 0.4}};  // 0.5 to 1 mm wide
  Loop ring_hole = round_loop(0, 0, 300, [](double) { return 9.5; });
  std::reverse(ring_hole.begin(), ring_hole.end());
  const Region regions[] = {
      Region{{outer, hole, sliver}},
      Region{{round_loop(0, 0, 300, [](double) { return 10.0; }), ring_hole}},
      Region{{round_loop(0, 0, 200, [](double) { return 2.0; }),
              round_loop(4.4, 0, 200, [](double) { return 2.0; })}}};
  for (const Region& r : regions) {
    const clipper::Paths region = geometry::to_clipper(r);
    for (auto [join, limit] : {std::pair{ClipperLib::jtMiter, 2.0}, std::pair{ClipperLib::jtMiter, 3.0},
                               std::pair{ClipperLib::jtSquare, 2.0}, std::pair{ClipperLib::jtRound, 2.0}}) {
      for (double d : {-1.0, -0.3, -0.2, -0.05, 0.05, 0.2, 0.3, 1.0}) {
        CAPTURE(r.loops.size());
        CAPTURE(int(join));
        CAPTURE(d);
        const clipper::Paths ours = clipper::offset(region, d, join, limit);
        const clipper::Paths theirs = clipper_offset(region, d, join, limit);
        CHECK(clipper::area_mm2(ours) == doctest::Approx(clipper::area_mm2(theirs)).epsilon(1e-6));
        CHECK(difference_area(ours, theirs) < 1e-4);
        CHECK(ours.size() == theirs.size());
      }
    }
  }
}

namespace {

// Clipper's raw offset of a CCW loop (nanometre grid) by d units, as ClipperOffset draws it
// before its union: each edge moved d along its outward normal, a mitre where the moved edges
// part, and where they cross, the end of the one, the vertex, the start of the other (a fold).
clipper::Path folded_offset(const clipper::Path& loop, double d) {
  const std::size_t n = loop.size();
  std::vector<Vec2> normal(n);
  for (std::size_t i = 0; i < n; ++i) {
    const auto& a = loop[i];
    const auto& b = loop[(i + 1) % n];
    const double dx = double(b.X - a.X), dy = double(b.Y - a.Y), l = std::hypot(dx, dy);
    normal[i] = {dy / l, -dx / l};
  }
  auto moved = [](const ClipperLib::IntPoint& p, double x, double y) {
    return ClipperLib::IntPoint{p.X + std::llround(x), p.Y + std::llround(y)};
  };
  clipper::Path raw;
  for (std::size_t v = 0; v < n; ++v) {
    const Vec2 a = normal[(v + n - 1) % n], b = normal[v];
    const double sin_turn = a.x * b.y - b.x * a.y, r = 1 + a.x * b.x + a.y * b.y;
    if (sin_turn * d < 0) {
      raw.push_back(moved(loop[v], a.x * d, a.y * d));
      raw.push_back(loop[v]);
      raw.push_back(moved(loop[v], b.x * d, b.y * d));
    } else {
      raw.push_back(moved(loop[v], (a.x + b.x) * d / r, (a.y + b.y) * d / r));
    }
  }
  return raw;
}

}  // namespace

// Loops with folds, the raw offsets of wavy loops grown and shrunk (a fold at every vertex
// the offset turns towards, where the moved edges cross): wherever union_of_folded_loop takes
// one, it is Clipper's union of it point for point, from the same start. Most of their folds
// nest or share edges, where cutting each fold off is not the union: it takes them by tracing
// the union's boundary, all but those whose union is more than one loop or whose crossings
// the sweep would place otherwise (105 of the 126; 6 by cutting folds alone).
TEST_CASE("union_of_folded_loop_is_clippers_union_of_the_loop") {
  int taken = 0;
  for (int waves = 3; waves <= 9; ++waves) {
    for (int n : {40, 90, 210}) {
      const Loop wavy = round_loop(0.37, -0.21, n, [&](double a) {
        return 10 + 1.5 * std::sin(waves * a + 0.3) + 0.3 * std::sin(3 * waves * a);
      });
      for (double d : {-0.9, -0.4, -0.15, 0.15, 0.4, 0.9}) {
        const clipper::Path raw = folded_offset(geometry::to_clipper(wavy), d * geometry::kClipperScale);
        clipper::Path ours;
        if (!clipper::union_of_folded_loop(raw, ours)) continue;
        ++taken;
        CAPTURE(waves);
        CAPTURE(n);
        CAPTURE(d);
        CHECK(clipper::Paths{ours} == clipper::union_positive({raw}));
      }
    }
  }
  CHECK(taken >= 100);
}

// The same on jagged loops (each vertex's radius drawn at random), whose raw offsets cross
// themselves in tangles of folds: wherever it takes one, Clipper's union point for point.
TEST_CASE("union_of_folded_loop_is_clippers_union_of_jagged_loops") {
  std::mt19937 random(7);
  std::uniform_real_distribution<double> jag(-1.5, 1.5);
  int taken = 0;
  for (int k = 0; k < 40; ++k) {
    std::vector<double> radius(60);
    for (double& r : radius) r = 10 + jag(random);
    const Loop jagged = round_loop(0.1 * k, -0.2, 60, [&](double a) {
      const auto i = static_cast<std::size_t>(std::lround(a / (2 * std::numbers::pi) * 60)) % 60;
      return radius[i];
    });
    for (double d : {-0.6, -0.25, 0.25, 0.6}) {
      const clipper::Path raw = folded_offset(geometry::to_clipper(jagged), d * geometry::kClipperScale);
      clipper::Path ours;
      if (!clipper::union_of_folded_loop(raw, ours)) continue;
      ++taken;
      CAPTURE(k);
      CAPTURE(d);
      CHECK(clipper::Paths{ours} == clipper::union_positive({raw}));
    }
  }
  CHECK(taken >= 40);
}

namespace {

// Clipper's islands of a region, as its union's tree gives them (the reference for the islands
// of loops apart, which are found without the union).
std::vector<clipper::Paths> swept_islands(const clipper::Paths& region) {
  clipper::PolyTree tree;
  return clipper::islands(clipper::union_nonzero_tree(region, tree));
}

// A loop of n points round (cx, cy), radii 1 +- spread / 2 mm at random, each point up to
// `jitter` of a step along; some points at the y of the one before, some repeated.
clipper::Path random_loop(std::mt19937& random, double cx, double cy, int n, double spread,
                          double jitter, double repeats) {
  std::uniform_real_distribution<double> unit(0, 1);
  clipper::Path loop;
  for (int i = 0; i < n; ++i) {
    const double a = 2 * std::numbers::pi * (i + jitter * unit(random)) / n;
    const double r = 1e6 * (1 + spread * (unit(random) - 0.5));
    ClipperLib::IntPoint p{std::llround(cx + r * std::cos(a)), std::llround(cy + r * std::sin(a))};
    if (i > 0 && unit(random) < 0.03) p.Y = loop.back().Y;     // a level edge
    if (i > 0 && unit(random) < repeats) p = loop.back();      // a point repeated
    loop.push_back(p);
  }
  return loop;
}

}  // namespace

// A diamond, CCW from its lowest point: the loop itself, started at the point after its
// lowest, as Clipper's union starts it; from any start, and only where the loop is simple.
TEST_CASE("islands_of_loops_apart_start_each_after_its_least_y") {
  const clipper::Path diamond{{0, -1000}, {1000, 0}, {0, 1000}, {-1000, 0}};
  const clipper::Path expected{{1000, 0}, {0, 1000}, {-1000, 0}, {0, -1000}};
  std::vector<clipper::Paths> ours;
  for (std::size_t start = 0; start < 4; ++start) {
    clipper::Path turned = diamond;
    std::rotate(turned.begin(), turned.begin() + static_cast<std::ptrdiff_t>(start), turned.end());
    REQUIRE(clipper::islands_of_loops_apart({turned}, ours));
    CHECK(ours == std::vector<clipper::Paths>{{expected}});
    CHECK(clipper::islands({turned}) == ours);
    CHECK(swept_islands({turned}) == ours);
  }
  // Two diamonds apart, the higher one first.
  clipper::Path low = diamond;
  for (auto& p : low) p.Y -= 5000;
  clipper::Path expected_low = expected;
  for (auto& p : expected_low) p.Y -= 5000;
  REQUIRE(clipper::islands_of_loops_apart({low, diamond}, ours));
  CHECK(ours == std::vector<clipper::Paths>{{expected}, {expected_low}});
  CHECK(swept_islands({low, diamond}) == ours);
  // Not taken: a CW loop; two points at the least y (a square's bottom edge); a point in line
  // with its neighbours; a bow tie (edges crossing); a point repeated (edges touching); one
  // diamond inside another; two loops with the same greatest y.
  const clipper::Path cw(diamond.rbegin(), diamond.rend());
  CHECK_FALSE(clipper::islands_of_loops_apart({cw}, ours));
  CHECK_FALSE(clipper::islands_of_loops_apart({{{0, 0}, {10, 0}, {10, 10}, {0, 10}}}, ours));
  CHECK_FALSE(clipper::islands_of_loops_apart({{{0, -10}, {5, -5}, {10, 0}, {0, 10}}}, ours));
  CHECK_FALSE(clipper::islands_of_loops_apart({{{0, -10}, {10, 10}, {0, 5}, {-10, 10}, {5, 0}}}, ours));
  CHECK_FALSE(clipper::islands_of_loops_apart(
      {{{0, -10}, {10, 0}, {0, 0}, {5, 5}, {0, 10}, {-5, 5}, {0, 0}, {-10, 0}}}, ours));
  clipper::Path small{{0, -100}, {100, 0}, {0, 100}, {-100, 0}};
  CHECK_FALSE(clipper::islands_of_loops_apart({diamond, small}, ours));
  clipper::Path beside = diamond;
  for (auto& p : beside) p.X += 5000;
  CHECK_FALSE(clipper::islands_of_loops_apart({diamond, beside}, ours));
}

// Random regions of one to six loops (each radii drawn at random round a centre, some with
// level edges or repeated points, some tangled so that edges cross), the loops apart, or
// overlapping, or one inside another: wherever the loops are taken as apart, the islands are
// Clipper's, point for point and in its order; and islands() is Clipper's on every region.
TEST_CASE("islands_of_loops_apart_are_clippers") {
  std::mt19937 random(11);
  std::uniform_real_distribution<double> unit(0, 1);
  int taken = 0, taken_several = 0;
  for (int k = 0; k < 600; ++k) {
    const int loops = 1 + k % 6;
    const bool tangled = k % 7 == 0;  // loops that cross themselves often
    const double apart = k % 5 == 0 ? 1.5e6 : 3e6;  // a fifth of them may overlap or nest
    clipper::Paths region;
    for (int l = 0; l < loops; ++l) {
      const int n = 3 + static_cast<int>(unit(random) * 80);
      region.push_back(random_loop(random, (l % 3) * apart + 5e5 * unit(random),
                                   (l / 3) * apart + 5e5 * unit(random), n, tangled ? 1.2 : 0.2,
                                   tangled ? 0.9 : 0.5, k % 11 == 1 ? 0.05 : 0));
    }
    CAPTURE(k);
    const std::vector<clipper::Paths> swept = swept_islands(region);
    std::vector<clipper::Paths> ours;
    if (clipper::islands_of_loops_apart(region, ours)) {
      ++taken;
      taken_several += loops > 1;
      CHECK(ours == swept);
    }
    CHECK(clipper::islands(region) == swept);
  }
  CHECK(taken >= 300);
  CHECK(taken_several >= 220);
}

TEST_CASE("clip_open_joined_cuts_a_closed_line_only_where_it_crosses_the_edge") {
  // A circle of r 6 about (12, 3), closed (last point = first) and begun inside a 20 mm square
  // at angles where Clipper hands one of its two pieces back reversed: joined, one piece, from
  // the circle's crossing with x = 10 to the other, 2 r acos(2 / 6) of arc long.
  const clipper::Paths square = geometry::to_clipper(
      Region{{Loop{{-10, -10}, {10, -10}, {10, 10}, {-10, 10}}}});
  for (const double begin : {2.1, 2.8, 3.5}) {
    Loop circle;
    for (int k = 0; k <= 32; ++k) {
      const double a = begin + 2 * std::numbers::pi * (k % 32) / 32;
      circle.push_back({12 + 6 * std::cos(a), 3 + 6 * std::sin(a)});
    }
    const clipper::Paths lines{geometry::to_clipper(circle)};
    INFO("begins at " << begin);
    CHECK(clipper::clip_open(lines, square).size() == 2);
    const clipper::Paths joined = clipper::clip_open_joined(lines, square);
    REQUIRE(joined.size() == 1);
    for (const auto& end : {joined[0].front(), joined[0].back()}) {
      CHECK(geometry::from_clipper(end).x == doctest::Approx(10).epsilon(1e-6));
    }
    double length = 0;
    for (std::size_t i = 1; i < joined[0].size(); ++i) {
      const Vec2 d = geometry::from_clipper(joined[0][i]) - geometry::from_clipper(joined[0][i - 1]);
      length += std::hypot(d.x, d.y);
    }
    // The 32-gon's chords fall short of the arc by about (pi / 32)^2 / 6 of it.
    CHECK(length == doctest::Approx(2 * 6 * std::acos(2.0 / 6)).epsilon(0.01));
  }
  // A closed line inside the region comes back whole.
  const clipper::Paths inside{geometry::to_clipper(Loop{{0, 0}, {1, 0}, {1, 1}, {0, 0}})};
  const clipper::Paths whole = clipper::clip_open_joined(inside, square);
  REQUIRE(whole.size() == 1);
  CHECK(whole[0].front() == whole[0].back());
}

TEST_CASE("proven_inside_holds_where_every_point_is_inside_clear_of_the_edges") {
  // A 20 mm square with a 2 mm square hole about (5, 5).
  const clipper::Paths outer = geometry::to_clipper(Region{{square(-10, -10, 10, 10), hole(4, 4, 6, 6)}});
  const auto inside = [&](const Region& inner) {
    return clipper::proven_inside(geometry::to_clipper(inner), outer);
  };
  CHECK(inside(Region{}));
  CHECK(inside(Region{{square(-6, -6, -4, -4)}}));
  // Round the hole, the hole inside its own: every point of it still in the square.
  CHECK(inside(Region{{square(2, 2, 8, 8), hole(3, 3, 7, 7)}}));
  CHECK_FALSE(inside(Region{{square(9, 0, 11, 1)}}));   // across the edge
  CHECK_FALSE(inside(Region{{square(8, 0, 10, 1)}}));   // along it
  CHECK_FALSE(inside(Region{{square(3, 3, 7, 7)}}));    // round the hole
  CHECK_FALSE(inside(Region{{square(4.5, 4.5, 5.5, 5.5)}}));  // in the hole
  CHECK_FALSE(inside(Region{{square(20, 20, 21, 21)}}));      // away from it
  CHECK_FALSE(inside(Region{{square(-6, -6, -4, -4), square(20, 20, 21, 21)}}));

  // Wavy loops about (-1, 1), 0.8 r to 1.2 r from it: inside the square and clear of the hole
  // where 1.2 r is under 5.83 mm (the hole's nearest corner, (4, 4)); round the hole or across
  // the square's edge where 0.8 r is over 8.60 (its farthest, (6, 6)). Where proven inside,
  // Clipper's difference is nothing.
  std::mt19937 random(7);
  std::uniform_real_distribution<double> size(0.5, 12), phase(0, 2 * std::numbers::pi);
  int proven = 0;
  for (int k = 0; k < 200; ++k) {
    const double r = size(random), p = phase(random);
    const Loop wavy = round_loop(-1, 1, 90, [&](double a) { return r * (1 + 0.2 * std::sin(5 * a + p)); });
    const clipper::Paths inner{geometry::to_clipper(wavy)};
    const bool holds = clipper::proven_inside(inner, outer);
    proven += holds;
    INFO("radius " << r);
    if (1.2 * r < 5.8) CHECK(holds);
    if (0.8 * r > 8.7) CHECK_FALSE(holds);
    if (holds) CHECK(clipper::difference(inner, outer).empty());
  }
  CHECK(proven >= 20);
}

// proven_specks on closed forms, and against the full difference on the shapes perimeters()
// takes it of: a region (the space a wall loop is laid in) and the bead of its loop (the
// region shrunk by w, grown back by w/2 mitred, straightened within 10 um and grown by
// w/2 + 10 um, square), whose difference is specks at the region's sharper corners.
TEST_CASE("proven_specks_holds_only_where_every_path_of_the_difference_is_under_the_area") {
  const clipper::Paths outer = geometry::to_clipper(Region{{square(-10, -10, 10, 10), hole(4, 4, 6, 6)}});
  const auto paths = [](const Region& r) { return geometry::to_clipper(r); };
  // Inside, clear of the edges: the difference is nothing, and the slivers of rounding it may
  // leave along the 8 mm of edge enclose at most 2 units x 8e6 units.
  const clipper::Paths inner = paths(Region{{square(-6, -6, -4, -4)}});
  CHECK(clipper::proven_specks(inner, outer, 1.7e7));
  CHECK_FALSE(clipper::proven_specks(inner, outer, 1.5e7));
  CHECK(clipper::proven_specks({}, outer, 1));
  // Across the edge x = 10: the difference is the square [10, 11] x [0, 1], 1e12 units^2.
  const clipper::Paths across = paths(Region{{square(9, 0, 11, 1)}});
  CHECK(clipper::proven_specks(across, outer, 1.1e12));
  CHECK_FALSE(clipper::proven_specks(across, outer, 1e12));
  CHECK_FALSE(clipper::proven_specks(paths(Region{{square(3, 3, 7, 7)}}), outer, 1e20));   // round the hole
  // The square [0, 10]^2 in a square 0.1 mm larger all round with its corners (10.1, 10.1)
  // and (-0.1, -0.1) cut off along x + y = 19.9 and x + y = 0.1: the difference is two
  // triangles of legs 0.1 mm (5e9 units^2 each), apart.
  const clipper::Paths ten = paths(Region{{square(0, 0, 10, 10)}});
  const clipper::Paths cut_corners{geometry::to_clipper(
      Loop{{0.2, -0.1}, {10.1, -0.1}, {10.1, 9.8}, {9.8, 10.1}, {-0.1, 10.1}, {-0.1, 0.2}})};
  const clipper::Paths corners = clipper::difference(ten, cut_corners);
  REQUIRE(corners.size() == 2);
  for (const clipper::Path& path : corners) CHECK(std::abs(ClipperLib::Area(path)) == doctest::Approx(5e9).epsilon(1e-3));
  CHECK(clipper::proven_specks(ten, cut_corners, 6e9));   // each under 6e9, both together not
  CHECK_FALSE(clipper::proven_specks(ten, cut_corners, 4.9e9));
  // One corner cut off deeper (legs 5 mm): the gap is worth a wall.
  const clipper::Paths deep{geometry::to_clipper(
      Loop{{-0.1, -0.1}, {10.1, -0.1}, {10.1, 5}, {5, 10.1}, {-0.1, 10.1}})};
  CHECK_FALSE(clipper::proven_specks(ten, deep, 1e10));

  // Wavy regions, some with lobes sharp enough to leave a gap worth a wall.
  const double w = 0.45;
  const double min_gap = w * w / 16 * geometry::kClipperScale * geometry::kClipperScale;
  std::mt19937 random(13);
  std::uniform_real_distribution<double> size(1, 8), phase(0, 2 * std::numbers::pi), depth(0, 0.6);
  std::uniform_int_distribution<int> lobes(2, 9);
  int proven = 0, kept = 0, specks_proven = 0;  // 132, 18 and 16 at the seed
  for (int k = 0; k < 150; ++k) {
    const double r = size(random), p = phase(random), d = depth(random);
    const int n = lobes(random);
    const Loop wavy = round_loop(0, 0, 240, [&](double a) { return r * (1 + d * std::sin(n * a + p)); });
    const clipper::Paths inside{geometry::to_clipper(wavy)};
    const clipper::Paths loops = clipper::offset(clipper::offset(inside, -w), w / 2, ClipperLib::jtMiter, 2.0);
    const clipper::Paths bead =
        clipper::offset(clipper::simplified(loops, 0.01), w / 2 + 0.01, ClipperLib::jtSquare);
    const clipper::Paths gap = clipper::difference(inside, bead);
    const bool holds = clipper::proven_specks(inside, bead, min_gap);
    proven += holds;
    const bool specks = std::all_of(gap.begin(), gap.end(), [&](const clipper::Path& path) {
      return std::abs(ClipperLib::Area(path)) < min_gap;
    });
    kept += !specks;
    specks_proven += holds && !gap.empty();
    INFO("radius " << r << ", lobes " << n << ", depth " << d);
    if (holds) CHECK(specks);
  }
  CHECK(proven >= 20);
  CHECK(specks_proven >= 10);  // proven where the difference is not nothing
  CHECK(kept >= 10);
}

// A 20 mm square with a 2 mm square hole about (5, 5); lines are closed loops, as the core's
// loops are clipped (last point = first).
TEST_CASE("proven_outside_holds_where_every_point_of_the_lines_is_outside_clear_of_the_edges") {
  const clipper::Paths region = geometry::to_clipper(Region{{square(-10, -10, 10, 10), hole(4, 4, 6, 6)}});
  const auto closed = [](const Loop& loop) {
    clipper::Path path = geometry::to_clipper(loop);
    path.push_back(path.front());
    return path;
  };
  const auto outside = [&](const clipper::Paths& lines) {
    const bool holds = clipper::proven_outside(lines, region);
    // Where proven, Clipper's clip of the lines is nothing.
    if (holds) CHECK(clipper::clip_open(lines, region).empty());
    return holds;
  };
  CHECK(outside({}));
  CHECK(clipper::proven_outside({closed(square(0, 0, 1, 1))}, {}));
  CHECK(outside({closed(square(-12, -12, 12, 12))}));           // round the square
  CHECK(outside({closed(square(4.5, 4.5, 5.5, 5.5))}));         // in the hole
  CHECK(outside({closed(square(20, 20, 21, 21)), closed(square(-12, -12, 12, 12))}));
  CHECK(outside({clipper::Path{geometry::to_clipper(Vec2{-11, 0}), geometry::to_clipper(Vec2{-11, 5})}}));
  CHECK_FALSE(outside({closed(square(-6, -6, -4, -4))}));       // inside
  CHECK_FALSE(outside({closed(square(3, 3, 7, 7))}));           // round the hole, inside
  CHECK_FALSE(outside({closed(square(9, 0, 11, 1))}));          // across the edge
  CHECK_FALSE(outside({closed(square(10, 0, 11, 1))}));         // along it, outside
  CHECK_FALSE(outside({closed(square(4, 4.5, 5, 5.5))}));       // along the hole's edge
  CHECK_FALSE(outside({closed(square(20, 20, 21, 21)), closed(square(-1, -1, 1, 1))}));
  // A line that leaves the square and comes back only by its closing edge.
  CHECK_FALSE(outside({clipper::Path{geometry::to_clipper(Vec2{-11, 0}), geometry::to_clipper(Vec2{-11, 5}),
                                     geometry::to_clipper(Vec2{0, 5})}}));

  // Wavy loops about (-1, 1), 0.8 r to 1.2 r from it: round the whole square where 0.8 r is
  // over 15.56 mm (its farthest corner, (10, -10)); inside it, or across the hole's edges
  // (5.83 mm away at the nearest), where 1.2 r is under 9 (its nearest sides).
  std::mt19937 random(11);
  std::uniform_real_distribution<double> size(0.5, 30), phase(0, 2 * std::numbers::pi);
  int proven = 0;
  for (int k = 0; k < 200; ++k) {
    const double r = size(random), p = phase(random);
    const Loop wavy = round_loop(-1, 1, 90, [&](double a) { return r * (1 + 0.2 * std::sin(5 * a + p)); });
    const bool holds = outside({closed(wavy)});
    proven += holds;
    INFO("radius " << r);
    if (0.8 * r > 15.7) CHECK(holds);
    if (1.2 * r < 9) CHECK_FALSE(holds);
  }
  CHECK(proven >= 20);
}

// offset_is_empty against offset(...).empty() and the closed form, on regions a shrink empties
// in part or whole. Each `expect` is the closed form; both functions must agree with it.
TEST_CASE("offset_is_empty_is_whether_the_offset_is_empty") {
  const auto rect = [](double x0, double y0, double x1, double y1) {
    return Loop{{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}};
  };
  const auto check = [](const Region& r, double d, bool expect,
                        ClipperLib::JoinType join = ClipperLib::jtMiter) {
    CAPTURE(d);
    CAPTURE(int(join));
    const clipper::Paths region = geometry::to_clipper(r);
    CHECK(clipper::offset(region, d, join).empty() == expect);
    CHECK(clipper::offset_is_empty(region, d, join) == expect);
  };

  SUBCASE("a square of side s shrunk by d is empty where d >= s / 2") {
    const Region square{{rect(0, 0, 10, 10)}};
    for (double d : {-1.0, -4.9, 1.0}) check(square, d, false);
    for (double d : {-5.1, -6.0}) check(square, d, true);
    CHECK(clipper::offset_is_empty({}, -1));
    CHECK_FALSE(clipper::offset_is_empty(geometry::to_clipper(square), 0));
  }

  SUBCASE("an annulus of width w shrunk by d is empty where 2 d > w") {
    // Outer loop of circumradius 10, hole of circumradius 5 (720-gons: the width is 5 to
    // within 2e-4 mm). The outer loop's centroid lies in the hole.
    Loop hole = round_loop(0, 0, 720, [](double) { return 5.0; });
    std::reverse(hole.begin(), hole.end());
    const Region annulus{{round_loop(0, 0, 720, [](double) { return 10.0; }), hole}};
    for (double d : {-0.5, -2.4, 0.5}) check(annulus, d, false);
    // The shrunk outer loop (radius 7.4) and grown hole (7.6) pass each other without
    // crossing: between them the raw loops wind -1, nowhere once or more.
    for (double d : {-2.6, -4.0}) check(annulus, d, true);
  }

  SUBCASE("an L of width 1 whose arms vanish but whose corner stays") {
    // Arms 10 mm long, 1 mm wide, meeting at the origin; the reflex vertex at (1, 1). Round
    // joins: the shrink keeps the points at d or more from the boundary; the largest disc in
    // the corner touches both outer sides and the reflex vertex, radius sqrt2 / (1 + sqrt2) =
    // 0.586, so the arms (half width 0.5) vanish first. The L's centroid (2.9, 2.9) is outside it.
    const Region l{{Loop{{0, 0}, {10, 0}, {10, 1}, {1, 1}, {1, 10}, {0, 10}}}};
    check(l, -0.45, false, ClipperLib::jtRound);
    check(l, -0.55, false, ClipperLib::jtRound);
    check(l, -0.6, true, ClipperLib::jtRound);
    // Mitred, the reflex vertex is a square corner: the L of width 1 - 2 d, empty past 0.5.
    check(l, -0.45, false);
    check(l, -0.55, true);
    // A 3 mm corner block with arms 1 mm wide, shrunk by 0.75 mm (split_narrow's bead
    // fraction at 1 mm): the arms vanish, the block's 1.5 mm square stays; past 1.5 it goes.
    const Region block{{Loop{{0, 0}, {13, 0}, {13, 1}, {3, 1}, {3, 3}, {1, 3}, {1, 13}, {0, 13}}}};
    check(block, -0.75, false);
    check(block, -1.6, true);
  }

  SUBCASE("two disjoint squares of which one vanishes") {
    // The small one first, so its centroid is the first point tried. Axis-aligned, a 1 mm
    // square is left out of the offset as narrower than 2 d; turned 45 degrees (1.5 mm side,
    // 2.12 mm across), it is kept and its raw loop turns over (the square of side 2 d - 1.5,
    // winding -1 at its centroid).
    const Loop turned{{21, -1.06066}, {22.06066, 0}, {21, 1.06066}, {19.93934, 0}};
    for (const Loop& small : {rect(20, 0, 21, 1), turned}) {
      const Region two{{small, rect(0, 0, 10, 10)}};
      check(two, -0.3, false);
      check(two, -1, false);
      check(two, -4.9, false);
      check(two, -5.1, true);
    }
  }

  SUBCASE("raw loops that wind, with an empty union") {
    // A square turned 45 degrees, side 3, shrunk by 2: every edge moves past the opposite
    // one's, and Clipper's raw loop (folded_offset) is turned over, of negative area: it
    // winds -1 round the centre and the union with the positive rule is empty.
    const Loop turned{{0, -2.12132}, {2.12132, 0}, {0, 2.12132}, {-2.12132, 0}};
    const clipper::Path loop = geometry::to_clipper(Region{{turned}})[0];
    CHECK(ClipperLib::Area(folded_offset(loop, -2 * geometry::kClipperScale)) < 0);
    check(Region{{turned}}, -2, true);
    check(Region{{turned}}, -1.4, false);
  }
}

}  // namespace clipper_test
