// Mesh repair: from the triangle soup of an STL file to a closed, outward-oriented Mesh.
//
// Input: facets as read (any units; the repair is scale-free). Output: an indexed Mesh whose
// faces are counter-clockwise seen from outside. Steps, each counted in the RepairReport:
//  1. merge vertices with identical coordinates (STL repeats every corner per facet);
//  2. drop degenerate facets (two corners the same, or three collinear) and duplicate facets;
//  3. split non-manifold vertices (two surfaces touching in one point) and orient every
//     connected surface consistently;
//  4. fill holes with flat, refined patches (CGAL triangulate_and_refine_hole; not faired, so
//     a patch never bulges past its rim) unless the holes together would
//     invent more than `max_hole_share` of the surface: a file that is missing that much of
//     its surface is left open and refused by check_printable, not guessed;
//  5. orient each closed surface outward (inner shells of hollow parts inward).
// Total: empty or fully degenerate input gives an empty Mesh and a report saying so.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include "geometry/mesh/mesh.h"

namespace geometry {

struct RepairOptions {
  double max_hole_share = 0.10;  // largest share of the surface area hole filling may add
};

struct RepairReport {
  std::size_t facets_read = 0;
  std::size_t vertices = 0;                  // after merging and splitting
  std::size_t vertices_merged = 0;           // corners that coincided with an earlier corner
  std::size_t degenerate_faces_dropped = 0;  // zero-area facets
  std::size_t duplicate_faces_dropped = 0;   // a second copy of the same three corners
  std::size_t non_manifold_vertices_split = 0;
  std::size_t faces_reoriented = 0;          // facets whose vertex order was reversed
  std::size_t open_edges_before = 0;         // edges with one facet, after merging
  std::size_t open_edges_after = 0;
  std::size_t non_manifold_edges = 0;        // edges shared by more than two facets
  std::size_t holes_found = 0;
  std::size_t holes_filled = 0;
  std::size_t faces_added = 0;
  double hole_area = 0;                      // area of the holes (filled or not), file units^2
  double hole_share = 0;                     // hole_area / area of the surface in the file
  double surface_area = 0;                   // of the repaired mesh, fill included
  double volume = 0;                         // signed volume of the repaired mesh
  Box3 bounds;                               // of the repaired mesh, file units
  bool closed = false;                       // no open edges left, at least one face

  // True when the mesh differs from the file beyond the vertex merge every STL needs.
  bool anything_repaired() const;
  // "3 degenerate facets dropped, 5 holes filled (+869 faces)"; "" when nothing was repaired.
  std::string summary() const;
};

Mesh repair(const std::vector<Triangle>& facets, RepairReport* report = nullptr,
            const RepairOptions& options = {});

// Refuses a repaired mesh that cannot be printed, with one line naming `name`: no facets,
// every facet degenerate, holes too large to fill, still open after repair, zero volume.
// Throws InputError; returns normally for a closed mesh with positive volume.
void check_printable(const RepairReport& report, std::string_view name,
                     const RepairOptions& options = {});

}  // namespace geometry
