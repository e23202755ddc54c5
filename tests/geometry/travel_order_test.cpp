// travel_order: seams, nearest-first order, path direction, retractions.
#include "geometry/travel_order.h"

#include <doctest/doctest.h>

#include "geometry/toolpath_shapes.h"

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
