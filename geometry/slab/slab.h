// The slab of a layer and its footprint (paper §3.2.1, §3.3 step 1; DESIGN.md §2, §6).
//
// Input: a layer stack and a layer index (or a mesh, the indices of the faces to consider and
// the layer's bounds z_lo < z_hi, mm).
// Output: Slab, the mesh's faces clipped to [z_lo, z_hi], each a convex polygon of 3-5
// vertices in the face's orientation (counter-clockwise seen from outside), mm.
//
// What lies on the slab's bounding planes is left out: a face, or a clipped piece, of zero
// height at z_lo or z_hi (a horizontal face there, a face touching the plane along an edge)
// bounds the slab rather than lies in it. So the underside of a T's bar that begins exactly at
// z_lo is not a strip of the layer, and the layer above a cube's top is empty. Horizontal faces
// strictly inside the slab stay.
//
// slab_footprint: the union of the facets' projections to XY, the region the model's surface
// covers inside the slab, which the boundary pair bounds (boundary_pair.h), grown by `margin`
// (a mitred offset: every point within `margin` of the projection is in, none much farther).
// The margin is not optional: a vertical wall projects to a segment of zero area, and the raw
// union pinches wherever lower and upper contours touch (DESIGN.md §6: 68 398 pieces over
// the bunny, no rings). With it a vertical wall is a ring 2 * margin wide round the wall, and
// every point just outside the footprint is at least `margin` from the surface, so which side
// is solid can be read there (boundary_pair.h). Facets thinner than 10 nm across in
// projection count as seen edge-on. Bunny, 334 layers at 0.15 mm: 452 islands, 449 holes.
// Cost: one Clipper union, of the facets' boundary chains grown as they stand (slab.cpp says
// why that is the grown union of the projections, to a unit along the boundary); bunny best
// slice at 0.15 mm: 1.09 G instructions of 11.69 G, where the chains' own union before
// growing them cost 0.55 G more (and gave 4% fewer footprint vertices, which the medial
// axis spends 0.12 G on).
// Empty slab: empty footprint. The result is a valid Region (outer loops CCW, holes CW).
#pragma once

#include <cstddef>
#include <cstdint>
#include <initializer_list>
#include <iterator>
#include <span>
#include <vector>

#include "geometry/slab/boundary_pair.h"
#include "geometry/slicing/layer_stack.h"
#include "geometry/mesh/mesh.h"
#include "geometry/core/polygon.h"

namespace geometry {

// A slab's facets, all their corners in one array: facets[i] is the span of facet i's corners.
// One allocation for the lot, where a vector a facet made slab_of allocate (and its reader
// free) once for each of the bunny's 246 509 layer facets (53 M instructions of operator new
// alone in the best slice at 0.15 mm).
class SlabFacets {
 public:
  class const_iterator {
   public:
    using value_type = std::span<const Vec3>;
    using difference_type = std::ptrdiff_t;
    using iterator_category = std::forward_iterator_tag;
    const_iterator() = default;
    const_iterator(const SlabFacets* facets, std::size_t i) : facets_(facets), i_(i) {}
    std::span<const Vec3> operator*() const { return (*facets_)[i_]; }
    const_iterator& operator++() {
      ++i_;
      return *this;
    }
    const_iterator operator++(int) {
      const_iterator before = *this;
      ++i_;
      return before;
    }
    bool operator==(const const_iterator& other) const { return i_ == other.i_; }

   private:
    const SlabFacets* facets_ = nullptr;
    std::size_t i_ = 0;
  };

  std::size_t size() const { return ends_.size(); }
  bool empty() const { return ends_.empty(); }
  std::span<const Vec3> operator[](std::size_t i) const {
    const std::size_t from = i == 0 ? 0 : ends_[i - 1];
    return {corners_.data() + from, ends_[i] - from};
  }
  const_iterator begin() const { return {this, 0}; }
  const_iterator end() const { return {this, size()}; }

  void push_back(std::span<const Vec3> corners) {
    corners_.insert(corners_.end(), corners.begin(), corners.end());
    ends_.push_back(static_cast<std::uint32_t>(corners_.size()));
  }
  void push_back(std::initializer_list<Vec3> corners) {
    push_back(std::span<const Vec3>(corners.begin(), corners.size()));
  }
  // Room for `facets` facets of `corners` corners in all.
  void reserve(std::size_t facets, std::size_t corners) {
    ends_.reserve(facets);
    corners_.reserve(corners);
  }

 private:
  std::vector<Vec3> corners_;
  std::vector<std::uint32_t> ends_;  // one past each facet's last corner in corners_
};

struct Slab {
  double z_lo = 0, z_hi = 0;
  SlabFacets facets;
};

// 2 um: far below what any extruder resolves, far above the slicer's rounding (1 nm units).
inline constexpr double kFootprintMargin = 0.002;

Slab slab_of(const LayerStack& stack, std::size_t layer);

// The same from a mesh and candidate faces (any superset of those meeting the slab).
Slab slab_of(const Mesh& mesh, std::span<const std::uint32_t> faces, double z_lo, double z_hi);

// Whether every facet of a non-empty slab is seen edge-on from above (thinner than 10 nm
// across in projection, as the footprint counts them): a prism, whose walls stand straight up
// through the whole slab, so that its section is the same at every height (a wall that
// leaned or stepped inside it would need a facet that does not). No horizontal face either:
// one inside the slab is seen face-on, and one on its planes is not in it (above).
bool is_prism(const Slab& slab);

// One convex polygon clipped to z_lo <= z <= z_hi, orientation kept, repeated points merged;
// empty if fewer than 3 points remain or the piece lies in the plane z_lo or z_hi.
std::vector<Vec3> clip_to_slab(std::span<const Vec3> polygon, double z_lo, double z_hi);

Region slab_footprint(const Slab& slab, double margin = kFootprintMargin);

// Only the islands: boundary_pairs(slab_footprint(slab, margin)) from Clipper's nesting of the
// offset, without the Region and without the second union boundary_pairs(Region) runs.
std::vector<BoundaryPair> slab_islands(const Slab& slab, double margin = kFootprintMargin);

}  // namespace geometry
