// Step 3 and the chaining of the medial-axis contour (paper §3.3, Observation 3.3.1: "all the
// Voronoi edges dual to Delaunay edges that are incident to two distinct [boundary loops] are
// identified as the components of Medial axis skeleton").
//
// Labels: every vertex of the triangulation is solid (1) or empty (0): the label of the free
// face beside its sample's loop (solid_beside, boundary_pair.h); the infinite vertex and the
// points CGAL made where constraints cross take the outer loop's label (any labelling closes).
// The axis: the Voronoi edges dual to the Delaunay edges with one solid and one empty end.
// With two labels every triangle has 0 or 2 such edges, so the kept edges chain into closed
// loops, one per strip of mixed triangles, never branching, even where three or more loops
// meet (islands that merge inside the slab): the loop goes round the union of the solid
// loops' territories. Each kept edge gives the contour one vertex where it crosses its dual
// Delaunay edge (fairing.h), which keeps the contour inside the triangles, hence inside the
// strip, simple, and disjoint from the other loops.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "geometry/contour/ma/fairing.h"
#include "geometry/contour/ma/samples.h"
#include "geometry/contour/ma/triangulation.h"
#include "geometry/core/polygon.h"

namespace geometry::ma {

// Per vertex of the triangulation: 1 solid, 0 empty. `solid` per loop (loops_of order).
std::vector<char> vertex_labels(const SampleTriangulation& triangulation,
                                std::span<const Sample> samples, std::span<const char> solid);

// Whether a face's corners carry both labels (its two mixed edges are crossed by the axis).
inline bool is_mixed(const SampleTriangulation::Face& face, const std::vector<char>& labels) {
  const char l0 = labels[face.vertex[0]];
  return labels[face.vertex[1]] != l0 || labels[face.vertex[2]] != l0;
}

// In a mixed face, the edge the contour leaves by, so that the solid stays on its left: with
// corners v0 v1 v2 counter-clockwise and v_i the odd one out, the contour enters by
// (v_i, v_i+1) and leaves by (v_i+2, v_i) when v_i is solid, the reverse if not. -1 for a
// face that is not mixed.
inline int exit_edge(const SampleTriangulation::Face& face, const std::vector<char>& labels) {
  const char l0 = labels[face.vertex[0]], l1 = labels[face.vertex[1]], l2 = labels[face.vertex[2]];
  if (l0 == l1 && l1 == l2) return -1;
  const int odd = l1 == l2 ? 0 : (l0 == l2 ? 1 : 2);
  return labels[face.vertex[odd]] ? (odd + 1) % 3 : (odd + 2) % 3;
}

// The contour's loops: every closed chain of mixed faces, each crossing placed by fairing.h
// (or at the Delaunay edge's middle without fairing), faired and simplified; chains of fewer
// than three crossings and loops left with fewer than three vertices are dropped. `loops` are
// the pair's loops (loops_of order), which the samples index. Solid on each loop's left. Each
// loop starts at its least vertex (by x, then y) and the loops are in the order of those
// vertices: the result depends on the triangulation's faces, not on the order they are listed
// in (which follows CGAL's insertion order).
std::vector<Loop> axis_loops(const SampleTriangulation& triangulation,
                             const std::vector<char>& labels, std::span<const Sample> samples,
                             const std::vector<const Loop*>& loops, bool fairing);

}  // namespace geometry::ma
