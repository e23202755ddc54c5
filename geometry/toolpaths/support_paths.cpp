#include "geometry/toolpaths/support_paths.h"

#include <algorithm>
#include <cmath>

#include "geometry/core/clipper.h"
#include "geometry/toolpaths/bead_spacing.h"
#include "geometry/toolpaths/infill.h"
#include "geometry/toolpaths/zigzag.h"

namespace geometry {

namespace {

// Longest connector, in line spacings, of the body's zig-zags: along an edge at less than
// 30 degrees to the lines a connector carries nothing the lines do not (the bunny at three:
// 0.603 m of support filament, at two 0.577 m, unsupported 208.9 and 208.6 mm; at one and a
// half 0.561 m but 220.6 mm, the connectors across the lines carry the interface's loop).
constexpr double kBodyConnector = 2;
// Support regions are straightened within this first (mm): where sparse lines end matters
// to tens of micrometres at most.
constexpr double kTolerance = 0.01;

// A loop half a bead inside each island's edge (closed paths, outer loops CCW, holes CW).
// An island narrower than a bead has none.
struct Sheath {
  std::vector<ExtrusionPath> loops;
  clipper::Paths centre;  // inside the loop's centre line
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

// The stretches of a sheath loop (closed, first point repeated last, the region on its
// left: outer loops CCW, holes CW) that the body's lines at `angle`, `spacing` apart, do
// not stand in for: those that run along them (within 45 degrees) farther than a quarter
// bead from the nearest line on the region's side (a line on the other side lies outside
// the lines' centre area: it is not laid). Across the lines, what stands on the edge
// bridges from line to line (and the zig-zags' connectors run there); on a line laid, the
// line carries it. The whole loop, closed, if every stretch is kept.
std::vector<ExtrusionPath> along_the_lines(const ExtrusionPath& loop, double angle, double spacing) {
  const std::size_t n = loop.points.size();
  if (n < 3) return {};
  const ScanFrame frame(angle);
  const double on_line = loop.width / 4, inward = 1e-6;
  std::vector<char> kept(n - 1);
  for (std::size_t i = 0; i + 1 < n; ++i) {
    const Vec2 a = frame.into(loop.points[i]), b = frame.into(loop.points[i + 1]);
    if (std::abs(b.y - a.y) > std::abs(b.x - a.x)) continue;  // across the lines
    // The nearest line on the region's side (+y when going +x) of each end.
    const bool up = b.x > a.x;
    auto line_in = [&](double y) {
      return up ? std::ceil((y - inward) / spacing) : std::floor((y + inward) / spacing);
    };
    const double k = line_in(a.y);
    const bool on = k == line_in(b.y) && std::abs(k * spacing - a.y) <= on_line &&
                    std::abs(k * spacing - b.y) <= on_line;
    kept[i] = !on;
  }
  std::vector<ExtrusionPath> result;
  const auto first_dropped = std::find(kept.begin(), kept.end(), 0);
  if (first_dropped == kept.end()) return {loop};
  // From the first dropped stretch round the loop, so that no run is cut at the seam.
  const std::size_t start = static_cast<std::size_t>(first_dropped - kept.begin());
  ExtrusionPath run;
  run.role = loop.role;
  run.width = loop.width;
  for (std::size_t step = 0; step < n - 1; ++step) {
    const std::size_t i = (start + step) % (n - 1);
    if (kept[i]) {
      if (run.points.empty()) run.points.push_back(loop.points[i]);
      run.points.push_back(loop.points[i + 1]);
    } else if (!run.points.empty()) {
      result.push_back(run);
      run.points.clear();
    }
  }
  if (!run.points.empty()) result.push_back(std::move(run));
  return result;
}

}  // namespace

namespace {

// The pieces of open paths (all `like`'s width and role) inside a region, in one pass.
std::vector<ExtrusionPath> clipped(const std::vector<ExtrusionPath>& paths, const clipper::Paths& region) {
  std::vector<ExtrusionPath> result;
  if (paths.empty()) return result;
  clipper::Paths lines;
  for (const ExtrusionPath& path : paths) {
    ClipperLib::Path line;
    for (Vec2 p : path.points) line.push_back(to_clipper(p));
    lines.push_back(std::move(line));
  }
  for (const auto& part : clipper::clip_open(lines, region)) {
    if (part.size() < 2) continue;
    ExtrusionPath kept;
    kept.role = paths.front().role;
    kept.width = paths.front().width;
    kept.points = from_clipper(part);
    result.push_back(std::move(kept));
  }
  return result;
}

}  // namespace

SupportSheath support_sheath(const ClipperLib::Paths& support, const Region& body, double width,
                             const SupportPathOptions& o) {
  SupportSheath sheath;
  if (!o.sheath || !(width > 0) || !(o.spacing > 0) || body.loops.empty()) return sheath;
  std::vector<ExtrusionPath> wanted;
  bool whole = true;  // every loop kept whole
  for (const clipper::Paths& island : clipper::islands(clipper::simplified(support, kTolerance))) {
    for (ExtrusionPath& loop : sheath_of(island, width, PathRole::support).loops) {
      if (o.pattern == SupportPattern::grid) {
        wanted.push_back(std::move(loop));
        continue;
      }
      for (ExtrusionPath& piece : along_the_lines(loop, o.angle, o.spacing)) {
        whole = whole && piece.points.front() == piece.points.back();
        wanted.push_back(std::move(piece));
      }
    }
  }
  if (wanted.empty()) return sheath;
  if (whole && clipper::area_mm2(support) - area(body) < 1e-9) {
    sheath.paths = std::move(wanted);  // no interface: all of it in the body
  } else {
    sheath.paths = clipped(wanted, to_clipper(body));  // the interface has its own loop
  }
  if (sheath.paths.empty()) return sheath;
  clipper::Paths open, closed;
  for (const ExtrusionPath& path : sheath.paths) {
    ClipperLib::Path line;
    for (Vec2 p : path.points) line.push_back(to_clipper(p));
    const bool loop = line.size() > 3 && line.front() == line.back();
    if (loop) line.pop_back();
    (loop ? closed : open).push_back(std::move(line));
  }
  if (!open.empty()) {
    sheath.beads = clipper::library_offset(open, width / 2, ClipperLib::jtRound, ClipperLib::etOpenButt, kTolerance);
  }
  if (!closed.empty()) {
    const clipper::Paths rings =
        clipper::library_offset(closed, width / 2, ClipperLib::jtRound, ClipperLib::etClosedLine, kTolerance);
    sheath.beads.insert(sheath.beads.end(), rings.begin(), rings.end());
    if (!open.empty()) sheath.beads = clipper::union_nonzero(sheath.beads);
  }
  return sheath;
}

std::vector<ExtrusionPath> support_body_paths(const Region& body, double width,
                                              const SupportPathOptions& o, const SupportSheath& sheath,
                                              const Region* carried) {
  std::vector<ExtrusionPath> paths;
  if (!(width > 0) || !(o.spacing > 0) || body.loops.empty()) return paths;
  // Only the pieces that something below carries (a closed loop stays closed if all of it is).
  if (!carried) {
    paths = sheath.paths;
  } else if (!sheath.paths.empty()) {
    paths = clipped(sheath.paths, to_clipper(*carried));
  }
  // Where the lines' beads may run: half a bead in from the edge, and a bead off the
  // sheath's centre line (where it is laid or not). Free line ends stay on that edge: a bead
  // never reaches past the body's edge, nor into the sheath's.
  clipper::Paths centres = clipper::offset(clipper::simplified(to_clipper(body), kTolerance), -width / 2);
  if (!sheath.beads.empty()) {
    centres = clipper::difference(centres, clipper::offset(sheath.beads, width / 2, ClipperLib::jtRound));
  }
  const Region centre_area = from_clipper(centres);
  auto lay = [&](double angle) {
    if (centre_area.loops.empty()) return;
    const double max_connector = o.connectors ? kBodyConnector * o.spacing : 0;
    auto lines = zigzag(centre_area, ScanLines{angle, o.spacing, 0}, max_connector, nullptr,
                        PathRole::support, width);
    paths.insert(paths.end(), std::make_move_iterator(lines.begin()), std::make_move_iterator(lines.end()));
  };
  lay(o.angle);
  if (o.pattern == SupportPattern::grid) lay(o.angle + 90);
  return paths;
}

std::vector<ExtrusionPath> support_body_paths(const Region& body, double width,
                                              const SupportPathOptions& o, const Region* carried) {
  return support_body_paths(body, width, o, support_sheath(to_clipper(body), body, width, o), carried);
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
