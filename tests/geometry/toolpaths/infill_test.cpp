// infill: line spacing from the density, angles, the fixed grid, solid fill.
#include "geometry/toolpaths/infill.h"

#include <doctest/doctest.h>

#include <cmath>
#include <numbers>

#include "geometry/toolpaths/bead_coverage.h"
#include "geometry/toolpaths/toolpath_shapes.h"

namespace infill_test {

using namespace geometry;
using namespace toolpath_shapes;

namespace {

constexpr double w = 0.45;

// Direction of a line in degrees, in [0, 180).
double direction(const ExtrusionPath& line) {
  const Vec2 d = line.points.back() - line.points.front();
  double a = std::atan2(d.y, d.x) * 180 / std::numbers::pi;
  if (a < 0) a += 180;
  if (a >= 180 - 1e-9) a -= 180;
  return a;
}

// Distance of a line from the origin, measured across lines of direction `angle`.
double offset_across(const ExtrusionPath& line, double angle) {
  const double a = angle * std::numbers::pi / 180;
  const Vec2 p = line.points.front();
  return -p.x * std::sin(a) + p.y * std::cos(a);
}

}  // namespace

TEST_CASE("sparse_line_length_is_area_times_density_over_width") {
  // Lines d/100/w per mm across the area: length = area d / (100 w), give or take one line
  // (the grid is fixed, so the area may hold one line more or less than the ratio).
  const Region disc{{circle({0, 0}, 30, 720)}};
  const double a = area(disc), longest = 60;
  for (InfillPattern pattern : {InfillPattern::rectilinear, InfillPattern::grid}) {
    for (double density : {10.0, 20.0, 50.0}) {
      CAPTURE(density);
      const auto lines = sparse_infill(disc, w, density, pattern, 45, 0, InfillLines::separate);
      const double expected = a * density / 100 / w;
      CHECK(std::abs(length(lines) - expected) <= (pattern == InfillPattern::grid ? 2 : 1) * longest);
      for (const auto& l : lines) CHECK(l.role == PathRole::sparse_infill);
    }
  }
}

TEST_CASE("rectilinear_turns_90_degrees_every_layer") {
  const Region square{{rectangle(0, 0, 20, 20)}};
  for (std::size_t layer : {0u, 1u, 2u, 3u}) {
    const auto lines = sparse_infill(square, w, 20, InfillPattern::rectilinear, 30, layer,
                                     InfillLines::separate);
    REQUIRE(!lines.empty());
    for (const auto& l : lines) {
      CHECK(direction(l) == doctest::Approx(layer % 2 ? 120 : 30).epsilon(1e-6));
    }
  }
}

TEST_CASE("grid_lays_both_directions_every_layer") {
  const Region square{{rectangle(0, 0, 20, 20)}};
  const auto lines = sparse_infill(square, w, 20, InfillPattern::grid, 45, 1, InfillLines::separate);
  int along = 0, across = 0;
  for (const auto& l : lines) {
    const double d = direction(l);
    if (std::abs(d - 45) < 1e-6) ++along;
    else if (std::abs(d - 135) < 1e-6) ++across;
  }
  CHECK(along > 0);
  CHECK(across > 0);
  CHECK(along + across == static_cast<int>(lines.size()));
}

TEST_CASE("sparse_lines_lie_on_a_grid_fixed_in_the_part_so_layers_stack") {
  // Every line is a whole number of spacings from the origin; the same area two layers up
  // gets the very same lines.
  const Region blob{{circle({7, 3}, 12, 90)}};
  const double spacing = w * 100 / 25;
  const auto lines = sparse_infill(blob, w, 25, InfillPattern::rectilinear, 0, 0);
  REQUIRE(!lines.empty());
  for (const auto& l : lines) {
    const double k = offset_across(l, 0) / spacing;
    CHECK(k == doctest::Approx(std::round(k)).epsilon(1e-6));
  }
  const auto again = sparse_infill(blob, w, 25, InfillPattern::rectilinear, 0, 2);
  REQUIRE(again.size() == lines.size());
  for (std::size_t i = 0; i < lines.size(); ++i) {
    CHECK(again[i].points.front() == lines[i].points.front());
    CHECK(again[i].points.back() == lines[i].points.back());
  }
}

TEST_CASE("solid_infill_spans_a_rectangle_with_whole_lines_edge_to_edge") {
  // A 10 x 2.25 mm area is exactly 5 beads tall: 5 lines at y = 0.225 + 0.45 k, end to end.
  const Region strip{{rectangle(0, 0, 10, 2.25)}};
  const auto lines = solid_infill(strip, w, 0, 0, PathRole::top_skin, InfillLines::separate);
  REQUIRE(lines.size() == 5);
  for (std::size_t k = 0; k < 5; ++k) {
    CHECK(lines[k].role == PathRole::top_skin);
    CHECK(lines[k].width == doctest::Approx(w).epsilon(1e-9));
    CHECK(lines[k].points.front().y == doctest::Approx(0.225 + 0.45 * k).epsilon(1e-9));
    CHECK(length(lines[k].points) == doctest::Approx(10).epsilon(1e-9));
  }
  // Odd layers run across: 10 / 0.45 = 22.2 -> 22 lines 10/22 mm apart and as wide, each
  // 2.25 long.
  const auto across = solid_infill(strip, w, 0, 1, PathRole::solid_infill, InfillLines::separate);
  REQUIRE(across.size() == 22);
  for (const auto& l : across) {
    CHECK(length(l.points) == doctest::Approx(2.25).epsilon(1e-9));
    CHECK(l.width == doctest::Approx(10.0 / 22).epsilon(1e-9));
  }
}

TEST_CASE("connected_solid_infill_is_one_zigzag_that_fills_a_rectangle") {
  // The same 5 lines, now half a bead in from the ends (x = 0.225 .. 9.775) and joined by
  // 0.45 mm connectors up alternate ends; the free ends reach the edge. Length: area / w
  // (a micrometre more per joined end: solid lines keep that much closer to the edge). The
  // beads fill the rectangle but for the notches a round bead leaves at the outside of each
  // turn, (1 - pi/4) (w/2)^2 each, too small to fill: 4 at each end of the rectangle (two
  // turns there, whose notches next to each other merge; the free ends fill their corners).
  const Region strip{{rectangle(0, 0, 10, 2.25)}};
  const auto paths = solid_infill(strip, w, 0, 0, PathRole::top_skin);
  REQUIRE(paths.size() == 1);
  const auto& p = paths[0].points;
  REQUIRE(p.size() == 10);
  CHECK(p.front().x == doctest::Approx(0).epsilon(1e-9));
  CHECK(p.back().x == doctest::Approx(10).epsilon(1e-9));
  for (std::size_t k = 0; k < 5; ++k) {
    CHECK(p[2 * k].y == doctest::Approx(0.225 + 0.45 * k).epsilon(1e-9));
    CHECK(p[2 * k + 1].y == doctest::Approx(0.225 + 0.45 * k).epsilon(1e-9));
  }
  CHECK(length(p) == doctest::Approx(22.5 / w + 8 * 0.001).epsilon(1e-9));
  const auto c = bead_coverage::coverage(strip, paths);
  const double notch = (1 - std::numbers::pi / 4) * (w / 2) * (w / 2) / 22.5;
  CHECK(c.inside == doctest::Approx(1 - 8 * notch).epsilon(2e-4));
  CHECK(c.double_coverage <= 1e-3);
}

TEST_CASE("solid_infill_fills_the_strip_an_edge_between_lines_leaves") {
  // An L: 10 x 2.3 with a 3 x 3 block on its left end. Lines span the 3 mm height 3/7 mm
  // apart; the step edge at y = 2.3 falls between the lines at 1.93 and 2.36, leaving a strip
  // about 0.16 mm wide and 7 mm long that only a centre line fills.
  const Region l_shape{{Loop{{0, 0}, {10, 0}, {10, 2.3}, {3, 2.3}, {3, 3}, {0, 3}}}};
  const auto lines = solid_infill(l_shape, w, 0, 0, PathRole::top_skin);
  int along_the_step = 0;
  for (const auto& p : lines) {
    CHECK(p.role == PathRole::top_skin);
    along_the_step += p.points.front().y > 2.14 && p.points.front().y < 2.3 &&
                      std::abs(p.points.front().x - p.points.back().x) > 5;
  }
  CHECK(along_the_step == 1);
  const auto c = bead_coverage::coverage(l_shape, lines);
  INFO("inside " << c.inside << " outside " << c.outside);
  CHECK(c.inside >= 0.98);  // (the round ends stick out of the area: in a plan, into walls)
  for (const auto& p : lines) {
    for (Vec2 v : p.points) CHECK(ClipperLib::PointInPolygon(to_clipper(v), to_clipper(l_shape.loops[0])) != 0);
  }
}

TEST_CASE("solid_pieces_of_different_roles_share_one_set_of_lines") {
  // A 10 x 4.5 mm area, its left half top skin and its right half solid infill, lines
  // along X: the 10 lines run across both halves and are cut at x = 5, each half taking its
  // role. Where the halves meet, the beads meet end to end: no gap and no overlap there.
  const Region left{{rectangle(0, 0, 5, 4.5)}}, right{{rectangle(5, 0, 10, 4.5)}};
  const auto paths = solid_infill({{left, PathRole::top_skin}, {right, PathRole::solid_infill}},
                                  w, 0, 0, InfillLines::separate);
  REQUIRE(paths.size() == 20);
  for (const auto& p : paths) {
    const double x = 0.5 * (p.points.front().x + p.points.back().x);
    CHECK(p.role == (x < 5 ? PathRole::top_skin : PathRole::solid_infill));
    CHECK(length(p.points) == doctest::Approx(5).epsilon(1e-6));
  }
  const Region whole{{rectangle(0, 0, 10, 4.5)}};
  const auto connected =
      solid_infill({{left, PathRole::top_skin}, {right, PathRole::solid_infill}}, w, 0, 0);
  const auto c = bead_coverage::coverage(whole, connected);
  INFO("inside " << c.inside << " double " << c.double_coverage);
  CHECK(c.inside >= 0.995);
  CHECK(c.double_coverage <= 0.005);
  for (const auto& p : connected) {
    for (Vec2 v : p.points) {
      const bool left_side = v.x < 5 - 1e-6, right_side = v.x > 5 + 1e-6;
      if (p.role == PathRole::top_skin) CHECK(!right_side);
      if (p.role == PathRole::solid_infill) CHECK(!left_side);
    }
  }
}

TEST_CASE("a_solid_ring_narrower_than_one_and_a_half_beads_is_one_path_along_it") {
  // The ring of skin a receding top leaves inside its walls: 0.6 mm wide (r 7 to 7.6). Lines
  // across it would be dashes under a millimetre long; it gets one closed path along r 7.3,
  // as wide as the ring, which crosses whatever lines lie below it.
  const Region ring{{circle({0, 0}, 7.6, 192), reversed(circle({0, 0}, 7, 192))}};
  const auto paths = solid_infill(ring, w, 45, 0, PathRole::solid_infill);
  REQUIRE(paths.size() == 1);
  CHECK(is_closed(paths[0]));
  CHECK(paths[0].role == PathRole::solid_infill);
  CHECK(paths[0].width == doctest::Approx(0.6).epsilon(0.02));
  for (Vec2 v : paths[0].points) CHECK(std::hypot(v.x, v.y) == doctest::Approx(7.3).epsilon(0.002));
  // One a bead wider (1.05 mm) is crossed by lines as any other area.
  const Region wide{{circle({0, 0}, 8.05, 192), reversed(circle({0, 0}, 7, 192))}};
  const auto across = solid_infill(wide, w, 45, 0, PathRole::top_skin);
  CHECK(across.size() > 1);
  const auto c = bead_coverage::coverage(wide, across);
  CHECK(c.inside >= 0.95);
}

TEST_CASE("internal_solid_infill_leaves_out_the_dabs_shorter_than_a_bead_that_skins_keep") {
  // The 1.05 mm ring crossed at 45 degrees: the zig-zag's turns leave notches that gap fill
  // fills with dabs shorter than a bead. A skin (seen from outside) keeps them; solid infill
  // inside the part, which nothing sees and which holds nothing up (and whose lowest layer
  // rests on sparse lines, between which a dab hangs), leaves them out.
  const Region ring{{circle({0, 0}, 8.05, 192), reversed(circle({0, 0}, 7, 192))}};
  auto dabs = [](const std::vector<ExtrusionPath>& paths) {
    int count = 0;
    for (const auto& p : paths) count += length(p.points) < w;
    return count;
  };
  const auto skin = solid_infill(ring, w, 45, 0, PathRole::top_skin);
  const auto inside = solid_infill(ring, w, 45, 0, PathRole::solid_infill);
  CHECK(dabs(skin) > 10);
  CHECK(dabs(inside) == 0);
  CHECK(skin.size() - inside.size() == static_cast<std::size_t>(dabs(skin)));
  const double skin_cover = bead_coverage::coverage(ring, skin).inside;
  const double inside_cover = bead_coverage::coverage(ring, inside).inside;
  INFO("skin " << skin_cover << " solid infill " << inside_cover);
  CHECK(inside_cover < skin_cover);
  CHECK(inside_cover >= 0.9);
}

TEST_CASE("a_line_under_a_skin_edge_follows_it_and_starts_on_a_sparse_line_below") {
  // The layer above is solid outside a disc of r 8 (its sparse core) over this layer's sparse
  // area, a 40 mm square: one loop along r 8, cut open where it crosses a line of the layer
  // below (a grid at 45 and 135 degrees through the origin, 4.5 mm apart at 20%), ending half
  // a bead before it.
  const Region square{{rectangle(-20, -20, 20, 20)}};
  const Region core{{circle({0, 0}, 8, 192)}};
  const auto lines = skin_edge_lines(square, core, w, 20, InfillPattern::grid, 45, 1);
  REQUIRE(lines.size() == 1);
  const ExtrusionPath& loop = lines[0];
  CHECK(loop.role == PathRole::sparse_infill);
  CHECK(loop.width == w);
  for (Vec2 v : loop.points) CHECK(std::hypot(v.x, v.y) == doctest::Approx(8).epsilon(1e-3));
  CHECK(length(loop.points.front() - loop.points.back()) == doctest::Approx(w / 2).epsilon(0.02));
  CHECK(length(loop.points) == doctest::Approx(2 * std::numbers::pi * 8 - w / 2).epsilon(2e-3));
  const double on_45 = offset_across(loop, 45) / 4.5, on_135 = offset_across(loop, 135) / 4.5;
  CHECK(std::min(std::abs(on_45 - std::round(on_45)), std::abs(on_135 - std::round(on_135))) <
        1e-6);
  // Where the core covers all of the area there is no edge to hold up.
  const Region all_sparse{{rectangle(-30, -30, 30, 30)}};
  CHECK(skin_edge_lines(square, all_sparse, w, 20, InfillPattern::grid, 45, 1).empty());
}

TEST_CASE("a_line_under_a_skin_edge_runs_along_the_area_edge_only_a_line_spacing_below") {
  // The core's right side, x = 9.9, runs 0.1 mm inside the area's edge (x = 10) for 10 mm:
  // along the edge the line goes on only 4.5 mm (a spacing of the grid below) from either
  // corner, far enough to reach the lines below where they end; the middle would double the
  // wall.
  const Region square{{rectangle(-10, -10, 10, 10)}};
  const Region core{{rectangle(-5, -5, 9.9, 5)}};
  const auto lines = skin_edge_lines(square, core, w, 20, InfillPattern::grid, 45, 1);
  REQUIRE(lines.size() == 1);
  const auto& p = lines[0].points;
  CHECK(length(p.front() - p.back()) > 0.5);
  CHECK(p.front().x == doctest::Approx(9.9));
  CHECK(p.back().x == doctest::Approx(9.9));
  for (Vec2 v : p) CHECK(!(v.x > 9.8 && std::abs(v.y) < 0.3));
  const double full = 2 * (14.9 + 10);
  INFO("length " << length(p));
  CHECK(length(p) > full - 10 + 2 * 4.0);
  CHECK(length(p) < full - 10 + 2 * 4.6);
}

TEST_CASE("a_line_under_a_skin_edge_is_not_cut_where_the_edge_loop_begins") {
  // The core's edge, a circle of r 6 about (12, 3), leaves the area (a 20 mm square) across
  // x = 10; its loop begins inside the area. Clipped, the loop comes back in two pieces that
  // meet where it begins, one of them reversed for these beginnings (Clipper's open paths
  // keep no direction). They are one line: none ends there, in the middle of the sparse area,
  // where an end would hang between the lines below.
  const Region square{{rectangle(-10, -10, 10, 10)}};
  for (const double begin : {2.1, 2.8, 3.5}) {
    Loop edge;
    for (int k = 0; k < 32; ++k) {
      const double a = begin + 2 * std::numbers::pi * k / 32;
      edge.push_back({12 + 6 * std::cos(a), 3 + 6 * std::sin(a)});
    }
    const auto lines = skin_edge_lines(square, Region{{edge}}, w, 20, InfillPattern::grid, 45, 1);
    REQUIRE(!lines.empty());
    for (const ExtrusionPath& line : lines) {
      for (Vec2 end : {line.points.front(), line.points.back()}) {
        INFO("begins at " << begin << ", a line ends at " << end.x << ", " << end.y);
        CHECK(length(end - edge.front()) > 1);
      }
    }
  }
}

TEST_CASE("solid_infill_length_is_area_over_width") {
  const Region disc{{circle({0, 0}, 10, 360)}};
  const auto lines = solid_infill(disc, w, 45, 0, PathRole::bottom_skin);
  CHECK(length(lines) == doctest::Approx(area(disc) / w).epsilon(0.02));
}

TEST_CASE("infill_lines_stay_inside_a_holed_area") {
  const Region holed{{rectangle(0, 0, 20, 20), reversed(rectangle(5, 5, 15, 15))}};
  for (InfillLines mode : {InfillLines::separate, InfillLines::connected}) {
    for (const auto& l : sparse_infill(holed, w, 40, InfillPattern::grid, 45, 0, mode)) {
      for (std::size_t i = 0; i + 1 < l.points.size(); ++i) {
        const Vec2 mid = 0.5 * (l.points[i] + l.points[i + 1]);
        CHECK(!(mid.x > 5 + 1e-6 && mid.x < 15 - 1e-6 && mid.y > 5 + 1e-6 && mid.y < 15 - 1e-6));
      }
      for (Vec2 p : l.points) {
        CHECK(p.x >= -1e-6);
        CHECK(p.x <= 20 + 1e-6);
      }
    }
  }
}

TEST_CASE("connected_sparse_lines_zigzag_inside_half_a_bead_from_the_edge") {
  // 20 mm square, 20% rectilinear along X: lines 2.25 mm apart on the fixed grid, at y =
  // 2.25 ... 18 (8 lines), running between x = w/2 and 20 - w/2, joined by 2.25 mm pieces of
  // the shrunk square's sides; the two free ends reach on to the square's edge.
  const Region square{{rectangle(0, 0, 20, 20)}};
  const auto paths = sparse_infill(square, w, 20, InfillPattern::rectilinear, 0, 0);
  REQUIRE(paths.size() == 1);
  const auto& p = paths[0].points;
  REQUIRE(p.size() == 16);
  for (std::size_t k = 0; k < 8; ++k) {
    CAPTURE(k);
    const double y = 2.25 * static_cast<double>(k + 1);
    CHECK(p[2 * k].y == doctest::Approx(y).epsilon(1e-9));
    CHECK(p[2 * k + 1].y == doctest::Approx(y).epsilon(1e-9));
    const bool rightwards = k % 2 == 0;
    const double start = rightwards ? w / 2 : 20 - w / 2;
    if (k > 0) CHECK(p[2 * k].x == doctest::Approx(start).epsilon(1e-9));
    if (k < 7) CHECK(p[2 * k + 1].x == doctest::Approx(20 - start).epsilon(1e-9));
  }
  CHECK(p.front().x == doctest::Approx(0).epsilon(1e-9));
  CHECK(p.back().x == doctest::Approx(0).epsilon(1e-9));
  CHECK(length(p) == doctest::Approx(8 * (20 - w) + 7 * 2.25 + w).epsilon(1e-9));
}

TEST_CASE("no_area_or_no_density_gives_no_lines") {
  CHECK(sparse_infill(Region{}, w, 20, InfillPattern::grid, 45, 0).empty());
  CHECK(sparse_infill(Region{{rectangle(0, 0, 5, 5)}}, w, 0, InfillPattern::grid, 45, 0).empty());
  CHECK(solid_infill(Region{}, w, 45, 0, PathRole::top_skin).empty());
  CHECK(hatch(Region{{rectangle(0, 0, 5, 5)}}, 0, 0, PathRole::top_skin, w).empty());
}

TEST_CASE("infill_pattern_names_round_trip") {
  for (InfillPattern p : {InfillPattern::rectilinear, InfillPattern::grid}) {
    CHECK(parse_infill_pattern(infill_pattern_name(p)) == p);
  }
  CHECK(!parse_infill_pattern("honeycomb"));
}

}  // namespace infill_test
