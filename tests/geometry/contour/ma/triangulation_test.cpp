// Step 2 of the medial-axis contour: the samples' constrained Delaunay triangulation as a
// plain structure, against Euler's formula and its own adjacency.
#include <doctest/doctest.h>

#include "geometry/contour/ma/samples.h"
#include "geometry/contour/ma/triangulation.h"

namespace triangulation_test {

using geometry::Loop;
using geometry::ma::SampleTriangulation;

TEST_CASE("triangulation_of_a_ring_is_closed_and_constrained_along_its_loops") {
  const Loop outer{{-5, -5}, {5, -5}, {5, 5}, {-5, 5}}, hole{{-2, -2}, {-2, 2}, {2, 2}, {2, -2}};
  geometry::MaOptions options;
  options.spacing = 0.5;
  const auto samples = geometry::ma::sample_boundary_pair({&outer, &hole}, options);
  REQUIRE(samples.size() == 4 * 20 + 4 * 8);
  const SampleTriangulation t = geometry::ma::triangulate_samples(samples);
  // Samples at distinct points: one vertex each, and the infinite vertex.
  REQUIRE(t.sample_of.size() == samples.size() + 1);
  // Euler, with the infinite vertex closing the plane into a sphere: F = 2 (V + 1) - 4.
  CHECK(t.faces.size() == 2 * samples.size() - 2);
  std::size_t infinite = 0, constrained = 0;
  for (std::uint32_t f = 0; f < t.faces.size(); ++f) {
    const SampleTriangulation::Face& face = t.faces[f];
    infinite += face.infinite;
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t n = face.neighbour[k];
      CHECK(t.faces[n].neighbour[t.index_in(n, f)] == f);  // neighbours agree
      // ... on the edge's ends: vertices cw and ccw of k, seen from the other side.
      const int back = t.index_in(n, f);
      CHECK(t.faces[n].vertex[geometry::ma::cw(back)] == face.vertex[geometry::ma::ccw(k)]);
      CHECK(face.is_constrained(k) == t.faces[n].is_constrained(back));
      constrained += face.is_constrained(k);
    }
    if (!face.infinite) {
      const geometry::Vec2 a = t.point[face.vertex[0]], b = t.point[face.vertex[1]],
                           c = t.point[face.vertex[2]];
      CHECK(geometry::cross(b - a, c - a) > 0);  // counter-clockwise
    }
  }
  // Every sample of the outer loop is on the convex hull, and so has an infinite face; every
  // loop edge between consecutive samples is constrained, seen from both sides.
  CHECK(infinite == 80);
  CHECK(constrained == 2 * samples.size());
  CHECK(t.faces[t.infinite_face].infinite);
}

TEST_CASE("triangulation_of_collinear_samples_has_no_faces") {
  const Loop flat{{0, 0}, {1, 0}, {2, 0}};
  geometry::MaOptions options;
  options.spacing = 10;
  const auto samples = geometry::ma::sample_boundary_pair({&flat}, options);
  CHECK(geometry::ma::triangulate_samples(samples).faces.empty());
}

}  // namespace triangulation_test
