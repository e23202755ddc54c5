#include "geometry/toolpaths/infill.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <utility>

#include "geometry/core/clipper.h"
#include "geometry/core/point_in_region.h"
#include "geometry/toolpaths/thin_walls.h"
#include "geometry/toolpaths/zigzag.h"

namespace geometry {

namespace {

// Longest connector of sparse and of solid infill, in line spacings (see infill.h).
constexpr double kSparseConnector = 3;
constexpr double kSolidConnector = 2;
// Beads are taken this much wider when finding what they leave bare (mm): where they fill
// the area, their edge then does not run along its edge, which would cost the difference
// a crossing at every vertex.
constexpr double kCoverTolerance = 0.01;
// Sparse infill's area is straightened within this first (mm).
constexpr double kSparseTolerance = 0.025;
// Round joins within this of the arc (mm).
constexpr double kArc = 0.005;
// How much less than half a bead solid lines keep from the edge (mm): see solid_infill.
constexpr double kGraze = 0.001;
// Solid islands no wider than twice this many beads anywhere are laid along their centre line.
constexpr double kNarrowStrip = 0.75;

// Lines at heights first + k * spacing (k = 0, 1, ...) in the rotated frame, clipped to area.
std::vector<ExtrusionPath> lines(const ScanFrame& frame, double first, double spacing,
                                 double y_max, double x_min, double x_max,
                                 const clipper::Paths& rotated, PathRole role, double width) {
  // More lines than this means a spacing no printer can lay down (nanometres over a bed).
  constexpr double kMaxLines = 1e6;
  if ((y_max - first) / spacing > kMaxLines) return {};
  clipper::Paths scan;
  for (std::size_t k = 0;; ++k) {
    const double y = first + static_cast<double>(k) * spacing;
    if (y > y_max) break;
    scan.push_back({to_clipper(Vec2{x_min - 1, y}), to_clipper(Vec2{x_max + 1, y})});
  }
  std::vector<ExtrusionPath> result;
  for (const auto& piece : clipper::clip_open(scan, rotated)) {
    if (piece.size() < 2) continue;
    ExtrusionPath path;
    path.role = role;
    path.width = width;
    for (const auto& p : piece) path.points.push_back(frame.out(from_clipper(p)));
    result.push_back(std::move(path));
  }
  // Clipper returns pieces in no promised order; sort so the output never depends on it.
  std::sort(result.begin(), result.end(), [&](const ExtrusionPath& a, const ExtrusionPath& b) {
    const Vec2 pa = frame.into(a.points.front()), pb = frame.into(b.points.front());
    return pa.y != pb.y ? pa.y < pb.y : pa.x < pb.x;
  });
  return result;
}

struct Rotated {
  clipper::Paths paths;
  double x_min = 0, x_max = 0, y_min = 0, y_max = 0;
  bool empty() const { return paths.empty(); }
};

Rotated rotate(const Region& area, const ScanFrame& frame) {
  Rotated r;
  bool any = false;
  for (const Loop& loop : area.loops) {
    if (loop.size() < 3) continue;
    ClipperLib::Path path;
    for (Vec2 p : loop) {
      const Vec2 q = frame.into(p);
      if (!any) { r.x_min = r.x_max = q.x; r.y_min = r.y_max = q.y; any = true; }
      r.x_min = std::min(r.x_min, q.x); r.x_max = std::max(r.x_max, q.x);
      r.y_min = std::min(r.y_min, q.y); r.y_max = std::max(r.y_max, q.y);
      path.push_back(to_clipper(q));
    }
    r.paths.push_back(std::move(path));
  }
  return r;
}

std::vector<ExtrusionPath> lines_across(const ScanFrame& frame, double first, double spacing,
                                        const Rotated& r, PathRole role, double width) {
  return lines(frame, first, spacing, r.y_max, r.x_min, r.x_max, r.paths, role, width);
}

// The piece (by index) whose area contains p, or the first one.
PathRole role_at(Vec2 p, const std::vector<SolidPiece>& pieces,
                 const std::vector<clipper::Paths>& piece_paths) {
  for (std::size_t i = 0; i < pieces.size(); ++i) {
    if (clipper::point_in_region(piece_paths[i], to_clipper(p))) return pieces[i].role;
  }
  return pieces.front().role;
}

// Paths cut where they pass from one piece into another, each piece's part with its role.
std::vector<ExtrusionPath> split_by_piece(const std::vector<ExtrusionPath>& paths,
                                          const std::vector<SolidPiece>& pieces,
                                          const std::vector<clipper::Paths>& piece_paths) {
  clipper::Paths open;
  for (const ExtrusionPath& path : paths) {
    ClipperLib::Path line;
    for (Vec2 p : path.points) line.push_back(to_clipper(p));
    open.push_back(std::move(line));
  }
  const double width = paths.empty() ? 0 : paths.front().width;
  std::vector<ExtrusionPath> result;
  for (std::size_t i = 0; i < pieces.size(); ++i) {
    for (const auto& piece : clipper::clip_open(open, piece_paths[i])) {
      if (piece.size() < 2) continue;
      ExtrusionPath path;
      path.role = pieces[i].role;
      path.width = width;
      path.points = from_clipper(piece);
      result.push_back(std::move(path));
    }
  }
  // Clipper returns pieces in no promised order; sort so the output never depends on it.
  std::sort(result.begin(), result.end(), [](const ExtrusionPath& a, const ExtrusionPath& b) {
    const Vec2 pa = a.points.front(), pb = b.points.front();
    return pa.x != pb.x ? pa.x < pb.x : pa.y < pb.y;
  });
  return result;
}

}  // namespace

std::string_view infill_pattern_name(InfillPattern pattern) {
  switch (pattern) {
    case InfillPattern::rectilinear: return "rectilinear";
    case InfillPattern::grid: return "grid";
  }
  return "grid";
}

std::optional<InfillPattern> parse_infill_pattern(std::string_view name) {
  if (name == "rectilinear") return InfillPattern::rectilinear;
  if (name == "grid") return InfillPattern::grid;
  return std::nullopt;
}

std::vector<ExtrusionPath> hatch(const Region& area, double spacing, double angle,
                                 PathRole role, double width) {
  if (!(spacing > 0) || !(width > 0)) return {};
  const ScanFrame frame(angle);
  const Rotated r = rotate(area, frame);
  if (r.empty()) return {};
  const double first = std::ceil(r.y_min / spacing) * spacing;
  return lines(frame, first, spacing, r.y_max, r.x_min, r.x_max, r.paths, role, width);
}

std::vector<ExtrusionPath> sparse_infill(const Region& area, double width, double density,
                                         InfillPattern pattern, double angle,
                                         std::size_t layer_index, InfillLines lines) {
  density = std::min(density, 100.0);
  if (!(density > 0) || !(width > 0)) return {};
  const double spacing = width * 100 / density;
  // Rectilinear: one set of lines, turning every layer; grid: both sets, twice as far apart.
  std::vector<double> angles{angle + (layer_index % 2 ? 90 : 0)};
  double set_spacing = spacing;
  if (pattern == InfillPattern::grid) {
    angles = {angle, angle + 90};
    set_spacing = 2 * spacing;
  }
  std::vector<ExtrusionPath> result;
  if (lines == InfillLines::separate) {
    for (double a : angles) {
      auto set = hatch(area, set_spacing, a, PathRole::sparse_infill, width);
      result.insert(result.end(), set.begin(), set.end());
    }
    return result;
  }
  // The lines are far apart: where exactly they end and their connectors run matters to
  // tens of micrometres at most, so the area is straightened within 25 um first (a third of
  // the vertices to offset).
  const Region centres =
      from_clipper(clipper::offset(clipper::simplified(to_clipper(area), kSparseTolerance), -width / 2));
  for (double a : angles) {
    auto set = zigzag(centres, ScanLines{a, set_spacing, 0}, kSparseConnector * set_spacing,
                      &area, PathRole::sparse_infill, width);
    result.insert(result.end(), set.begin(), set.end());
  }
  return result;
}

namespace {

// A closed path (last point = first) cut open where it first crosses one of the lines
// `below` (per set: its frame, lines across it `apart` mm apart through the origin), starting
// there and ending half a bead before it; as it is, closed, if it crosses none or on the
// first layer (nothing below).
std::vector<Vec2> cut_on_line_below(const ClipperLib::Path& loop,
                                    const std::vector<std::pair<ScanFrame, double>>& below,
                                    double width, std::size_t layer_index) {
  std::vector<Vec2> p;
  for (const auto& q : loop) p.push_back(from_clipper(q));
  p.pop_back();
  std::optional<std::pair<std::size_t, Vec2>> cut;
  for (std::size_t k = 0; k < p.size() && !cut && layer_index > 0; ++k) {
    const Vec2 a = p[k], b = p[(k + 1) % p.size()];
    for (const auto& [frame, apart] : below) {
      const double ya = frame.into(a).y / apart, yb = frame.into(b).y / apart;
      const double line = std::ceil(std::min(ya, yb));
      if (ya != yb && line <= std::max(ya, yb)) {
        cut = {k, a + ((line - ya) / (yb - ya)) * (b - a)};
        break;
      }
    }
  }
  if (!cut) {
    p.push_back(p.front());
    return p;
  }
  std::vector<Vec2> turned{cut->second};
  for (std::size_t k = 1; k <= p.size(); ++k) turned.push_back(p[(cut->first + k) % p.size()]);
  turned.push_back(cut->second);
  double left = width / 2;
  while (turned.size() > 2 && left > 0) {
    const Vec2 a = turned[turned.size() - 2], b = turned.back();
    const double d = length(b - a);
    if (d > left) {
      turned.back() = b + (left / d) * (a - b);
      break;
    }
    left -= d;
    turned.pop_back();
  }
  return turned;
}

// The sparse lines of the layer below, as sparse_infill lays them: per set, its frame and
// spacing (lines through the origin).
std::vector<std::pair<ScanFrame, double>> sparse_lines_below(double width, double density,
                                                             InfillPattern pattern, double angle,
                                                             std::size_t layer_index) {
  const double spacing = width * 100 / density;
  if (pattern == InfillPattern::grid) {
    return {{ScanFrame(angle), 2 * spacing}, {ScanFrame(angle + 90), 2 * spacing}};
  }
  return {{ScanFrame(angle + ((layer_index + 1) % 2 ? 90 : 0)), spacing}};
}

// The core's loops, closed, clipped to the area as open paths. A loop cut by the area's edge
// comes back cut at its first vertex too; the two pieces that meet there are one (an end there
// would hang between the lines below). Only the loops whose boxes meet the area's are clipped:
// the core above is the whole layer's, the area one island's, and a loop clear of its box has
// no piece in it (left out, it costs the clip nothing: bench_toolpaths' clip_open_joined
// 236 -> 230 M instructions, the bunny having few islands a layer).
clipper::Paths edges_in_area(const Region& core_above, const clipper::Paths& area) {
  const ClipperLib::IntRect box = clipper::bounding_box(area);
  clipper::Paths edges;
  edges.reserve(core_above.loops.size());
  for (const Loop& loop : core_above.loops) {
    ClipperLib::Path path = to_clipper(loop);
    if (path.empty() || !clipper::boxes_meet(clipper::bounding_box(path), box)) continue;
    path.push_back(path.front());
    edges.push_back(std::move(path));
  }
  // Loops that lie outside the area, clear of its edges (the core above round a sparse area
  // that does not grow), have no piece in it: proven so, they cost the clip nothing.
  if (clipper::proven_outside(edges, area)) return {};
  return clipper::clip_open_joined(edges, area);
}

// A step of a piece of the edge, at most a quarter bead long.
struct EdgeStep {
  Vec2 from, to;
  bool vertex;  // `to` is a vertex of the piece
  bool inside;  // runs inside the area shrunk by half a bead (not along the area's edge)
};

std::vector<EdgeStep> quarter_bead_steps(const ClipperLib::Path& piece,
                                         const clipper::PointsInRegion& shrunk, double width) {
  std::vector<EdgeStep> steps;
  for (std::size_t k = 1; k < piece.size(); ++k) {
    const Vec2 a = from_clipper(piece[k - 1]), b = from_clipper(piece[k]);
    const int cuts = std::max(1, static_cast<int>(std::ceil(length(b - a) / (width / 4))));
    for (int c = 0; c < cuts; ++c) {
      const Vec2 from = a + (static_cast<double>(c) / cuts) * (b - a);
      const Vec2 to = a + (static_cast<double>(c + 1) / cuts) * (b - a);
      steps.push_back({from, to, c + 1 == cuts, shrunk.contains(to_clipper(0.5 * (from + to)))});
    }
  }
  return steps;
}

// Arc distance of each step to the nearest step inside, along the piece (round a loop, both
// ways round).
std::vector<double> distance_to_inside(const std::vector<EdgeStep>& steps, bool loop) {
  const std::size_t m = steps.size();
  std::vector<double> reach(m, std::numeric_limits<double>::infinity());
  double run = std::numeric_limits<double>::infinity();
  const auto step_on = [&](std::size_t k) {
    const EdgeStep& step = steps[k % m];
    run = step.inside ? 0 : run + length(step.to - step.from);
    reach[k % m] = std::min(reach[k % m], run);
  };
  const std::size_t rounds = loop ? 2 : 1;
  for (std::size_t k = 0; k < rounds * m; ++k) step_on(k);
  run = std::numeric_limits<double>::infinity();
  for (std::size_t k = rounds * m; k-- > 0;) step_on(k);
  return reach;
}

// A line of the edge, kept if it is at least a bead long.
void add_edge_line(std::vector<Vec2> points, double width, std::vector<ExtrusionPath>& result) {
  if (points.size() >= 2 && polyline_length(points) >= width) {
    result.push_back({PathRole::sparse_infill, std::move(points), width});
  }
}

// The runs of steps kept (`kept`, per step); round a loop, from a step left out (`from`), so
// that no run is cut where the loop closes. A run with less than two beads of it inside the shrunk
// area mostly follows the area's edge beside the wall, where nothing of the skin above ends on
// it and the layer below's wall may not reach under it: left out.
void add_kept_runs(const std::vector<EdgeStep>& steps, const std::vector<char>& kept,
                   std::size_t from, double width, std::vector<ExtrusionPath>& result) {
  const std::size_t m = steps.size();
  std::vector<Vec2> points;
  double inner = 0;
  for (std::size_t j = 0; j < m; ++j) {
    const std::size_t k = (from + j) % m;
    if (!kept[k]) {
      if (inner >= 2 * width) add_edge_line(std::move(points), width, result);
      points.clear();
      inner = 0;
      continue;
    }
    if (steps[k].inside) inner += length(steps[k].to - steps[k].from);
    if (points.empty()) points.push_back(steps[k].from);
    const bool last = j + 1 == m || !kept[(k + 1) % m];
    if (steps[k].vertex || last) points.push_back(steps[k].to);
  }
  if (inner >= 2 * width) add_edge_line(std::move(points), width, result);
}

// The lines along one piece of the edge. A step along the area's edge is kept within `follow`
// of a step inside, so that an end rests on what the layer below has there; the rest of the
// edge's run along the area's edge is left out (it would double the wall there).
void add_piece_lines(const ClipperLib::Path& piece, const clipper::PointsInRegion& shrunk,
                     const std::vector<std::pair<ScanFrame, double>>& below, double follow,
                     double width, std::size_t layer_index, std::vector<ExtrusionPath>& result) {
  const std::vector<EdgeStep> steps = quarter_bead_steps(piece, shrunk, width);
  const std::size_t m = steps.size();
  const bool loop = piece.front() == piece.back();
  const std::vector<double> reach = distance_to_inside(steps, loop);
  std::vector<char> kept(m);
  for (std::size_t k = 0; k < m; ++k) kept[k] = !(reach[k] > follow + 1e-9);
  std::size_t first_out = 0;
  while (first_out < m && kept[first_out]) ++first_out;
  if (loop && first_out == m) {
    // A whole loop: cut open where it crosses a line below, so that it starts and ends on
    // one, and end half a bead before it (the round ends meet).
    add_edge_line(cut_on_line_below(piece, below, width, layer_index), width, result);
    return;
  }
  add_kept_runs(steps, kept, loop ? first_out : 0, width, result);
}

}  // namespace

std::vector<ExtrusionPath> skin_edge_lines(const Region& sparse, const Region& core_above,
                                           double width, double density, InfillPattern pattern,
                                           double angle, std::size_t layer_index) {
  density = std::min(density, 100.0);
  if (!(density > 0) || !(width > 0) || sparse.loops.empty() || core_above.loops.empty()) return {};
  const clipper::Paths area = to_clipper(sparse);
  // The pieces first: where none of the edge lies in the area (a third of the bunny's
  // islands), there is no line to lay and no shrunk area to find.
  const clipper::Paths pieces = edges_in_area(core_above, area);
  if (pieces.empty()) return {};
  const clipper::Paths shrunk = clipper::offset(area, -width / 2);
  if (shrunk.empty()) return {};
  const clipper::PointsInRegion inside_shrunk(shrunk);
  const auto below = sparse_lines_below(width, density, pattern, angle, layer_index);
  // Where the edge meets the sparse area's edge it follows it on for a spacing of the lines
  // below, far enough to meet one of them (they end along the area's edge).
  const double follow = below.front().second;
  std::vector<ExtrusionPath> result;
  for (const auto& piece : pieces) {
    if (piece.size() >= 2) add_piece_lines(piece, inside_shrunk, below, follow, width, layer_index, result);
  }
  return result;
}

namespace {

// The union of the pieces' areas.
clipper::Paths united(const std::vector<clipper::Paths>& piece_paths) {
  if (piece_paths.size() == 1) return clipper::union_nonzero(piece_paths[0]);
  clipper::Paths all;
  for (const clipper::Paths& paths : piece_paths) all.insert(all.end(), paths.begin(), paths.end());
  return clipper::union_nonzero(all);
}

// The islands of `area` at least 1.5 beads wide somewhere (whole), and the others (narrow).
std::pair<clipper::Paths, clipper::Paths> split_narrow(const clipper::Paths& area, double width) {
  clipper::Paths whole, narrow;
  for (clipper::Paths& island : clipper::islands(area)) {
    clipper::Paths& into = clipper::offset_is_empty(island, -kNarrowStrip * width) ? narrow : whole;
    into.insert(into.end(), island.begin(), island.end());
  }
  return {std::move(whole), std::move(narrow)};
}

// Narrow islands laid along their centre lines, each line with the role of the piece at its
// middle.
void add_narrow_strips(const clipper::Paths& narrow, double width,
                       const std::vector<SolidPiece>& pieces,
                       const std::vector<clipper::Paths>& piece_paths,
                       std::vector<ExtrusionPath>& result) {
  if (narrow.empty()) return;
  const Region narrow_area = from_clipper(narrow);
  for (ExtrusionPath& strip : thin_walls(narrow_area, width / 4, 2 * kNarrowStrip * width,
                                         std::numeric_limits<double>::infinity(), &narrow_area)) {
    strip.role = role_at(strip.points[strip.points.size() / 2], pieces, piece_paths);
    result.push_back(std::move(strip));
  }
}

// Lines across `whole` at the layer's angle, as many as fit its extent across them a bead
// apart, spaced evenly; the beads as wide as they are apart.
struct SolidLines {
  std::vector<ExtrusionPath> across;
  double bead = 0;  // mm
};

// None when `whole` has no loop to lay lines in.
std::optional<SolidLines> solid_lines(const clipper::Paths& whole, double width, double angle,
                                      std::size_t layer_index, PathRole role,
                                      InfillLines lines) {
  const double layer_angle = angle + (layer_index % 2 ? 90 : 0);
  const ScanFrame frame(layer_angle);
  const Rotated r = rotate(from_clipper(whole), frame);
  if (r.empty()) return std::nullopt;
  const double extent = r.y_max - r.y_min;
  const double count = std::max(1.0, std::round(extent / width));
  const double spacing = extent > 0 ? extent / count : width;
  // Beads as wide as the lines are apart tile the area; a single line in a strip narrower
  // than a bead is a thin wall's business, kept to a printable width.
  const double bead = std::clamp(spacing, width / 4, 1.5 * width);
  if (lines == InfillLines::separate) {
    return SolidLines{lines_across(frame, r.y_min + spacing / 2, spacing, r, role, bead), bead};
  }
  // Centre lines run half a bead inside; a micrometre less, so that the first and last
  // lines, which lie exactly on the shrunk area's extremes, are not lost to rounding.
  const Region centres = from_clipper(clipper::offset(whole, -(bead / 2 - kGraze)));
  const Region fill = from_clipper(whole);
  return SolidLines{zigzag(centres, ScanLines{layer_angle, spacing, r.y_min + spacing / 2},
                           kSolidConnector * spacing, &fill, role, bead),
                    bead};
}

// What the lines leave bare of `whole`, up to a bead wide. (The beads are taken with square
// ends and corners: as much as round ones but for specks.)
clipper::Paths left_bare(const clipper::Paths& whole, const std::vector<ExtrusionPath>& across,
                         double bead, double width) {
  clipper::Paths centre_lines;
  for (const ExtrusionPath& line : across) centre_lines.push_back(to_clipper(line.points));
  const clipper::Paths covered =
      clipper::library_offset(centre_lines, bead / 2 + kCoverTolerance, ClipperLib::jtSquare,
                              ClipperLib::etOpenSquare, kArc);
  clipper::Paths bare = clipper::difference(whole, covered);
  // A piece under an eighth of a bead's square is a notch a round bead leaves at a turn of
  // the zig-zag or at a corner (two notches of (1 - pi/4) w^2/4 where turns meet): a bead
  // there would be a dab laid beside beads that nearly fill it already.
  const double speck = width * width / 8 * kClipperScale * kClipperScale;
  auto drop_specks = [&] {
    std::erase_if(bare, [&](const auto& path) { return std::abs(ClipperLib::Area(path)) < speck; });
  };
  drop_specks();
  bare = clipper::opening(bare, width / 8);
  drop_specks();  // the opening cuts a bare edge into the notches along it
  return bare;
}

// Centre lines of their own width along what the lines left bare, each with the role of the
// piece at its middle.
void add_gap_lines(const clipper::Paths& bare, const clipper::Paths& whole, double width,
                   const std::vector<SolidPiece>& pieces,
                   const std::vector<clipper::Paths>& piece_paths,
                   std::vector<ExtrusionPath>& result) {
  const Region fill_area = from_clipper(whole);
  for (ExtrusionPath& gap : thin_walls(from_clipper(bare), width / 4, width,
                                       std::numeric_limits<double>::infinity(), &fill_area)) {
    gap.role = role_at(gap.points[gap.points.size() / 2], pieces, piece_paths);
    // A dab in the notch of a turn, inside the part (solid infill, covered above and below),
    // is seen by no one and holds nothing up, and over sparse infill it hangs in the air.
    if (gap.role == PathRole::solid_infill && polyline_length(gap.points) < width) continue;
    result.push_back(std::move(gap));
  }
}

}  // namespace

std::vector<ExtrusionPath> solid_infill(const Region& area, double width, double angle,
                                        std::size_t layer_index, PathRole role,
                                        InfillLines lines) {
  return solid_infill(std::vector<SolidPiece>{{area, role}}, width, angle, layer_index, lines);
}

std::vector<ExtrusionPath> solid_infill(const std::vector<SolidPiece>& pieces, double width,
                                        double angle, std::size_t layer_index,
                                        InfillLines lines) {
  if (!(width > 0) || pieces.empty()) return {};
  std::vector<clipper::Paths> piece_paths;
  for (const SolidPiece& piece : pieces) piece_paths.push_back(to_clipper(piece.area));
  // An island nowhere 1.5 beads wide (the ring of skin a receding top leaves inside its
  // walls) is laid along its centre line, round a ring in one path: lines across it would be
  // dashes a bead or two long, each held by nothing where the layer below is sparse, where
  // one path along it crosses the lines below and bridges between them.
  const auto [whole, narrow] = split_narrow(united(piece_paths), width);
  std::vector<ExtrusionPath> result;
  add_narrow_strips(narrow, width, pieces, piece_paths, result);
  if (whole.empty()) return result;
  std::optional<SolidLines> solid =
      solid_lines(whole, width, angle, layer_index, pieces.front().role, lines);
  if (!solid) return {};
  if (pieces.size() > 1) solid->across = split_by_piece(solid->across, pieces, piece_paths);
  const clipper::Paths bare = left_bare(whole, solid->across, solid->bead, width);
  result.insert(result.end(), std::make_move_iterator(solid->across.begin()),
                std::make_move_iterator(solid->across.end()));
  add_gap_lines(bare, whole, width, pieces, piece_paths, result);
  return result;
}

}  // namespace geometry
