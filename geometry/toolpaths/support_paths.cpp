#include "geometry/toolpaths/support_paths.h"

#include <algorithm>
#include <cmath>

#include "geometry/core/clipper.h"
#include "geometry/toolpaths/bead_spacing.h"
#include "geometry/toolpaths/infill.h"
#include "geometry/toolpaths/zigzag.h"

namespace geometry {

namespace {

// Longest connector, in line spacings, of the body's zig-zags.
constexpr double kBodyConnector = 3;
// Support regions are straightened within this first (mm): where sparse lines end matters
// to tens of micrometres at most.
constexpr double kTolerance = 0.01;

// Lines `spacing` apart at `angle`, bead centres half a bead inside `area`.
std::vector<ExtrusionPath> lines_in(const Region& area, double width, double spacing, double angle,
                                    double connector, PathRole role) {
  if (!(width > 0) || !(spacing > 0) || area.loops.empty()) return {};
  const clipper::Paths clean = clipper::simplified(to_clipper(area), kTolerance);
  const Region fill = from_clipper(clean);
  const Region centres = from_clipper(clipper::offset(clean, -width / 2));
  if (centres.loops.empty()) return {};
  return zigzag(centres, ScanLines{angle, spacing, 0}, connector * spacing, &fill, role, width);
}

// A loop half a bead inside each island's edge (closed paths, outer loops CCW, holes CW),
// and what lies inside its bead, a bead in from the edge. An island narrower than a bead
// has neither.
struct Sheath {
  std::vector<ExtrusionPath> loops;
  clipper::Paths centre;  // inside the loop's centre line
  clipper::Paths inside;  // inside its bead
};

Sheath sheath_of(const clipper::Paths& island, double width, PathRole role) {
  Sheath sheath;
  sheath.centre = clipper::offset(island, -width / 2, ClipperLib::jtRound);
  for (const auto& path : sheath.centre) {
    ExtrusionPath loop;
    loop.role = role;
    loop.width = width;
    loop.points = from_clipper(path);
    if (loop.points.size() < 3) continue;
    loop.points.push_back(loop.points.front());
    sheath.loops.push_back(std::move(loop));
  }
  if (!sheath.loops.empty()) sheath.inside = clipper::offset(island, -width);
  return sheath;
}

// Per island a loop round the edge and lines
// `spacing` apart at `angle` from the loop's centre line to its centre line: the beads cover
// the island to its edge whatever its shape, and each line reaches, at both ends, whatever
// carries the loop (the ends of lines over sparse lines below land on the loop, which the
// widened contacts put over a body line). The lines are separate: a zig-zag's connectors
// would run half a bead inside the loop, off what carries it.
std::vector<ExtrusionPath> looped_lines_in(const Region& area, double width, double spacing,
                                           double angle, PathRole role) {
  std::vector<ExtrusionPath> result;
  if (!(width > 0) || !(spacing > 0)) return result;
  const clipper::Paths clean = clipper::simplified(to_clipper(area), kTolerance);
  for (const clipper::Paths& island : clipper::islands(clean)) {
    Sheath loop = sheath_of(island, width, role);
    if (loop.loops.empty()) continue;
    for (ExtrusionPath& path : loop.loops) result.push_back(std::move(path));
    auto lines = hatch(from_clipper(loop.centre), spacing, angle, role, width);
    result.insert(result.end(), std::make_move_iterator(lines.begin()),
                  std::make_move_iterator(lines.end()));
  }
  return result;
}

}  // namespace

std::vector<ExtrusionPath> support_body_paths(const Region& body, double width,
                                              const SupportPathOptions& o, const Region* carried) {
  std::vector<ExtrusionPath> paths;
  const clipper::Paths held = carried ? to_clipper(*carried) : clipper::Paths{};
  Region inside = body;
  if (o.sheath && width > 0 && o.spacing > 0) {
    // The sheath: a loop round each island, under the edges of what stands on it.
    inside.loops.clear();
    for (const clipper::Paths& island : clipper::islands(clipper::simplified(to_clipper(body), kTolerance))) {
      Sheath loop = sheath_of(island, width, PathRole::support);
      if (loop.loops.empty()) continue;  // narrower than a bead: nothing fits
      for (ExtrusionPath& path : loop.loops) {
        if (!carried) {
          paths.push_back(std::move(path));
          continue;
        }
        // Only the pieces of the loop that something below carries.
        ClipperLib::Path line;
        for (Vec2 p : path.points) line.push_back(to_clipper(p));
        for (const auto& piece : clipper::clip_open({line}, held)) {
          if (piece.size() < 2) continue;
          ExtrusionPath kept = path;
          kept.points = from_clipper(piece);
          paths.push_back(std::move(kept));
        }
      }
      const Region within = from_clipper(loop.inside);
      inside.loops.insert(inside.loops.end(), within.loops.begin(), within.loops.end());
    }
  }
  auto lines = lines_in(inside, width, o.spacing, o.angle, kBodyConnector, PathRole::support);
  paths.insert(paths.end(), std::make_move_iterator(lines.begin()), std::make_move_iterator(lines.end()));
  if (o.pattern == SupportPattern::grid) {
    auto across = lines_in(inside, width, o.spacing, o.angle + 90, kBodyConnector, PathRole::support);
    paths.insert(paths.end(), std::make_move_iterator(across.begin()),
                 std::make_move_iterator(across.end()));
  }
  return paths;
}

std::vector<ExtrusionPath> support_interface_paths(const Region& interface, double width,
                                                   double height, const SupportPathOptions& o) {
  const double density = std::clamp(o.interface_density, 1.0, 100.0);
  const double spacing = bead_spacing(width, height) * 100 / density;
  return looped_lines_in(interface, width, spacing, o.angle + 90, PathRole::support_interface);
}

std::vector<ExtrusionPath> raft_paths(const Region& area, RaftPart part, std::size_t index,
                                      double width, double height, const SupportPathOptions& o) {
  switch (part) {
    case RaftPart::base:
      return looped_lines_in(area, std::max(o.raft_base_width, height), o.raft_base_spacing, 0,
                             PathRole::raft);
    case RaftPart::interface:
      return looped_lines_in(area, width, o.raft_interface_spacing, 90, PathRole::raft);
    case RaftPart::surface: {
      // Solid, by shares, as a part's skin (toolpath_plan.h).
      const double share = bead_spacing(width, height);
      const clipper::Paths shrunk = clipper::offset(to_clipper(area), -(width - share) / 2);
      std::vector<ExtrusionPath> paths =
          solid_infill(from_clipper(shrunk), share, 45, index, PathRole::raft);
      for (ExtrusionPath& path : paths) {
        path.width = path.width == share ? width : bead_width_for_spacing(path.width, height);
      }
      return paths;
    }
  }
  return {};
}

}  // namespace geometry
