// A cheap estimate of a candidate slab's distance error, for the layer plan (issue 11): how
// far the model's surface inside [z_lo, z_hi] spreads horizontally, facet by facet.
//
// A planar facet with normal n meets the horizontal plane at z along a line that moves, as z
// rises, by |n_z| / |n_xy| per mm across its own horizontal direction; over the part of the
// slab it spans (its overlap, mm) it covers w = overlap * |n_z| / |n_xy| horizontally. A
// vertical wall standing anywhere across that band leaves one of its ends at least w / 2
// away, so a region whose boundary follows the facet with one wall (what mid, ma and
// optimal-height print where the surface is one sheet) has D >= w / 2. The estimate is the
// largest w / 2 over the slab's facets. It is not a bound for every region (two walls close
// together, or another sheet's wall nearer, do better) and it misses what facets do together
// (a cap of many small facets), so the plan measures every layer it keeps exactly
// (slab_error.h) and uses this only to choose which candidates to measure.
//
// Horizontal facets are left out (flat_levels.h: they decide where boundaries must go).
// Input: a mesh (mm). Output of operator(): mm, >= 0; 0 for a slab no sloped facet meets.
#pragma once

#include <cstdint>
#include <vector>

#include "geometry/mesh/mesh.h"

namespace geometry {

class SlabSpreadEstimate {
 public:
  explicit SlabSpreadEstimate(const Mesh& mesh);
  double operator()(double z_lo, double z_hi) const;

 private:
  struct Facet {
    double z_min, z_max, spread_per_mm;  // |n_z| / |n_xy|
  };
  // Facets by height: bucket b lists every sloped facet whose z-range meets
  // [z_0 + b h, z_0 + (b + 1) h]; a facet in several buckets is met more than once by a
  // query, which a maximum does not mind.
  std::vector<Facet> facets_;
  std::vector<std::uint32_t> bucket_begin_, bucket_facets_;
  double z_0_ = 0, bucket_height_ = 0.1;
};

}  // namespace geometry
