#include "geometry/toolpaths/support_paths.h"

#include <algorithm>
#include <cmath>

#include "geometry/core/clipper_bridge.h"
#include "geometry/core/toolpath_clipper.h"
#include "geometry/toolpaths/bead_spacing.h"
#include "geometry/toolpaths/infill.h"
#include "geometry/toolpaths/perimeters.h"
#include "geometry/toolpaths/zigzag.h"

namespace geometry {

namespace {

namespace tc = toolpath_clipper;

// Longest connector, in line spacings, of the body's and the interface's zig-zags.
constexpr double kBodyConnector = 3;
constexpr double kInterfaceConnector = 2;
// Support regions are straightened within this first (mm): where sparse lines end matters
// to tens of micrometres at most.
constexpr double kTolerance = 0.01;

// Lines `spacing` apart at `angle`, bead centres half a bead inside `area`.
std::vector<ExtrusionPath> lines_in(const Region& area, double width, double spacing, double angle,
                                    double connector, PathRole role) {
  if (!(width > 0) || !(spacing > 0) || area.loops.empty()) return {};
  const tc::Paths clean = tc::simplified(to_clipper(area), kTolerance);
  const Region fill = from_clipper(clean);
  const Region centres = from_clipper(tc::offset(clean, -width / 2));
  if (centres.loops.empty()) return {};
  return zigzag(centres, ScanLines{angle, spacing, 0}, connector * spacing, &fill, role, width);
}

}  // namespace

std::vector<ExtrusionPath> support_body_paths(const Region& body, double width,
                                              const SupportPathOptions& o) {
  std::vector<ExtrusionPath> paths =
      lines_in(body, width, o.spacing, o.angle, kBodyConnector, PathRole::support);
  if (o.pattern == SupportPattern::grid) {
    auto across = lines_in(body, width, o.spacing, o.angle + 90, kBodyConnector, PathRole::support);
    paths.insert(paths.end(), std::make_move_iterator(across.begin()),
                 std::make_move_iterator(across.end()));
  }
  return paths;
}

std::vector<ExtrusionPath> support_interface_paths(const Region& interface, double width,
                                                   double height, const SupportPathOptions& o) {
  const double density = std::clamp(o.interface_density, 1.0, 100.0);
  const double spacing = bead_spacing(width, height) * 100 / density;
  std::vector<ExtrusionPath> result;
  const tc::Paths clean = tc::simplified(to_clipper(interface), kTolerance);
  for (const tc::Paths& island : tc::islands(clean)) {
    // A loop round the edge (and a centre line where the island is too narrow for one),
    // then lines inside it; their ends reach the loop.
    Perimeters loop = perimeters(island, width, 1);
    if (!loop.walls.empty()) {
      loop.thin_walls.insert(loop.thin_walls.end(), loop.walls[0].begin(), loop.walls[0].end());
    }
    for (ExtrusionPath& path : loop.thin_walls) {
      path.role = PathRole::support_interface;
      result.push_back(std::move(path));
    }
    if (loop.infill_area.loops.empty()) continue;
    const Region centres = from_clipper(tc::offset(to_clipper(loop.infill_area), -width / 2));
    if (centres.loops.empty()) continue;
    auto lines = zigzag(centres, ScanLines{o.angle + 90, spacing, 0}, kInterfaceConnector * spacing,
                        &loop.infill_area, PathRole::support_interface, width);
    result.insert(result.end(), std::make_move_iterator(lines.begin()),
                  std::make_move_iterator(lines.end()));
  }
  return result;
}

std::vector<ExtrusionPath> raft_paths(const Region& area, RaftPart part, std::size_t index,
                                      double width, double height, const SupportPathOptions& o) {
  switch (part) {
    case RaftPart::base:
      return lines_in(area, std::max(o.raft_base_width, height), o.raft_base_spacing, 0,
                      kBodyConnector, PathRole::raft);
    case RaftPart::interface:
      return lines_in(area, width, o.raft_interface_spacing, 90, kInterfaceConnector,
                      PathRole::raft);
    case RaftPart::surface: {
      // Solid, by shares, as a part's skin (toolpath_plan.h).
      const double share = bead_spacing(width, height);
      const tc::Paths shrunk = tc::offset(to_clipper(area), -(width - share) / 2);
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
