// The medial-axis contour's loops as a function of the triangulation, not of the order its
// faces are listed in (which follows CGAL's insertion order): every loop starts at its least
// vertex and the loops are in the order of those vertices. And the axis where it is known in
// closed form: the middle of a strip between parallel sides, the middle circle of an annulus.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>

#include "geometry/contour/ma/axis.h"

namespace axis_start_test {

using geometry::Loop;
using geometry::Vec2;
using geometry::ma::SampleTriangulation;

namespace {

constexpr double kPi = 3.14159265358979323846;

bool before(Vec2 a, Vec2 b) { return a.x < b.x || (a.x == b.x && a.y < b.y); }

// The same triangulation listed otherwise: vertices and faces renumbered at random, and each
// face's corners rotated (still counter-clockwise), as another insertion order lists it.
SampleTriangulation relisted(const SampleTriangulation& t, unsigned seed) {
  std::mt19937 random(seed);
  const auto shuffled = [&](std::size_t n) {
    std::vector<std::uint32_t> order(n);
    std::iota(order.begin(), order.end(), 0u);
    std::shuffle(order.begin(), order.end(), random);
    std::vector<std::uint32_t> index(n);  // old number -> new
    for (std::uint32_t i = 0; i < n; ++i) index[order[i]] = i;
    return std::make_pair(order, index);
  };
  const auto [vertex_order, vertex_index] = shuffled(t.sample_of.size());
  const auto [face_order, face_index] = shuffled(t.faces.size());
  SampleTriangulation out;
  for (std::uint32_t v : vertex_order) {
    out.sample_of.push_back(t.sample_of[v]);
    out.point.push_back(t.point[v]);
  }
  for (std::uint32_t f : face_order) {
    const SampleTriangulation::Face& face = t.faces[f];
    const int turn = static_cast<int>(random() % 3);
    SampleTriangulation::Face moved;
    for (int k = 0; k < 3; ++k) {
      const int from = (k + turn) % 3;
      moved.vertex[k] = vertex_index[face.vertex[from]];
      moved.neighbour[k] = face_index[face.neighbour[from]];
      if (face.is_constrained(from)) moved.constrained |= static_cast<std::uint8_t>(1 << k);
    }
    moved.infinite = face.infinite;
    out.faces.push_back(moved);
  }
  out.infinite_face = face_index[t.infinite_face];
  return out;
}

std::vector<Loop> axis_of(const SampleTriangulation& t, const std::vector<geometry::ma::Sample>& samples,
                          const std::vector<const Loop*>& loops, const std::vector<char>& solid,
                          bool fairing) {
  const std::vector<char> labels = geometry::ma::vertex_labels(t, samples, solid);
  return geometry::ma::axis_loops(t, labels, samples, loops, fairing);
}

Loop circle(double r, int n, bool counter_clockwise) {
  Loop loop;
  for (int i = 0; i < n; ++i) {
    const double a = 2 * kPi * (counter_clockwise ? i : n - i) / n;
    loop.push_back({r * std::cos(a), r * std::sin(a)});
  }
  return loop;
}

}  // namespace

TEST_CASE("axis_loops_are_the_same_lists_whatever_order_the_faces_are_listed_in") {
  // Three holes in a row: the outer loop and the middle hole empty, the outer holes solid,
  // so two axis loops, one round each solid hole.
  const Loop outer{{-12, -4}, {12, -4}, {12, 4}, {-12, 4}};
  const Loop left{{-10, -2}, {-10, 2}, {-6, 2}, {-6, -2}}, middle{{-2, -2}, {-2, 2}, {2, 2}, {2, -2}},
      right{{6, -2}, {6, 2}, {10, 2}, {10, -2}};
  const std::vector<const Loop*> loops{&outer, &left, &middle, &right};
  const std::vector<char> solid{0, 1, 0, 1};
  geometry::MaOptions options;
  const auto samples = geometry::ma::sample_boundary_pair(loops, options);
  const SampleTriangulation t = geometry::ma::triangulate_samples(samples);
  for (const bool fairing : {true, false}) {
    CAPTURE(fairing);
    const std::vector<Loop> axis = axis_of(t, samples, loops, solid, fairing);
    REQUIRE(axis.size() == 2);
    for (const Loop& loop : axis) {
      CHECK(std::min_element(loop.begin(), loop.end(), before) == loop.begin());
    }
    CHECK(before(axis[0][0], axis[1][0]));
    CHECK(axis[0][0].x < -10);  // round the left hole first
    for (unsigned seed = 1; seed <= 8; ++seed) {
      CAPTURE(seed);
      CHECK(axis_of(relisted(t, seed), samples, loops, solid, fairing) == axis);
    }
  }
}

TEST_CASE("axis_of_an_annulus_is_its_middle_circle_from_any_face_order") {
  // Inscribed 512-gons of radius 5 and 2: the axis lies between the middle circles of the
  // polygons' inner (r cos(pi/n)) and outer (r) radii.
  const int n = 512;
  const Loop outer = circle(5, n, true), hole = circle(2, n, false);
  const std::vector<const Loop*> loops{&outer, &hole};
  geometry::MaOptions options;
  const auto samples = geometry::ma::sample_boundary_pair(loops, options);
  const SampleTriangulation t = geometry::ma::triangulate_samples(samples);
  const std::vector<char> solid{1, 0};
  const std::vector<Loop> axis = axis_of(t, samples, loops, solid, true);
  REQUIRE(axis.size() == 1);
  const double low = 3.5 * std::cos(kPi / n) - 2e-5, high = 3.5 + 2e-5;
  for (Vec2 p : axis[0]) {
    const double r = std::hypot(p.x, p.y);
    CHECK(r >= low);
    CHECK(r <= high);
  }
  // Starts at its least vertex: near (-3.5, 0).
  CHECK(axis[0][0].x < -3.5 + 1e-3);
  for (unsigned seed = 1; seed <= 4; ++seed) {
    CHECK(axis_of(relisted(t, seed), samples, loops, solid, true) == axis);
  }
}

TEST_CASE("axis_of_a_rectangular_strip_runs_midway_between_its_parallel_sides") {
  // Outer 20 x 6, hole 16 x 2: the sides 2 apart everywhere, the axis on x = +-9 and y = +-2
  // wherever both nearest sides are the parallel pair (away from the corners' parabolas).
  const Loop outer{{-10, -3}, {10, -3}, {10, 3}, {-10, 3}}, hole{{-8, -1}, {-8, 1}, {8, 1}, {8, -1}};
  const std::vector<const Loop*> loops{&outer, &hole};
  geometry::MaOptions options;
  const auto samples = geometry::ma::sample_boundary_pair(loops, options);
  const SampleTriangulation t = geometry::ma::triangulate_samples(samples);
  const std::vector<Loop> axis = axis_of(t, samples, loops, {0, 1}, true);
  REQUIRE(axis.size() == 1);
  // Along every edge (simplification leaves a straight stretch one edge).
  std::size_t long_sides = 0;
  const Loop& loop = axis[0];
  for (std::size_t i = 0; i < loop.size(); ++i) {
    for (const double t : {0.0, 0.25, 0.5, 0.75}) {
      const Vec2 p = loop[i] + t * (loop[(i + 1) % loop.size()] - loop[i]);
      if (std::abs(p.x) <= 7) {
        CHECK(std::abs(std::abs(p.y) - 2) <= 2e-5);
        ++long_sides;
      } else if (std::abs(p.y) <= 0.5) {
        CHECK(std::abs(std::abs(p.x) - 9) <= 2e-5);
      }
    }
  }
  CHECK(long_sides >= 4);  // points on both long sides
  CHECK(axis[0][0] == *std::min_element(axis[0].begin(), axis[0].end(), before));
  for (unsigned seed = 1; seed <= 4; ++seed) {
    CHECK(axis_of(relisted(t, seed), samples, loops, {0, 1}, true) == axis);
  }
}

}  // namespace axis_start_test
