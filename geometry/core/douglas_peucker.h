// Douglas-Peucker on a closed loop: which of its n vertices to keep so that every vertex
// dropped lies within a tolerance of the edge that replaces it (a strict bound). The loop is
// split at vertex 0 and the vertex farthest from it, and each half simplified as an open
// polyline. One algorithm for the loops of any point type: the faired MA contour in mm
// (ma_contour.cpp) and Clipper's integer loops (clipper.cpp).
//
// Input:  n, the loop's vertex count; limit2, the squared tolerance in the units of
//         distance2; distance2(i, a, b), the squared distance from vertex i to the segment
//         from vertex a to vertex b (a == b: to that vertex).
// Output: keep[i] != 0 for the vertices kept; vertex 0 and the farthest from it always are.
// Total: n < 2 keeps every vertex.
#pragma once

#include <cstddef>
#include <utility>
#include <vector>

namespace geometry {

template <class Distance2>
std::vector<char> douglas_peucker_keep(std::size_t n, double limit2, Distance2&& distance2) {
  std::vector<char> keep(n, 1);
  if (n < 2) return keep;
  std::size_t far = 0;
  double far2 = -1;
  for (std::size_t i = 1; i < n; ++i) {
    const double d = distance2(i, 0, 0);
    if (d > far2) {
      far2 = d;
      far = i;
    }
  }
  keep.assign(n, 0);
  keep[0] = keep[far] = 1;
  std::vector<std::pair<std::size_t, std::size_t>> stack{{0, far}, {far, n}};
  while (!stack.empty()) {
    const auto [first, last] = stack.back();  // last may be n: vertex 0 again
    stack.pop_back();
    std::size_t worst = first;
    double worst2 = limit2;
    for (std::size_t i = first + 1; i < last; ++i) {
      const double d = distance2(i, first, last % n);
      if (d > worst2) {
        worst2 = d;
        worst = i;
      }
    }
    if (worst == first) continue;
    keep[worst] = 1;
    stack.push_back({first, worst});
    stack.push_back({worst, last});
  }
  return keep;
}

}  // namespace geometry
