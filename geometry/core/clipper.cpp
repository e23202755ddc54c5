// The Clipper layer's conversions and booleans (clipper.h); its offset is clipper_offset.cpp.
#include "geometry/core/clipper.h"

#include <algorithm>
#include <limits>

#include "geometry/core/clipper_engine.h"
#include "geometry/core/douglas_peucker.h"

namespace geometry {

namespace {

// One conversion for both grids.
ClipperLib::IntPoint to_grid(Vec2 p, double scale) {
  return {rounded_units(p.x * scale), rounded_units(p.y * scale)};
}

Vec2 from_grid(const ClipperLib::IntPoint& p, double scale) {
  return {static_cast<double>(p.X) / scale, static_cast<double>(p.Y) / scale};
}

ClipperLib::Path to_grid(const Loop& loop, double scale) {
  ClipperLib::Path path;
  path.reserve(loop.size());
  for (Vec2 p : loop) path.push_back(to_grid(p, scale));
  return path;
}

ClipperLib::Paths to_grid(const Region& region, double scale) {
  ClipperLib::Paths paths;
  paths.reserve(region.loops.size());
  for (const Loop& loop : region.loops) paths.push_back(to_grid(loop, scale));
  return paths;
}

}  // namespace

ClipperLib::IntPoint to_clipper(Vec2 p) { return to_grid(p, kClipperScale); }
Vec2 from_clipper(const ClipperLib::IntPoint& p) { return from_grid(p, kClipperScale); }
ClipperLib::Path to_clipper(const Loop& loop) { return to_grid(loop, kClipperScale); }
ClipperLib::Paths to_clipper(const Region& region) { return to_grid(region, kClipperScale); }

ClipperLib::Path to_fine_clipper(const Loop& loop) { return to_grid(loop, kFineClipperScale); }
ClipperLib::Paths to_fine_clipper(const Region& region) {
  return to_grid(region, kFineClipperScale);
}
Vec2 from_fine_clipper(const ClipperLib::IntPoint& p) { return from_grid(p, kFineClipperScale); }

Loop from_clipper(const ClipperLib::Path& path) {
  Loop loop;
  loop.reserve(path.size());
  for (const auto& p : path) loop.push_back(from_clipper(p));
  return loop;
}

Region from_clipper(const ClipperLib::Paths& paths) {
  Region region;
  region.loops.reserve(paths.size());
  for (const auto& path : paths) region.loops.push_back(from_clipper(path));
  return region;
}

Region from_clipper(const ClipperLib::PolyTree& tree) {
  Region region;
  for (const ClipperLib::PolyNode* node = tree.GetFirst(); node; node = node->GetNext()) {
    if (node->IsOpen()) continue;
    ClipperLib::Path path = node->Contour;
    // Outer boundaries and islands CCW, holes CW, whatever orientation Clipper returned.
    if (ClipperLib::Orientation(path) == node->IsHole()) ClipperLib::ReversePath(path);
    region.loops.push_back(from_clipper(path));
  }
  return region;
}

namespace clipper {

namespace {

template <class Result>
void boolean(const Paths& a, const Paths& b, ClipperLib::ClipType type,
             ClipperLib::PolyFillType fill, Result& result) {
  ReusedEngine engine;
  engine->AddPaths(a, ClipperLib::ptSubject, true);
  engine->AddPaths(b, ClipperLib::ptClip, true);
  engine->Execute(type, result, fill, fill);
}

Paths boolean(const Paths& a, const Paths& b, ClipperLib::ClipType type,
              ClipperLib::PolyFillType fill) {
  Paths result;
  boolean(a, b, type, fill, result);
  return result;
}

// The loops of `paths` whose boxes meet `box`: `paths` itself when all do, else those copied
// into `kept`. A loop's winding counts only inside its box, so a loop clear of the other
// operand's box neither adds to an intersection nor takes from a difference; left out, it
// costs the sweep nothing (an island's booleans against a whole layer's regions meet its own
// neighbourhood only).
const Paths& meeting(const Paths& paths, const ClipperLib::IntRect& box, Paths& kept) {
  std::vector<char> near(paths.size());
  std::size_t count = 0;
  for (std::size_t i = 0; i < paths.size(); ++i) {
    near[i] = boxes_meet(bounding_box(paths[i]), box);
    count += near[i];
  }
  if (count == paths.size()) return paths;
  kept.reserve(count);
  for (std::size_t i = 0; i < paths.size(); ++i) {
    if (near[i]) kept.push_back(paths[i]);
  }
  return kept;
}

}  // namespace

Paths intersection(const Paths& a, const Paths& b) {
  if (a.empty() || b.empty()) return {};
  Paths kept_a, kept_b;
  const Paths& a_near = meeting(a, bounding_box(b), kept_a);
  if (a_near.empty()) return {};
  const Paths& b_near = meeting(b, bounding_box(a_near), kept_b);
  if (b_near.empty()) return {};
  return boolean(a_near, b_near, ClipperLib::ctIntersection, ClipperLib::pftNonZero);
}

Paths difference(const Paths& a, const Paths& b) {
  if (a.empty()) return {};
  if (b.empty()) return a;
  // Swept even when nothing of b is near: the result is `a` cleaned as the sweep cleans it.
  Paths kept;
  return boolean(a, meeting(b, bounding_box(a), kept), ClipperLib::ctDifference,
                 ClipperLib::pftNonZero);
}

Paths symmetric_difference(const Paths& a, const Paths& b) {
  return boolean(a, b, ClipperLib::ctXor, ClipperLib::pftNonZero);
}

Paths union_nonzero(const Paths& a, const Paths& b) {
  return boolean(a, b, ClipperLib::ctUnion, ClipperLib::pftNonZero);
}

PolyTree& union_nonzero_tree(const Paths& paths, PolyTree& tree) {
  boolean(paths, {}, ClipperLib::ctUnion, ClipperLib::pftNonZero, tree);
  return tree;
}

Paths union_positive(const Paths& a, const Paths& b) {
  return boolean(a, b, ClipperLib::ctUnion, ClipperLib::pftPositive);
}

PolyTree& union_positive_tree(const Paths& paths, PolyTree& tree) {
  boolean(paths, {}, ClipperLib::ctUnion, ClipperLib::pftPositive, tree);
  return tree;
}

Paths clip_open(const Paths& lines, const Paths& region) {
  if (lines.empty() || region.empty()) return {};
  ReusedEngine engine;
  engine->AddPaths(lines, ClipperLib::ptSubject, false);
  engine->AddPaths(region, ClipperLib::ptClip, true);
  PolyTree tree;
  engine->Execute(ClipperLib::ctIntersection, tree, ClipperLib::pftNonZero,
                 ClipperLib::pftNonZero);
  Paths result;
  ClipperLib::OpenPathsFromPolyTree(tree, result);
  return result;
}

Paths clip_open_joined(const Paths& lines, const Paths& region) {
  Paths pieces = clip_open(lines, region);
  for (std::size_t a = 0; a < pieces.size(); ++a) {
    for (std::size_t b = 0; b < pieces.size(); ++b) {
      if (a == b || pieces[a].empty() || pieces[b].empty()) continue;
      if (pieces[a].front() == pieces[a].back()) break;  // a whole loop already
      if (pieces[b].front() == pieces[b].back()) continue;
      if (pieces[a].back() != pieces[b].front()) {  // turned so that a ends where b begins
        if (pieces[a].back() == pieces[b].back()) {
          std::reverse(pieces[b].begin(), pieces[b].end());
        } else if (pieces[a].front() == pieces[b].back()) {
          std::swap(pieces[a], pieces[b]);
        } else if (pieces[a].front() == pieces[b].front()) {
          std::reverse(pieces[a].begin(), pieces[a].end());
        } else {
          continue;
        }
      }
      pieces[a].insert(pieces[a].end(), pieces[b].begin() + 1, pieces[b].end());
      pieces[b].clear();
      b = static_cast<std::size_t>(-1);  // look again from the start: the joined piece may join on
    }
  }
  std::erase_if(pieces, [](const Path& piece) { return piece.empty(); });
  return pieces;
}

std::vector<Paths> islands(const Paths& region) {
  std::vector<Paths> result;
  if (region.empty()) return result;
  // Loops apart, each simple (most of a layer's sections): each its own island.
  if (islands_of_loops_apart(region, result)) return result;
  PolyTree tree;
  return islands(union_nonzero_tree(region, tree));
}

std::vector<Paths> islands(const PolyTree& tree) {
  std::vector<Paths> result;
  for (const ClipperLib::PolyNode* node = tree.GetFirst(); node; node = node->GetNext()) {
    if (node->IsHole() || node->IsOpen()) continue;
    Paths island{node->Contour};
    if (!ClipperLib::Orientation(island.front())) ClipperLib::ReversePath(island.front());
    for (const ClipperLib::PolyNode* hole : node->Childs) {
      island.push_back(hole->Contour);
      if (ClipperLib::Orientation(island.back())) ClipperLib::ReversePath(island.back());
    }
    result.push_back(std::move(island));
  }
  return result;
}

Paths library_offset(const Paths& paths, double delta, ClipperLib::JoinType join,
                     ClipperLib::EndType end, double arc_tolerance, double miter_limit) {
  ClipperLib::ClipperOffset engine(miter_limit, arc_tolerance * kClipperScale);
  engine.AddPaths(paths, join, end);
  Paths result;
  engine.Execute(result, delta * kClipperScale);
  return result;
}

namespace {

// A point in units as doubles (exact below 2^53 units): squared distances in nm^2 overflow
// int64.
Vec2 in_units(const IntPoint& p) { return {double(p.X), double(p.Y)}; }

}  // namespace

Paths simplified(const Paths& region, double tolerance) {
  const double limit2 = tolerance * kClipperScale * tolerance * kClipperScale;
  Paths result;
  result.reserve(region.size());
  for (const Path& path : region) {
    const std::size_t n = path.size();
    if (n < 3) continue;
    const std::vector<char> keep =
        douglas_peucker_keep(n, limit2, [&](std::size_t i, std::size_t a, std::size_t b) {
          return squared_distance_to_segment(in_units(path[i]), in_units(path[a]),
                                             in_units(path[b]));
        });
    Path kept;
    for (std::size_t i = 0; i < n; ++i) {
      if (keep[i]) kept.push_back(path[i]);
    }
    if (kept.size() >= 3) result.push_back(std::move(kept));
  }
  return result;
}

ClipperLib::IntRect bounding_box(const Path& path) {
  constexpr ClipperLib::cInt kMax = std::numeric_limits<ClipperLib::cInt>::max();
  ClipperLib::IntRect box{kMax, kMax, -kMax, -kMax};
  for (const IntPoint& p : path) {
    box.left = std::min(box.left, p.X);
    box.top = std::min(box.top, p.Y);
    box.right = std::max(box.right, p.X);
    box.bottom = std::max(box.bottom, p.Y);
  }
  return box;
}

ClipperLib::IntRect bounding_box(const Paths& paths) {
  ClipperLib::IntRect box = bounding_box(Path{});
  for (const Path& path : paths) add_to_box(box, bounding_box(path));
  return box;
}

void add_to_box(ClipperLib::IntRect& box, const ClipperLib::IntRect& other) {
  box = {std::min(box.left, other.left), std::min(box.top, other.top),
         std::max(box.right, other.right), std::max(box.bottom, other.bottom)};
}

double area_units2(const Paths& paths) {
  double total = 0;
  for (const Path& path : paths) total += ClipperLib::Area(path);
  return total;
}

double area_mm2(const Paths& region) {
  return area_units2(region) / (kClipperScale * kClipperScale);
}

}  // namespace clipper

}  // namespace geometry
