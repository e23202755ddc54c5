#include "geometry/contour/ma/axis.h"

#include <algorithm>

namespace geometry::ma {

std::vector<char> vertex_labels(const SampleTriangulation& triangulation,
                                std::span<const Sample> samples, std::span<const char> solid) {
  const char outside = solid[0] != 0;
  std::vector<char> labels(triangulation.sample_of.size());
  for (std::size_t v = 0; v < labels.size(); ++v) {
    labels[v] = triangulation.known(v) ? solid[samples[triangulation.sample_of[v]].loop] != 0
                                       : outside;
  }
  return labels;
}

namespace {

// The contour's crossing of the edge face f leaves by (`out`), if both its ends are samples:
// the point fairing puts there, with the loops of the edge's ends and of the two corners
// opposite it as where the axis is measured from.
bool axis_crossing(const SampleTriangulation& triangulation, const std::vector<char>& labels,
                   std::span<const Sample> samples, const std::vector<LoopEdges>& loops,
                   std::uint32_t f, int out, bool fairing, ContourVertex& crossing) {
  const SampleTriangulation::Face& face = triangulation.faces[f];
  const std::uint32_t u = face.vertex[cw(out)], v = face.vertex[ccw(out)];
  if (!triangulation.known(u) || !triangulation.known(v)) return false;
  const Sample& su = samples[triangulation.sample_of[u]];
  const Sample& sv = samples[triangulation.sample_of[v]];
  const bool u_solid = labels[u];
  const Sample& s = u_solid ? su : sv;
  const Sample& e = u_solid ? sv : su;
  AxisQuery query;
  query.add(true, &loops[s.loop], s.segment);
  query.add(false, &loops[e.loop], e.segment);
  const std::uint32_t across = face.neighbour[out];
  const std::uint32_t beyond =
      triangulation.faces[across].vertex[triangulation.index_in(across, f)];
  for (std::uint32_t w : {face.vertex[out], beyond}) {
    if (!triangulation.known(w)) continue;
    const Sample& sw = samples[triangulation.sample_of[w]];
    query.add(labels[w], &loops[sw.loop], sw.segment);
  }
  crossing = {fairing ? equidistant_on(query, s, e) : 0.5 * (s.at + e.at), query};
  return true;
}

}  // namespace

std::vector<Loop> axis_loops(const SampleTriangulation& triangulation,
                             const std::vector<char>& labels, std::span<const Sample> samples,
                             const std::vector<const Loop*>& loops, bool fairing) {
  std::vector<Loop> contour;
  std::vector<LoopEdges> edges;  // what the crossings' queries walk
  edges.reserve(loops.size());
  for (const Loop* loop : loops) edges.emplace_back(*loop);
  std::vector<char> visited(triangulation.faces.size(), 0);
  std::vector<ContourVertex> chain;  // one loop's, before fairing
  chain.reserve(samples.size());     // about one crossing per sample
  ContourVertex crossing;
  for (std::uint32_t start = 0; start < triangulation.faces.size(); ++start) {
    if (visited[start] || exit_edge(triangulation.faces[start], labels) < 0) continue;
    chain.clear();
    std::uint32_t f = start;
    do {
      visited[f] = 1;
      const int out = exit_edge(triangulation.faces[f], labels);
      if (out < 0) break;  // never: the loop condition checked it (said for GCC's -Warray-bounds)
      if (axis_crossing(triangulation, labels, samples, edges, f, out, fairing, crossing)) {
        chain.push_back(crossing);
      }
      f = triangulation.faces[f].neighbour[out];
    } while (f != start && exit_edge(triangulation.faces[f], labels) >= 0 && !visited[f]);
    if (chain.size() < 3) continue;
    Loop loop = axis_loop(chain, fairing);
    if (loop.size() >= 3) contour.push_back(std::move(loop));
  }
  // In the order of their first vertices, not of the faces (disjoint loops: distinct points).
  std::sort(contour.begin(), contour.end(), [](const Loop& a, const Loop& b) { return before(a[0], b[0]); });
  return contour;
}

}  // namespace geometry::ma
