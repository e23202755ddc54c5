#include "geometry/contour/ma/pockets.h"

#include <algorithm>
#include <cstdint>
#include <utility>

#include "geometry/contour/ma/axis.h"

namespace geometry::ma {

std::vector<char> faces_inside(const SampleTriangulation& triangulation) {
  // How many loops a walk from the infinite face crosses to reach each face: flooded from it,
  // one more loop crossed at every constrained edge.
  std::vector<std::int8_t> nesting(triangulation.faces.size(), -1);
  std::vector<std::pair<std::uint32_t, int>> border{{triangulation.infinite_face, 0}};
  std::vector<std::uint32_t> queue;
  while (!border.empty()) {
    const auto [seed, level] = border.back();
    border.pop_back();
    if (nesting[seed] != -1) continue;
    queue.assign(1, seed);
    while (!queue.empty()) {
      const std::uint32_t f = queue.back();
      queue.pop_back();
      if (nesting[f] != -1) continue;
      nesting[f] = static_cast<std::int8_t>(std::min(level, 100));
      const SampleTriangulation::Face& face = triangulation.faces[f];
      for (int i = 0; i < 3; ++i) {
        const std::uint32_t n = face.neighbour[i];
        if (nesting[n] != -1) continue;
        if (face.is_constrained(i)) {
          border.push_back({n, level + 1});
        } else {
          queue.push_back(n);
        }
      }
    }
  }
  std::vector<char> inside(triangulation.faces.size());
  for (std::size_t f = 0; f < inside.size(); ++f) {
    inside[f] = !triangulation.faces[f].infinite && (nesting[f] & 1) != 0;
  }
  return inside;
}

namespace {

// Contributing samples: 1 for the corners of a mixed face inside the footprint, else 0.
std::vector<char> contributing_samples(const SampleTriangulation& triangulation,
                                       const std::vector<char>& labels,
                                       const std::vector<char>& inside, std::size_t samples) {
  std::vector<char> contributing(samples, 0);
  for (std::size_t f = 0; f < triangulation.faces.size(); ++f) {
    const SampleTriangulation::Face& face = triangulation.faces[f];
    if (!inside[f] || !is_mixed(face, labels)) continue;
    for (std::uint32_t v : face.vertex) {
      if (triangulation.known(v)) contributing[triangulation.sample_of[v]] = 1;
    }
  }
  return contributing;
}

// The same-side faces inside the footprint connected to `seed` across unconstrained edges;
// `taken` marks the faces of every component found so far.
void component_of(const SampleTriangulation& triangulation, const std::vector<char>& labels,
                  const std::vector<char>& inside, std::uint32_t seed, std::vector<char>& taken,
                  std::vector<std::uint32_t>& component, std::vector<std::uint32_t>& queue) {
  component.clear();
  queue.assign(1, seed);
  taken[seed] = 1;
  while (!queue.empty()) {
    const std::uint32_t f = queue.back();
    queue.pop_back();
    component.push_back(f);
    const SampleTriangulation::Face& face = triangulation.faces[f];
    for (int i = 0; i < 3; ++i) {
      const std::uint32_t n = face.neighbour[i];
      if (taken[n] || !inside[n] || face.is_constrained(i)) continue;
      if (is_mixed(triangulation.faces[n], labels)) continue;
      taken[n] = 1;
      queue.push_back(n);
    }
  }
}

// Face f's corners on the nanometre grid, CCW as CGAL keeps its faces.
void add_triangle(const SampleTriangulation& triangulation, std::uint32_t f,
                  std::vector<ClipperLib::IntPoint>& corners) {
  for (std::uint32_t v : triangulation.faces[f].vertex) {
    corners.push_back(to_clipper(triangulation.point[v]));
  }
}

// A component as a pocket: its non-contributing samples (marked 2 in `contributing`, so each
// is listed once), its faces and the mixed faces at its mouths. Empty if all contribute.
Pocket pocket_of(const SampleTriangulation& triangulation, const std::vector<char>& labels,
                 const std::vector<char>& inside, std::span<const Sample> samples,
                 const std::vector<std::uint32_t>& component, std::vector<char>& contributing) {
  Pocket pocket;
  for (std::uint32_t f : component) {
    for (std::uint32_t v : triangulation.faces[f].vertex) {
      if (triangulation.known(v) && !contributing[triangulation.sample_of[v]]) {
        contributing[triangulation.sample_of[v]] = 2;
        pocket.non_contributing.push_back(samples[triangulation.sample_of[v]].at);
      }
    }
  }
  if (pocket.non_contributing.empty()) return pocket;
  // A mixed face has one same-side edge, so it is the mouth of one pocket at most, once.
  for (std::uint32_t f : component) {
    add_triangle(triangulation, f, pocket.triangle_corners);
    const SampleTriangulation::Face& face = triangulation.faces[f];
    for (int i = 0; i < 3; ++i) {
      const std::uint32_t n = face.neighbour[i];
      if (inside[n] && is_mixed(triangulation.faces[n], labels) && !face.is_constrained(i)) {
        add_triangle(triangulation, n, pocket.triangle_corners);
      }
    }
  }
  pocket.corners.reserve(pocket.triangle_corners.size());
  for (const auto& p : pocket.triangle_corners) pocket.corners.push_back(from_clipper(p));
  return pocket;
}

}  // namespace

void Pocket::add_triangles(ClipperLib::Paths& paths) const {
  for (std::size_t k = 0; k + 2 < triangle_corners.size(); k += 3) {
    paths.push_back({triangle_corners[k], triangle_corners[k + 1], triangle_corners[k + 2]});
  }
}

IslandPockets island_pockets(const SampleTriangulation& triangulation,
                             const std::vector<char>& labels, std::span<const Sample> samples) {
  IslandPockets found;
  const std::vector<char> inside = faces_inside(triangulation);
  std::vector<char> contributing =
      contributing_samples(triangulation, labels, inside, samples.size());
  for (std::size_t i = 0; i < samples.size(); ++i) {
    if (contributing[i]) found.contributing.push_back(samples[i].at);
  }
  std::vector<char> taken(triangulation.faces.size(), 0);
  std::vector<std::uint32_t> component, queue;
  for (std::uint32_t seed = 0; seed < triangulation.faces.size(); ++seed) {
    const SampleTriangulation::Face& face = triangulation.faces[seed];
    if (taken[seed] || !inside[seed] || is_mixed(face, labels)) continue;
    component_of(triangulation, labels, inside, seed, taken, component, queue);
    Pocket pocket = pocket_of(triangulation, labels, inside, samples, component, contributing);
    if (!pocket.non_contributing.empty()) found.pockets.push_back(std::move(pocket));
  }
  return found;
}

}  // namespace geometry::ma
