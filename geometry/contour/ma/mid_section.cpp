#include "geometry/contour/ma/mid_section.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "geometry/core/point_in_region.h"

namespace geometry::ma {

namespace {

constexpr double kSquareMicrometre = 1e6;  // Clipper areas are in nm^2

// 10 nm, in Clipper units (clipper.h).
constexpr double kCleanDistance = 10;

// A section's part inside the island's outline (`paths`, clipped to `outline`) as paths to add
// with positive winding: where the island is solid all round, the outline reversed takes that
// solid away first.
ClipperLib::Paths section_in_island(ClipperLib::Paths paths, const ClipperLib::Path& outline,
                                    bool solid_outside) {
  if (solid_outside) {
    ClipperLib::Path reversed = outline;
    ClipperLib::ReversePath(reversed);
    paths.push_back(std::move(reversed));
  }
  return paths;
}

}  // namespace

// A vertical wall's strip: one outer loop, one hole, and every point of the ring within four
// margins of both (a wall's ring is two margins wide). Checked as: the outline lies inside
// the hole grown by that much, and the outline shrunk by it inside the hole.
bool is_wall(const BoundaryPair& pair) {
  if (pair.inner.size() != 1) return false;
  // First the cheap test that rejects nearly every real strip: a wall's ring is on average
  // two margins wide (its area over its mean perimeter), and most rings are so much wider
  // that a bound on the perimeter tells.
  const double ring_area = signed_area(pair.outer) + signed_area(pair.inner[0]);
  const double length_bound = 0.5 * (perimeter_bound(pair.outer) + perimeter_bound(pair.inner[0]));
  if (ring_area > 3 * kFootprintMargin * length_bound) return false;
  const double mean_length = 0.5 * (perimeter(pair.outer) + perimeter(pair.inner[0]));
  if (!(mean_length > 0) || ring_area > 3 * kFootprintMargin * mean_length) return false;
  const double reach = 4 * kFootprintMargin;
  const ClipperLib::Path outline = to_clipper(pair.outer);
  ClipperLib::Path hole = to_clipper(pair.inner[0]);
  ClipperLib::ReversePath(hole);  // as a filled polygon
  // Round joins within an eighth of the reach (ClipperOffset's, its very points).
  const auto grown = [](const ClipperLib::Path& filled, double delta) {
    return clipper::library_offset({filled}, delta, ClipperLib::jtRound,
                                   ClipperLib::etClosedPolygon, std::abs(delta) / 8);
  };
  if (clipper::area_units2(clipper::difference({outline}, grown(hole, reach))) >
      kSquareMicrometre) {
    return false;
  }
  return clipper::area_units2(clipper::difference(grown(outline, -reach), {hole})) <=
         kSquareMicrometre;
}

// The same from the whole section.
ClipperLib::Paths section_in_island(const ClipperLib::Paths& section, const BoundaryPair& pair,
                                    bool solid_outside) {
  const ClipperLib::Path outline = to_clipper(pair.outer);
  return section_in_island(clipper::intersection(section, {outline}), outline, solid_outside);
}

// A cap: the mid section inside it; if the feature does not reach the middle (nothing of an
// empty-beside cap there, all of a solid-beside one, a cavity), the section half-way through
// the feature's own height range inside the slab.
ClipperLib::Paths cap_contour(const Slab& slab, const BoundaryPair& pair, bool solid_outside,
                              const ClipperLib::Paths& middle,
                              const std::function<Region(double z)>& cross_section) {
  const ClipperLib::Path outline = to_clipper(pair.outer);
  const double island = ClipperLib::Area(outline);
  ClipperLib::Paths middle_inside = clipper::intersection(middle, {outline});
  const double inside = clipper::area_units2(middle_inside);
  const bool reaches_middle = solid_outside ? std::abs(inside - island) > kSquareMicrometre
                                            : inside > kSquareMicrometre;
  if (reaches_middle) return section_in_island(std::move(middle_inside), outline, solid_outside);
  Region ring{{pair.outer}};
  ring.loops.insert(ring.loops.end(), pair.inner.begin(), pair.inner.end());
  double lo = slab.z_hi, hi = slab.z_lo;
  for (const auto& facet : slab.facets) {
    if (!point_in_region(ring, {facet[0].x, facet[0].y})) continue;
    for (const Vec3& v : facet) {
      lo = std::min(lo, v.z);
      hi = std::max(hi, v.z);
    }
  }
  if (!(lo < hi)) return section_in_island(middle, pair, solid_outside);
  return section_in_island(to_clipper(cross_section(0.5 * (lo + hi))), pair, solid_outside);
}

// `region` with the mid section taking its place inside `zone`: (region \ zone) ∪ (mid ∩ zone),
// in one Clipper operation, so that the two parts meet exactly along the zone's edges (two
// operations round their crossings apart and leave nanometre cracks there). Each input has
// winding 1 inside and 0 outside. Subject: region - zone > 0; clip: mid + zone - box > 0,
// the box reversed round everything. (About 3.8 M instructions a call, on 73 of the bunny's
// layers at 0.15 mm. Not taken: uniting only the region's loops near the zone's box and
// passing the others through. The point set would be the same, but the paths Clipper lists
// (their order, their first vertices) follow from all of its input, so the same output could
// not be shown.)
Region mid_inside(const ClipperLib::Paths& region, const ClipperLib::Paths& all_middle,
                  const ClipperLib::Paths& zone) {
  ClipperLib::IntRect bounds = clipper::bounding_box(zone);
  // Only the section's loops whose box meets the zone's: the others add no winding inside it.
  ClipperLib::Paths middle;
  for (const auto& path : all_middle) {
    if (clipper::boxes_meet(clipper::bounding_box(path), bounds)) middle.push_back(path);
  }
  clipper::add_to_box(bounds, clipper::bounding_box(middle));
  const ClipperLib::cInt lo_x = bounds.left, lo_y = bounds.top, hi_x = bounds.right,
                         hi_y = bounds.bottom;
  ClipperLib::Paths subject = region;
  for (ClipperLib::Path path : zone) {
    ClipperLib::ReversePath(path);
    subject.push_back(std::move(path));
  }
  ClipperLib::Paths clip = middle;
  clip.insert(clip.end(), zone.begin(), zone.end());
  clip.push_back({{lo_x - 1, lo_y - 1}, {lo_x - 1, hi_y + 1}, {hi_x + 1, hi_y + 1},
                  {hi_x + 1, lo_y - 1}});  // the box, clockwise
  ClipperLib::Paths joined = clipper::union_positive(subject, clip);
  // Where the mid section's walls meet the zone's edges a few nanometres from another vertex,
  // the crossing leaves edges of a nanometre or two: nothing a printer or a metric sees, but
  // slivers for a mesh made from the region (extruded_layers.h, CGAL's corefinement).
  ClipperLib::CleanPolygons(joined, kCleanDistance);
  ClipperLib::PolyTree tree;
  return from_clipper(clipper::union_nonzero_tree(joined, tree));
}

// Whether add_floating_features can find a feature in the island, read off the mid section's
// loops as they are, without the union that nests them: a loop inside the island's ring whose
// face (inside it, outside the loops nested in it) holds none of the island's boundary points.
// The section's loops lie on the surface inside the slab, so each lies inside one island's
// ring, at least the footprint margin from its edge; they are nested, never crossing, and
// the innermost holding a point is the one of least area that holds it. (One case reads
// differently: a section loop touching itself at a vertex exactly at mid height, which the
// union could split in two. That is answered as the loop, not as its two halves.)
bool may_float(const BoundaryPair& pair, const Region& middle) {
  const std::vector<const Loop*> boundaries = loops_of(pair);
  const std::size_t n = middle.loops.size();
  std::vector<char> anchored(n, 0);
  for (const Loop* boundary : boundaries) {
    const Vec2 p = (*boundary)[0];
    std::size_t innermost = n;
    double least = std::numeric_limits<double>::infinity();
    for (std::size_t k = 0; k < n; ++k) {
      if (winding_number(middle.loops[k], p) == 0) continue;
      const double a = std::abs(signed_area(middle.loops[k]));
      if (a < least) {
        least = a;
        innermost = k;
      }
    }
    if (innermost < n) anchored[innermost] = 1;
  }
  for (std::size_t k = 0; k < n; ++k) {
    if (anchored[k] || middle.loops[k].size() < 3) continue;
    int in_ring = 0;
    for (const Loop* boundary : boundaries) in_ring += winding_number(*boundary, middle.loops[k][0]);
    if (in_ring != 0) return true;
  }
  return false;
}

// Floating features of an island (mid_section.h): the faces of the mid section
// (solid: an outer loop less its holes; empty: a hole less the outer loops inside it) that are
// bounded by a loop inside the island's footprint and hold none of the island's loops (a loop
// is held where its free face is: a point of it lies in the face). `middle` is the section's
// nesting (Clipper's PolyTree); the faces go to `zones`, as paths with winding 1 inside.
void add_floating_features(const BoundaryPair& pair, const ClipperLib::PolyTree& middle,
                           ClipperLib::Paths& zones, MaStats* stats) {
  Region ring{{pair.outer}};
  ring.loops.insert(ring.loops.end(), pair.inner.begin(), pair.inner.end());
  const std::vector<const Loop*> boundaries = loops_of(pair);
  for (const ClipperLib::PolyNode* node = middle.GetFirst(); node; node = node->GetNext()) {
    if (node->Contour.size() < 3 || !point_in_region(ring, from_clipper(node->Contour[0]))) continue;
    // The face: inside the node's loop, outside its children's.
    const Region outline{{from_clipper(node->Contour)}};
    std::vector<Region> children;
    for (const ClipperLib::PolyNode* child : node->Childs) children.push_back({{from_clipper(child->Contour)}});
    bool anchored = false;
    for (const Loop* boundary : boundaries) {
      const Vec2 p = (*boundary)[0];
      if (!point_in_region(outline, p)) continue;
      bool in_child = false;
      for (const Region& child : children) in_child = in_child || point_in_region(child, p);
      anchored = anchored || !in_child;
    }
    if (anchored) continue;
    // Winding 1 inside the face: the node's loop counter-clockwise, its children clockwise.
    ClipperLib::Path outer = node->Contour;
    if (!ClipperLib::Orientation(outer)) ClipperLib::ReversePath(outer);
    zones.push_back(std::move(outer));
    for (const ClipperLib::PolyNode* child : node->Childs) {
      ClipperLib::Path hole = child->Contour;
      if (ClipperLib::Orientation(hole)) ClipperLib::ReversePath(hole);
      zones.push_back(std::move(hole));
    }
    if (stats) ++stats->features;
  }
}

}  // namespace geometry::ma
