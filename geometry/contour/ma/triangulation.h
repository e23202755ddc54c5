// Step 2 of the medial-axis contour (paper §3.3, "the Voronoi diagram is constructed via a
// robust O(n log n) scheme provided by CGAL"): the Delaunay triangulation of one island's
// samples, whose dual is their Voronoi diagram. The only file of the MA that sees CGAL is
// triangulation.cpp; the steps after it read this plain copy.
//
// Input: the samples of one boundary pair (samples.h), mm.
// Output: CGAL's constrained Delaunay triangulation (Epick: exact predicates) of the samples,
// with every boundary edge between consecutive samples of a loop as a constraint. Where a
// strip is wider than the spacing that is the plain Delaunay triangulation; where it is
// thinner (a vertical wall's strip is 4 um wide) the constraints keep a Delaunay edge from
// jumping across the other loop, so every triangle with corners on two loops lies inside the
// strip. Faces are listed in CGAL's order, the infinite ones (a corner at the infinite vertex,
// outside the convex hull) included; each face's vertices run counter-clockwise and its
// neighbour k lies across the edge opposite its vertex k. Fewer than three samples, or all
// of them on one line: no faces.
// Cost: CGAL's insertion, about eight in-circle and seven orientation tests per sample;
// Epick's tests are tried first against one error bound per island (triangulation.cpp), the
// same signs.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "geometry/contour/ma/samples.h"
#include "geometry/core/polygon.h"

namespace geometry::ma {

struct SampleTriangulation {
  static constexpr std::uint32_t kNoSample = 0xffffffffu;
  struct Face {
    std::array<std::uint32_t, 3> vertex{};     // counter-clockwise
    std::array<std::uint32_t, 3> neighbour{};  // across the edge opposite vertex k
    std::uint8_t constrained = 0;              // bit k: that edge is a boundary edge
    bool infinite = false;                     // one corner is the infinite vertex
    bool is_constrained(int k) const { return (constrained >> k) & 1; }
  };
  // Per vertex: the sample it is (the least numbered of samples at one point), or kNoSample
  // for the infinite vertex and for points CGAL made where two constraints cross.
  std::vector<std::uint32_t> sample_of;
  std::vector<Vec2> point;  // per vertex, mm (the infinite vertex: 0, 0)
  std::vector<Face> faces;
  std::uint32_t infinite_face = 0;  // a face of the infinite vertex

  bool known(std::uint32_t vertex) const { return sample_of[vertex] != kNoSample; }
  // The edge's index in face f's neighbour (CGAL's Face::index(neighbour)).
  int index_in(std::uint32_t f, std::uint32_t neighbour) const {
    const Face& face = faces[f];
    return face.neighbour[0] == neighbour ? 0 : face.neighbour[1] == neighbour ? 1 : 2;
  }
};

// CGAL's vertex numbering round a face.
inline int ccw(int k) { return k == 2 ? 0 : k + 1; }
inline int cw(int k) { return k == 0 ? 2 : k - 1; }

SampleTriangulation triangulate_samples(std::span<const Sample> samples);

}  // namespace geometry::ma
