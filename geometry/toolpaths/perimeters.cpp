#include "geometry/toolpaths/perimeters.h"

#include <cmath>

#include "geometry/core/clipper_specks.h"
#include "geometry/toolpaths/thin_walls.h"

namespace geometry {

namespace {

// A loop with less length than this is a speck left by the offset, not a printable wall;
// dropping it leaves its area to the thin-wall pass, which covers it if it is wide enough.
constexpr double kMinLoopLength = 0.5;  // in bead widths
// A gap with less area than this is a speck of the offsets, not a wall to print.
constexpr double kMinGapArea = 1.0 / 16;  // in bead widths squared
// The loops' beads are taken as covering what they do within this, for finding gaps (mm).
constexpr double kCoverTolerance = 0.01;

ExtrusionPath closed_path(const ClipperLib::Path& path, PathRole role, double width) {
  ExtrusionPath result;
  result.role = role;
  result.width = width;
  result.points = from_clipper(path);
  result.points.push_back(result.points.front());
  return result;
}

}  // namespace

Perimeters perimeters(const Region& island, double width, int count) {
  return perimeters(clipper::union_nonzero(to_clipper(island)), width, count);
}

Perimeters perimeters(const ClipperLib::Paths& whole, double width, int count) {
  Perimeters result;
  if (!(width > 0) || count <= 0) {
    if (count <= 0) result.infill_area = from_clipper(whole);
    return result;
  }
  // Morphology makes every level an offset of the island by whole beads: the space left
  // inside k loops is the island shrunk by k w (shrinking an opening by at least its radius
  // is shrinking the original), so each level costs three offsets, none of the chain
  // of loop, inside of loop, core of the next that following the loops would.
  //   inside: the island shrunk by k w, the space loop k is laid in;
  //   core: shrunk by (k + 1) w, where loop k's centre may go with half a bead to spare on
  //         either side; it is the next level's inside.
  clipper::Paths inside = whole, core = clipper::offset(whole, -width);
  // gaps: what the loops' beads leave of the space each was laid in (inside), taking a
  // bead's convex corners as cut square at half a bead from the centre line: a bead rounds
  // them, and a corner sharper than about 60 degrees leaves a sliver worth a gap fill, one
  // blunter a speck. The bead is taken 10 um wider (its straightened centre line, 10 um, is
  // what it is grown from), so that where there is no gap its edge does not run along the
  // edge of the space, which would cost the difference a crossing at every vertex.
  clipper::Paths gaps;
  // The difference is mostly specks along the edge where the offsets round off short
  // edges; a piece of wall to print has at least a sixteenth of a bead square of area.
  const double min_gap = kMinGapArea * width * width * kClipperScale * kClipperScale;
  int made = 0;
  for (int k = 0; k < count && !core.empty(); ++k) {
    // The loop's centre line runs w/2 inside what is left, except where that is narrower
    // than two beads and the loop's two sides would overlap (or at best touch with nothing
    // between): the core grown back by w/2 (an opening), which those parts do not survive;
    // they are left to the gap fill, which lays one bead there or two side by side. The
    // opening is mitred, so that corners stay sharp, with the smallest mitre limit (2):
    // where the core pinched to a point, a mitre pokes out towards the edge, at most w/2
    // further than a round join would.
    clipper::Paths loops = clipper::offset(core, width / 2, ClipperLib::jtMiter, 2.0);
    // Summed only until it reaches the least length: a sum of lengths never falls as it goes
    // on, in floating point too, so a loop is kept exactly where its whole length would be.
    const double least = kMinLoopLength * width;
    std::erase_if(loops, [&](const ClipperLib::Path& path) {
      double length = 0;
      for (std::size_t i = 0; i < path.size() && length < least; ++i) {
        const Vec2 d = from_clipper(path[(i + 1) % path.size()]) - from_clipper(path[i]);
        length += std::hypot(d.x, d.y);
      }
      return length < least;
    });
    if (loops.empty()) break;
    std::vector<ExtrusionPath> level;
    const PathRole role = k == 0 ? PathRole::outer_wall : PathRole::inner_wall;
    for (const auto& path : loops) level.push_back(closed_path(path, role, width));
    result.walls.push_back(std::move(level));
    const clipper::Paths bead = clipper::offset(clipper::simplified(loops, kCoverTolerance),
                                      width / 2 + kCoverTolerance, ClipperLib::jtSquare);
    // What the bead leaves of the space it was laid in; nothing where every path of that is
    // proven a speck (under min_gap), which drop_specks below would drop, each path on its own
    // before anything else is done with them: the same gaps are left without the difference.
    if (!clipper::proven_specks(inside, bead, min_gap)) {
      const clipper::Paths gap = clipper::difference(inside, bead);
      gaps.insert(gaps.end(), gap.begin(), gap.end());
    }
    ++made;
    inside = std::move(core);
    if (k + 1 < count) core = clipper::offset(inside, -width);
  }
  // Infill goes inside the last of `count` loops; if fewer fit, what they leave is gap.
  clipper::Paths infill;
  if (made == count) {
    infill = std::move(inside);
  } else {
    gaps.insert(gaps.end(), inside.begin(), inside.end());
  }
  // Slivers narrower than a quarter bead are offset noise, not walls.
  auto drop_specks = [&] {
    std::erase_if(gaps, [&](const auto& path) { return std::abs(ClipperLib::Area(path)) < min_gap; });
  };
  drop_specks();
  gaps = clipper::opening(gaps, width / 8);
  drop_specks();
  if (!gaps.empty()) {
    const Region island = from_clipper(whole);
    result.thin_walls = thin_walls(from_clipper(gaps), width / 4, 2 * width, 1.5 * width, &island);
  }
  result.infill_area = from_clipper(infill);
  return result;
}

}  // namespace geometry
