#include "sim/unsupported_extrusion.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include <fmt/core.h>
#include <polyclipping/clipper.hpp>

#include "geometry/core/clipper.h"
#include "geometry/core/point_in_region.h"
#include "printer/bead_model.h"

namespace sim {

namespace {

namespace clipper = geometry::clipper;
using ClipperLib::IntPoint;
using ClipperLib::Path;
using ClipperLib::Paths;

// Z levels, widths and points closer than these are the same (mm).
constexpr double kHeight = 1e-6;
constexpr double kJoin = 1e-6;
// Consecutive moves whose bead widths differ by less than this are widened as one (mm).
constexpr double kSameWidth = 0.02;
// Round joins within this of the arc (mm).
constexpr double kArc = 0.005;

struct Move {
  geometry::Vec2 from, to;
  double width = 0, length = 0;
};

struct Layer {
  double z = 0, height = 0;
  std::vector<std::vector<Move>> chains;  // consecutive moves, end to start
  double extruded = 0;
};

std::vector<Layer> layers_of(const DepositionRecord& record, double filament_diameter) {
  std::vector<Layer> layers(record.layer_z.size());
  for (std::size_t i = 0; i < layers.size(); ++i) {
    layers[i].z = record.layer_z[i];
    layers[i].height = record.layer_height(static_cast<int>(i));
  }
  int last_layer = -1;
  geometry::Vec2 last_end{};
  for (const DepositedMove& m : record.moves) {
    Layer& layer = layers[static_cast<std::size_t>(m.layer)];
    const geometry::Vec2 d = m.end - m.start;
    const double length = std::hypot(d.x, d.y);
    if (!(length > 0)) continue;
    layer.extruded += length;
    const double width = printer::bead_width(m.e, length, layer.height, filament_diameter);
    const bool joined = m.layer == last_layer && std::abs(m.start.x - last_end.x) < kJoin &&
                        std::abs(m.start.y - last_end.y) < kJoin && !layer.chains.empty();
    if (!joined) layer.chains.emplace_back();
    layer.chains.back().push_back({m.start, m.end, width, length});
    last_layer = m.layer;
    last_end = m.end;
  }
  return layers;
}

// A disc of radius r about c, within 2 um of the circle.
Path disc(geometry::Vec2 c, double r) {
  const int sides = std::max(8, static_cast<int>(std::ceil(M_PI / std::acos(1 - std::min(0.002 / r, 1.0)))));
  Path path;
  for (int i = 0; i < sides; ++i) {
    const double a = 2 * M_PI * i / sides;
    path.push_back(geometry::to_clipper({c.x + r * std::cos(a), c.y + r * std::sin(a)}));
  }
  return path;
}

// The union of a layer's beads: each run of moves of one width widened to it (round joins,
// square-cut ends), runs of different widths meeting in a round joint.
Paths bead_area(const Layer& layer) {
  Paths all;
  for (const std::vector<Move>& chain : layer.chains) {
    std::size_t start = 0;
    while (start < chain.size()) {
      std::size_t stop = start + 1;
      while (stop < chain.size() && std::abs(chain[stop].width - chain[start].width) < kSameWidth) ++stop;
      Path path{geometry::to_clipper(chain[start].from)};
      double weighted = 0, length = 0;
      for (std::size_t i = start; i < stop; ++i) {
        path.push_back(geometry::to_clipper(chain[i].to));
        weighted += chain[i].width * chain[i].length;
        length += chain[i].length;
      }
      const double width = length > 0 ? weighted / length : chain[start].width;
      if (width > 0) {
        const bool closed = path.size() > 3 && path.front() == path.back();
        if (closed) path.pop_back();
        ClipperLib::ClipperOffset offset(2.0, kArc * geometry::kClipperScale);
        offset.AddPath(path, ClipperLib::jtRound,
                       closed ? ClipperLib::etClosedLine : ClipperLib::etOpenButt);
        Paths widened;
        offset.Execute(widened, width / 2 * geometry::kClipperScale);
        all.insert(all.end(), widened.begin(), widened.end());
      }
      if (stop < chain.size()) {
        const double joint = std::min(chain[stop - 1].width, chain[stop].width) / 2;
        if (joint > 0) all.push_back(disc(chain[stop].from, joint));
      }
      start = stop;
    }
  }
  return clipper::union_nonzero(all);
}

double median_width(const Layer& layer) {
  std::vector<std::pair<double, double>> widths;  // width, length
  double total = 0;
  for (const auto& chain : layer.chains) {
    for (const Move& m : chain) {
      widths.emplace_back(m.width, m.length);
      total += m.length;
    }
  }
  if (widths.empty()) return 0;
  std::sort(widths.begin(), widths.end());
  double seen = 0;
  for (const auto& [width, length] : widths) {
    seen += length;
    if (seen >= total / 2) return width;
  }
  return widths.back().first;
}

double length_of(const Path& path) {
  double length = 0;
  for (std::size_t i = 1; i < path.size(); ++i) {
    const geometry::Vec2 d = geometry::from_clipper(path[i]) - geometry::from_clipper(path[i - 1]);
    length += std::hypot(d.x, d.y);
  }
  return length;
}

// Layer k's unsupported stretches over `below` (the beads it may rest on, closed).
std::vector<UnsupportedStretch> check_layer(const Layer& layer, int k, const Paths& below,
                                            const Paths& raw_below, const SupportCheckOptions& o) {
  Paths lines;
  for (const auto& chain : layer.chains) {
    Path line{geometry::to_clipper(chain.front().from)};
    for (const Move& m : chain) line.push_back(geometry::to_clipper(m.to));
    lines.push_back(std::move(line));
  }
  std::vector<UnsupportedStretch> found;
  if (lines.empty()) return found;
  Paths off;
  if (below.empty()) {
    off = lines;
  } else {
    ClipperLib::Clipper clipper;
    clipper.AddPaths(lines, ClipperLib::ptSubject, false);
    clipper.AddPaths(below, ClipperLib::ptClip, true);
    ClipperLib::PolyTree tree;
    clipper.Execute(ClipperLib::ctDifference, tree, ClipperLib::pftNonZero, ClipperLib::pftNonZero);
    ClipperLib::OpenPathsFromPolyTree(tree, off);
  }
  const Paths held = below.empty() ? below : clipper::offset(below, o.tolerance);
  Paths enclosed;  // among the beads below, computed when first needed
  bool enclosed_known = false;
  for (const Path& piece : off) {
    if (piece.size() < 2) continue;
    const double length = length_of(piece);
    if (!(length > 0)) continue;
    const bool anchored = !held.empty() && clipper::point_in_region(held, piece.front()) &&
                          clipper::point_in_region(held, piece.back());
    if (anchored && length <= o.bridge_length) continue;
    if (!enclosed_known) {
      enclosed = raw_below.empty() ? raw_below
                                   : clipper::offset(clipper::offset(raw_below, o.sparse_reach, ClipperLib::jtRound),
                                                -o.sparse_reach, ClipperLib::jtRound);
      enclosed_known = true;
    }
    // The middle of the piece, along it.
    IntPoint middle = piece.front();
    double walked = 0;
    for (std::size_t i = 1; i < piece.size(); ++i) {
      const geometry::Vec2 a = geometry::from_clipper(piece[i - 1]), b = geometry::from_clipper(piece[i]);
      const double step = std::hypot(b.x - a.x, b.y - a.y);
      if (walked + step >= length / 2 && step > 0) {
        middle = geometry::to_clipper(a + ((length / 2 - walked) / step) * (b - a));
        break;
      }
      walked += step;
    }
    const bool between = !enclosed.empty() && clipper::point_in_region(enclosed, middle);
    found.push_back({k, layer.z, geometry::from_clipper(piece.front()),
                     geometry::from_clipper(piece.back()), length, anchored, between});
  }
  return found;
}

}  // namespace

SupportCheck check_unsupported_extrusion(const DepositionRecord& record,
                                         const SupportCheckOptions& o) {
  SupportCheck check;
  const std::vector<Layer> layers = layers_of(record, o.filament_diameter);
  const std::size_t n = layers.size();
  check.unsupported_per_layer.assign(n, 0);
  for (const Layer& layer : layers) check.extruded_mm += layer.extruded;
  if (n < 2) return check;

  std::vector<Paths> beads(n);
  tbb::parallel_for(std::size_t{0}, n, [&](std::size_t i) { beads[i] = bead_area(layers[i]); });

  std::vector<std::vector<UnsupportedStretch>> found(n);
  tbb::parallel_for(std::size_t{1}, n, [&](std::size_t k) {
    const Layer& layer = layers[k];
    if (layer.chains.empty()) return;
    const double bottom = layers[k - 1].z;
    // The bed, a layer below layer 0, carries whatever may sag onto it.
    if (layers[0].z > bottom - o.contact_gap + kHeight) return;
    Paths under;
    for (std::size_t j = k; j-- > 0;) {
      if (j + 1 < k && !(layers[j + 1].z > bottom - o.contact_gap + kHeight)) break;
      under.insert(under.end(), beads[j].begin(), beads[j].end());
    }
    const double r = median_width(layer) / 4;
    const Paths raw = clipper::union_nonzero(under);
    Paths below = raw;
    if (!below.empty()) {
      below = clipper::offset(clipper::offset(below, r, ClipperLib::jtRound), -(r - o.tolerance),
                         ClipperLib::jtRound);
    }
    found[k] = check_layer(layer, static_cast<int>(k), below, raw, o);
  });
  for (std::size_t k = 0; k < n; ++k) {
    for (const UnsupportedStretch& s : found[k]) {
      check.unsupported_per_layer[k] += s.length;
      check.unsupported_mm += s.length;
      if (s.between) check.between_mm += s.length;
      if (check.stretches.size() < o.stretches_kept) check.stretches.push_back(s);
    }
  }
  return check;
}

std::string unsupported_summary(const SupportCheck& check, const SupportCheckOptions& options) {
  const double share = check.extruded_mm > 0 ? 100 * check.unsupported_mm / check.extruded_mm : 0;
  const std::string where =
      check.unsupported_mm > 0
          ? fmt::format(": {:.1f} mm in the open, {:.1f} mm between sparse lines below",
                        check.unsupported_mm - check.between_mm, check.between_mm)
          : "";
  return fmt::format("unsupported extrusion: {:.1f} mm of {:.1f} m ({:.2f}%{}; bridges up to "
                     "{:g} mm, contact gap {:g} mm)",
                     check.unsupported_mm, check.extruded_mm / 1000, share, where,
                     options.bridge_length, options.contact_gap);
}

}  // namespace sim
