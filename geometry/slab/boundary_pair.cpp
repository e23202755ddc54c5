#include "geometry/slab/boundary_pair.h"

#include <algorithm>

#include "geometry/core/clipper.h"
#include "geometry/core/point_in_region.h"

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
