// Uniform slicing: all planes in one upward sweep over the faces sorted by their lowest
// vertex, keeping the list of faces that still reach above the current plane; each plane is
// then cut from its own list (plane_section.h), the planes in parallel. What happens to a
// mesh that is not closed (open chains) and to planes through vertices: see plane_section.h.
#include "geometry/slicing/slicer.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>

#include "geometry/slicing/plane_section.h"

namespace geometry {

std::vector<Region> slice_mesh(const Mesh& mesh, std::span<const double> heights) {
  std::vector<Region> sections(heights.size());

  // Planes bottom-up; a NaN or infinite height has an empty section and stays out of the sweep.
  std::vector<std::size_t> planes;
  for (std::size_t i = 0; i < heights.size(); ++i) {
    if (std::isfinite(heights[i])) planes.push_back(i);
  }
  std::stable_sort(planes.begin(), planes.end(),
                   [&](std::size_t a, std::size_t b) { return heights[a] < heights[b]; });

  // A face crosses the plane at z (taken just above z) when z_low <= z < z_high; horizontal
  // faces never do, and faces with a vertex index out of range are not part of any surface.
  struct FaceSpan {
    double z_low, z_high;
    std::uint32_t face;
  };
  std::vector<FaceSpan> spans;
  spans.reserve(mesh.faces.size());
  const std::size_t vertex_count = mesh.vertices.size();
  for (std::uint32_t f = 0; f < mesh.faces.size(); ++f) {
    const auto& face = mesh.faces[f];
    if (face[0] >= vertex_count || face[1] >= vertex_count || face[2] >= vertex_count) continue;
    const double a = mesh.vertices[face[0]].z, b = mesh.vertices[face[1]].z,
                 c = mesh.vertices[face[2]].z;
    const double low = std::min({a, b, c}), high = std::max({a, b, c});
    if (low < high) spans.push_back({low, high, f});
  }
  std::sort(spans.begin(), spans.end(),
            [](const FaceSpan& a, const FaceSpan& b) { return a.z_low < b.z_low; });

  std::vector<std::vector<std::uint32_t>> crossing(planes.size());
  std::vector<FaceSpan> active;
  std::size_t next = 0;
  for (std::size_t k = 0; k < planes.size(); ++k) {
    const double z = heights[planes[k]];
    while (next < spans.size() && spans[next].z_low <= z) active.push_back(spans[next++]);
    std::erase_if(active, [z](const FaceSpan& s) { return s.z_high <= z; });
    crossing[k].reserve(active.size());
    for (const FaceSpan& s : active) crossing[k].push_back(s.face);
  }

  tbb::parallel_for(std::size_t{0}, planes.size(), [&](std::size_t k) {
    sections[planes[k]] = plane_section(mesh, crossing[k], heights[planes[k]]);
    std::vector<std::uint32_t>().swap(crossing[k]);
  });
  return sections;
}

}  // namespace geometry
