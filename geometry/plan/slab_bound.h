// Bounds on what a candidate slab of the layer plan would need, from the mesh's facets alone
// (no section cut): FacetsByHeight finds the facets a slab meets, and ThickOverhangEstimate
// the overhang a slab has only for being thick.
//
// Horizontal facets are left out (flat_levels.h: they decide where boundaries must go).
// Input: a mesh (mm).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include "geometry/mesh/mesh.h"

namespace geometry {

// Facets by height, for queries of one slab at a time: bucket b lists every facet whose
// z-range meets [z_0 + b h, z_0 + (b + 1) h].
class FacetsByHeight {
 public:
  FacetsByHeight() = default;
  // Each facet's z-range (low < high), in the caller's order.
  explicit FacetsByHeight(std::vector<std::pair<double, double>> ranges, double bucket_height = 0.1);

  const std::pair<double, double>& range(std::size_t k) const { return ranges_[k]; }

  // Calls f(k) once for each facet k whose z-range overlaps (z_lo, z_hi).
  template <class F>
  void for_each(double z_lo, double z_hi, F&& f) const {
    if (ranges_.empty() || !(z_hi > z_lo)) return;
    const std::size_t buckets = bucket_begin_.size() - 1;
    const double first = std::floor((z_lo - z_0_) / bucket_height_);
    const double last = std::floor((z_hi - z_0_) / bucket_height_);
    if (last < 0 || first >= static_cast<double>(buckets)) return;
    for (std::size_t b = static_cast<std::size_t>(std::max(first, 0.0)),
                     e = std::min(buckets - 1, static_cast<std::size_t>(last));
         b <= e; ++b) {
      for (std::uint32_t i = bucket_begin_[b]; i < bucket_begin_[b + 1]; ++i) {
        const std::uint32_t k = bucket_facets_[i];
        const auto [low, high] = ranges_[k];
        // Once: in the bucket of the overlap's bottom (or the query's first).
        if (!(std::min(z_hi, high) > std::max(z_lo, low))) continue;
        if (bucket_of(std::max(z_lo, low)) != b) continue;
        f(k);
      }
    }
  }

 private:
  std::size_t bucket_of(double z) const;
  std::vector<std::pair<double, double>> ranges_;
  std::vector<std::uint32_t> bucket_begin_, bucket_facets_;
  double z_0_ = 0, bucket_height_ = 0.1;
};

// The overhang a slab has only for being thick, for a plan that keeps
// supports to what the part's slopes need: a downward-facing facet leaning phi from
// vertical steps out t tan(phi) from one layer to the next, and a layer reaches only
// min(t tan(a), w / 2) past the one below (overhang.h: a the overhang angle, w the bead
// width). Where phi is within a but t tan(phi) > w / 2 the layer has overhang beyond its
// reach that a layer thinner than w / (2 tan(phi)) would not have, and support goes under it.
// The estimate: over those facets, the share of the step beyond the reach,
// 1 - w / (2 t tan(phi)), times the facet's area seen from below inside the slab, mm^2 (the
// overhang stage drops pieces of less than its min_area: a slab estimated below that has
// none of its own). Facets leaning past a need support at any thickness and are left out, as
// are upward-facing and vertical ones. It sums facets, not pieces: many specks a slab apart
// count together.
class ThickOverhangEstimate {
 public:
  ThickOverhangEstimate(const Mesh& mesh, double overhang_angle_degrees, double bead_width);
  double operator()(double z_lo, double z_hi) const;

 private:
  struct Facet {
    double lean = 0;          // tan(phi)
    double area = 0;          // seen from below, mm^2
    double z[3] = {0, 0, 0};  // its corners' heights, ascending
    double area_below(double h) const;  // of the part below height h
  };
  std::vector<Facet> facets_;
  FacetsByHeight by_height_;
  double half_bead_ = 0;
};

}  // namespace geometry
