#include "geometry/slab/boundary_pair.h"

#include <algorithm>

#include "geometry/core/clipper.h"

namespace geometry {

namespace {

Loop oriented(const ClipperLib::Path& path, bool counter_clockwise) {
  ClipperLib::Path copy = path;
  if (ClipperLib::Orientation(copy) != counter_clockwise) ClipperLib::ReversePath(copy);
  return from_clipper(copy);
}

}  // namespace

std::vector<BoundaryPair> boundary_pairs(const Region& footprint) {
  std::vector<BoundaryPair> pairs;
  if (footprint.loops.empty()) return pairs;
  ClipperLib::PolyTree tree;
  return boundary_pairs(clipper::union_nonzero_tree(to_clipper(footprint), tree));
}

std::vector<BoundaryPair> boundary_pairs(const ClipperLib::PolyTree& tree) {
  std::vector<BoundaryPair> pairs;
  for (const ClipperLib::PolyNode* node = tree.GetFirst(); node; node = node->GetNext()) {
    if (node->IsHole() || node->IsOpen()) continue;
    BoundaryPair pair;
    pair.outer = oriented(node->Contour, true);
    for (const ClipperLib::PolyNode* hole : node->Childs) {
      pair.inner.push_back(oriented(hole->Contour, false));
    }
    pairs.push_back(std::move(pair));
  }
  return pairs;
}

std::vector<const Loop*> loops_of(const BoundaryPair& pair) {
  std::vector<const Loop*> loops{&pair.outer};
  for (const Loop& hole : pair.inner) loops.push_back(&hole);
  return loops;
}

int winding_number(const Loop& loop, Vec2 p) {
  int w = 0;
  for (std::size_t i = 0, n = loop.size(); i < n; ++i) {
    const Vec2 a = loop[i], b = loop[i + 1 == n ? 0 : i + 1];
    // Wholly above or below p: the edge neither crosses p's ray nor holds p.
    if ((a.y < p.y && b.y < p.y) || (a.y > p.y && b.y > p.y)) continue;
    const double side = cross(b - a, p - a);
    if (side == 0 && distance_to_segment(p, a, b) == 0) {
      return signed_area(loop) >= 0 ? 1 : -1;
    }
    if (a.y <= p.y) {
      if (b.y > p.y && side > 0) ++w;
    } else if (b.y <= p.y && side < 0) {
      --w;
    }
  }
  return w;
}

bool point_in_region(const Region& region, Vec2 p) {
  int w = 0;
  for (const Loop& loop : region.loops) w += winding_number(loop, p);
  return w != 0;
}

std::vector<char> solid_beside(const BoundaryPair& pair, const Region& section) {
  std::vector<char> solid;
  for (const Loop* loop : loops_of(pair)) {
    const std::size_t n = loop->size();
    const std::size_t votes = std::min<std::size_t>(5, n);
    std::size_t inside = 0, outside = 0;  // votes counted until they make a majority
    for (std::size_t k = 0; k < votes && 2 * inside <= votes && 2 * outside < votes; ++k) {
      ++(point_in_region(section, (*loop)[k * n / votes]) ? inside : outside);
    }
    solid.push_back(2 * inside > votes ? 1 : 0);
  }
  return solid;
}

}  // namespace geometry
