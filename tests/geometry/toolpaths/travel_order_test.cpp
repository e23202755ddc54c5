// travel_order: seams, nearest-first order, path direction, retractions.
#include "geometry/toolpaths/travel_order.h"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>

#include "geometry/toolpaths/toolpath_shapes.h"

namespace travel_order_test {

using namespace geometry;
using namespace toolpath_shapes;

namespace {

ExtrusionPath closed_path(Loop loop) {
  ExtrusionPath p;
  p.points = loop;
  p.points.push_back(loop.front());
  p.width = 0.45;
  return p;
}

ExtrusionPath line(Vec2 a, Vec2 b) {
  ExtrusionPath p;
  p.role = PathRole::sparse_infill;
  p.points = {a, b};
  p.width = 0.45;
  return p;
}

}  // namespace

TEST_CASE("aligned_seam_takes_the_rear_left_corner_of_a_square") {
  const auto square = closed_path(rectangle(0, 0, 20, 20));
  const std::size_t i = aligned_seam(square.points);
  CHECK(square.points[i] == Vec2{0, 20});
}

TEST_CASE("aligned_seam_hides_in_a_concave_rear_corner") {
  // A V-notch 0.4 mm deep in the back wall (a 43.6 degree concave turn) takes the seam from
  // the convex rear corners.
  const Loop notch{{0, 0}, {20, 0}, {20, 20}, {11, 20}, {10, 19.6}, {9, 20}, {0, 20}};
  const auto notched = closed_path(notch);
  CHECK(notched.points[aligned_seam(notched.points)] == Vec2{10, 19.6});
  // A U open at the back: its concave corners lie deep inside (y = 5), out of the rear band;
  // the rear corners are all convex and equal, so the leftmost wins.
  const Loop u{{0, 0}, {20, 0}, {20, 20}, {15, 20}, {15, 5}, {5, 5}, {5, 20}, {0, 20}};
  const auto path = closed_path(u);
  CHECK(path.points[aligned_seam(path.points)] == Vec2{0, 20});
}

TEST_CASE("aligned_seam_stays_put_on_similar_loops_of_consecutive_layers") {
  const auto a = closed_path(circle({0, 0}, 10, 90));
  const auto b = closed_path(circle({0.01, 0}, 10.02, 90));
  CHECK(aligned_seam(a.points) == aligned_seam(b.points));
}

namespace {

// A 20 x 10 rectangle whose back edge rises by `tilt` mm to the right (falls if negative):
// the rear corner on the higher side is the sharper one.
ExtrusionPath tilted_box(double tilt) {
  return closed_path(Loop{{0, 0}, {20, 0}, {20, 10 + std::max(tilt, 0.0)},
                          {0, 10 + std::max(-tilt, 0.0)}});
}

}  // namespace

TEST_CASE("remembered_seam_stays_where_the_layer_below_had_it") {
  // The per-layer rule picks the sharper rear corner, which flips sides with the tilt; with
  // the seam below at the right-hand corner, the seam stays there.
  const auto right = tilted_box(0.2), left = tilted_box(-0.2);
  CHECK(right.points[aligned_seam(right.points)].x == 20);
  CHECK(left.points[aligned_seam(left.points)].x == 0);
  const std::vector<Seam> below{{PathRole::outer_wall, false, {20, 10.2}}};
  const std::size_t i = remembered_seam(left.points, PathRole::outer_wall, below, 1.35, 0.45);
  CHECK(left.points[i] == Vec2{20, 10});
  // A seam below of another role, or running the other way (a hole's), or too far away,
  // is not this loop's: the per-layer rule.
  const std::vector<Seam> other_role{{PathRole::inner_wall, false, {20, 10.2}}};
  CHECK(remembered_seam(left.points, PathRole::outer_wall, other_role, 1.35, 0.45) ==
        aligned_seam(left.points));
  const std::vector<Seam> hole{{PathRole::outer_wall, true, {20, 10.2}}};
  CHECK(remembered_seam(left.points, PathRole::outer_wall, hole, 1.35, 0.45) ==
        aligned_seam(left.points));
  const std::vector<Seam> far{{PathRole::outer_wall, false, {22, 12}}};
  CHECK(remembered_seam(left.points, PathRole::outer_wall, far, 1.35, 0.45) ==
        aligned_seam(left.points));
}

TEST_CASE("remembered_seam_moves_into_a_concave_corner_only_from_a_smooth_stretch") {
  // A 90-gon circle has no corner (4 degree turns): the seam below, at the front, stays.
  Loop ring = circle({0, 0}, 10, 90);
  const auto smooth = closed_path(ring);
  const std::vector<Seam> front{{PathRole::outer_wall, false, {0, -10}}};
  const std::size_t kept = remembered_seam(smooth.points, PathRole::outer_wall, front, 1.35, 0.45);
  CHECK(std::hypot(smooth.points[kept].x, smooth.points[kept].y + 10) < 0.45);
  // A notch at the back is a better place: the seam goes there.
  Loop notched = ring;
  notched[22] = {0.33, 9.6};  // vertex 22 of 90, at 88 degrees, pulled in 0.4 mm: a concave
                              // corner (56 degrees) within the rear band
  const auto with_notch = closed_path(notched);
  CHECK(with_notch.points[remembered_seam(with_notch.points, PathRole::outer_wall, front, 1.35,
                                          0.45)] == Vec2{0.33, 9.6});
  // From a corner, it stays: a square with the notch in its back edge, seam below at the
  // front-right corner.
  const auto box = closed_path(Loop{{0, 0}, {20, 0}, {20, 20}, {11, 20}, {10, 19.6}, {9, 20}, {0, 20}});
  CHECK(box.points[aligned_seam(box.points)] == Vec2{10, 19.6});
  const std::vector<Seam> corner{{PathRole::outer_wall, false, {20.1, 0}}};
  CHECK(box.points[remembered_seam(box.points, PathRole::outer_wall, corner, 1.35, 0.45)] ==
        Vec2{20, 0});
}

TEST_CASE("appended_loops_remember_and_report_their_seams") {
  std::vector<ExtrusionPath> out;
  Vec2 at{-5, -5};
  std::vector<Seam> laid;
  const std::vector<Seam> below{{PathRole::outer_wall, false, {20, 10.2}}};
  append_nearest_first({tilted_box(-0.2)}, SeamPosition::aligned, at, out, &below, &laid);
  REQUIRE(out.size() == 1);
  CHECK(out[0].points.front() == Vec2{20, 10});
  REQUIRE(laid.size() == 1);
  CHECK(laid[0].at == Vec2{20, 10});
  CHECK(laid[0].role == PathRole::outer_wall);
  CHECK(!laid[0].hole);
}

TEST_CASE("closed_path_rotates_to_its_seam_and_still_closes") {
  std::vector<ExtrusionPath> out;
  Vec2 at{30, -5};
  append_nearest_first({closed_path(rectangle(0, 0, 20, 20))}, SeamPosition::nearest, at, out);
  REQUIRE(out.size() == 1);
  CHECK(out[0].points.front() == Vec2{20, 0});
  CHECK(out[0].points.back() == Vec2{20, 0});
  CHECK(out[0].points.size() == 5);
  CHECK(at == Vec2{20, 0});
  out.clear();
  append_nearest_first({closed_path(rectangle(0, 0, 20, 20))}, SeamPosition::aligned, at, out);
  CHECK(out[0].points.front() == Vec2{0, 20});
}

TEST_CASE("open_paths_print_nearest_first_from_their_nearer_end") {
  // Three parallel lines, given out of order: a serpentine from the bottom.
  std::vector<ExtrusionPath> lines{line({0, 2}, {10, 2}), line({0, 0}, {10, 0}),
                                   line({0, 1}, {10, 1})};
  std::vector<ExtrusionPath> out;
  Vec2 at{-1, -1};
  append_nearest_first(lines, SeamPosition::aligned, at, out);
  REQUIRE(out.size() == 3);
  CHECK(out[0].points.front() == Vec2{0, 0});
  CHECK(out[1].points.front() == Vec2{10, 1});
  CHECK(out[2].points.front() == Vec2{0, 2});
  CHECK(at == Vec2{10, 2});
}

TEST_CASE("travel_that_leaves_the_region_retracts_one_inside_does_not") {
  // A 20 mm square with a 10 mm hole: a travel over the hole or out of the part oozes where
  // nothing covers it, and retracts if longer than 2 mm; one inside the part never does,
  // however long: what oozes there lands on the part.
  const Region holed{{rectangle(0, 0, 20, 20), reversed(rectangle(5, 5, 15, 15))}};
  std::vector<ExtrusionPath> paths{
      line({1, 10}, {2, 10}),      // first: always (the layer change)
      line({2.5, 10}, {3, 10}),    // 0.5 mm on: no
      line({17, 10}, {18, 10}),    // 14 mm across the hole: yes
      line({18, 11}, {18, 12}),    // 1 mm on: no
      line({18, 16}, {18, 17}),    // 4 mm, inside: no
      line({1, 17}, {1, 18}),      // 17 mm along the top, inside: no
      line({-0.5, 18}, {-0.5, 1}),  // 1.5 mm out of the part: shorter than 2 mm, no
      line({25, 1}, {26, 1}),      // 25.5 mm through the part and out: yes
  };
  mark_retractions(paths, holed, 2.0);
  CHECK(paths[0].retract_before);
  CHECK(!paths[1].retract_before);
  CHECK(paths[2].retract_before);
  CHECK(!paths[3].retract_before);
  CHECK(!paths[4].retract_before);
  CHECK(!paths[5].retract_before);
  CHECK(!paths[6].retract_before);
  CHECK(paths[7].retract_before);
}

TEST_CASE("crosses_boundary_sees_walls_and_holes_only") {
  const Region holed{{rectangle(0, 0, 20, 20), reversed(rectangle(5, 5, 15, 15))}};
  CHECK(crosses_boundary(holed, {1, 10}, {18, 10}));
  CHECK(crosses_boundary(holed, {1, 10}, {25, 10}));
  CHECK(!crosses_boundary(holed, {1, 1}, {19, 1}));
  CHECK(!crosses_boundary(Region{}, {1, 1}, {19, 1}));
}

TEST_CASE("empty_paths_order_to_nothing") {
  std::vector<ExtrusionPath> out;
  Vec2 at{};
  append_nearest_first({}, SeamPosition::nearest, at, out);
  CHECK(out.empty());
  std::vector<ExtrusionPath> none;
  mark_retractions(none, Region{}, 2);
  CHECK(!nearest_start({}, SeamPosition::aligned, at));
  CHECK(aligned_seam({}) == 0);
}

TEST_CASE("seam_names_round_trip") {
  for (SeamPosition s : {SeamPosition::aligned, SeamPosition::nearest}) {
    CHECK(parse_seam_position(seam_position_name(s)) == s);
  }
  CHECK(!parse_seam_position("random"));
}

}  // namespace travel_order_test
