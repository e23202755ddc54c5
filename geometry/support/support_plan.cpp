#include "geometry/support/support_plan.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "geometry/core/clipper.h"
#include "geometry/support/bridge_detector.h"
#include "geometry/support/overhang.h"

namespace geometry {

namespace {

// Regions are straightened within this before any of the below (mm): a tenth of the
// unsupported-extrusion check's tolerance, and half the vertices of a fine mesh's section.
constexpr double kTolerance = 0.005;
// Heights closer than this are equal (mm): layer bounds are sums of thicknesses.
constexpr double kHeight = 1e-6;
// How far into the layer below a bridge's anchors are looked for (mm, in bead widths).
constexpr double kAnchorReach = 2;
// Widened contacts reach this much past half a body line's bead (mm), so that the zig-zag's
// centre area, half a bead in, still holds the line.
constexpr double kOnLine = 0.01;

clipper::Paths box_path(const SupportBox& box) {
  return {{to_clipper(Vec2{box.min.x, box.min.y}), to_clipper(Vec2{box.max.x, box.min.y}),
           to_clipper(Vec2{box.max.x, box.max.y}), to_clipper(Vec2{box.min.x, box.max.y})}};
}

// The boxes' footprints that layer meets.
clipper::Paths boxes_at(const std::vector<SupportBox>& boxes, const Layer& layer) {
  clipper::Paths result;
  for (const SupportBox& box : boxes) {
    if (box.max.x <= box.min.x || box.max.y <= box.min.y) continue;
    if (box.min.z < layer.z_hi && box.max.z > layer.z_lo) {
      const clipper::Paths path = box_path(box);
      result.insert(result.end(), path.begin(), path.end());
    }
  }
  return result.empty() ? result : clipper::union_nonzero(result);
}

// The region widened across lines `spacing` apart at `angle` (through the origin) to the
// nearest line on each side and `past` beyond it: per band between two neighbouring lines,
// each piece of the region in it becomes the band's full width over the piece's extent
// along the lines, that extent made `shortest` at least (about its middle); a piece within
// `past` less kOnLine of one line, which the widened region covers anyway, only that line's
// strip.
clipper::Paths widened_to_lines(const clipper::Paths& region, double angle, double spacing, double past,
                                double shortest) {
  if (region.empty() || !(spacing > 0)) return region;
  const double a = angle * std::numbers::pi / 180;
  const double c = std::cos(a), s = std::sin(a);
  auto into = [&](Vec2 p) { return Vec2{p.x * c + p.y * s, -p.x * s + p.y * c}; };
  auto out = [&](Vec2 p) { return Vec2{p.x * c - p.y * s, p.x * s + p.y * c}; };
  clipper::Paths turned;
  double y_min = 1e300, y_max = -1e300, x_min = 1e300, x_max = -1e300;
  for (const auto& path : region) {
    ClipperLib::Path t;
    for (const auto& q : path) {
      const Vec2 p = into(from_clipper(q));
      y_min = std::min(y_min, p.y);
      y_max = std::max(y_max, p.y);
      x_min = std::min(x_min, p.x);
      x_max = std::max(x_max, p.x);
      t.push_back(to_clipper(p));
    }
    turned.push_back(std::move(t));
  }
  const double slack = std::clamp(past - kOnLine, 0.0, spacing / 4);
  clipper::Paths boxes;
  for (double k = std::floor(y_min / spacing); k * spacing < y_max; k += 1) {
    const double y0 = k * spacing, y1 = y0 + spacing;
    const clipper::Paths band{{to_clipper(Vec2{x_min - 1, y0}), to_clipper(Vec2{x_max + 1, y0}),
                          to_clipper(Vec2{x_max + 1, y1}), to_clipper(Vec2{x_min - 1, y1})}};
    for (const clipper::Paths& piece : clipper::islands(clipper::intersection(turned, band))) {
      double lo = 1e300, hi = -1e300, bottom = 1e300, top = -1e300;
      for (const auto& q : piece.front()) {
        const Vec2 p = from_clipper(q);
        lo = std::min(lo, p.x);
        hi = std::max(hi, p.x);
        bottom = std::min(bottom, p.y);
        top = std::max(top, p.y);
      }
      const double short_by = std::max(0.0, shortest - (hi - lo)) / 2;
      lo -= short_by;
      hi += short_by;
      // A piece within the slack of one line needs only that line.
      double from = y0 - past, to = y1 + past;
      if (top <= y0 + slack) {
        to = y0 + past;
      } else if (bottom >= y1 - slack) {
        from = y1 - past;
      }
      boxes.push_back({to_clipper(out({lo, from})), to_clipper(out({hi, from})),
                       to_clipper(out({hi, to})), to_clipper(out({lo, to}))});
    }
  }
  return clipper::union_nonzero(boxes);
}

// Step 1-3 for layer k >= 1: the pieces that need support (contact) and those bridged.
struct LayerContacts {
  clipper::Paths contact;
  std::vector<Bridge> bridges;
};

LayerContacts layer_contacts(const std::vector<clipper::Paths>& part, const std::vector<Layer>& layers,
                             std::size_t k, const SupportOptions& o, const clipper::Paths* shadow) {
  LayerContacts result;
  const clipper::Paths& region = part[k];
  const clipper::Paths& below = part[k - 1];
  const double reach = overhang_reach(layers[k].thickness(), o.overhang_angle, o.bead_width);
  clipper::Paths pieces = overhang(region, below, reach, o.min_area);
  const clipper::Paths enforced = boxes_at(o.enforcers, layers[k]);
  const clipper::Paths blocked = boxes_at(o.blockers, layers[k]);
  if (!blocked.empty()) pieces = without_specks(clipper::difference(pieces, blocked), o.min_area);
  if (shadow && !shadow->empty() && !pieces.empty()) {
    pieces = without_specks(clipper::difference(pieces, *shadow), o.min_area);
  }
  clipper::Paths contact;
  if (!pieces.empty() && o.bridge_length > 0) {
    const double reach_out = kAnchorReach * o.bead_width;
    const clipper::Paths near = clipper::intersection(below, clipper::offset(pieces, reach_out));
    for (clipper::Paths& piece : clipper::islands(pieces)) {
      const clipper::Paths anchors = clipper::intersection(near, clipper::offset(piece, reach_out));
      const BridgeDirection direction = bridge_direction(piece, anchors, o.bead_width);
      if (direction.anchored && direction.span <= o.bridge_length) {
        result.bridges.push_back({from_clipper(piece), direction.angle, direction.span});
      } else {
        contact.insert(contact.end(), piece.begin(), piece.end());
      }
    }
  } else {
    contact = std::move(pieces);
  }
  if (!enforced.empty()) {
    // Inside an enforcer, whatever is not over the layer below, however gentle the slope.
    clipper::Paths forced = overhang(clipper::intersection(region, enforced), below, 0, o.min_area);
    if (shadow && !shadow->empty()) forced = without_specks(clipper::difference(forced, *shadow), o.min_area);
    contact.insert(contact.end(), forced.begin(), forced.end());
  }
  if (!contact.empty()) {
    // Out to the body's lines across them, a bead's half past the line (the interface's
    // ends then rest on the line), and along them at least as long as a loop fits in.
    const double past = o.bead_width / 2 + kOnLine, shortest = o.bead_width + 2 * kOnLine;
    clipper::Paths grown = clipper::union_nonzero(contact);
    if (o.pattern == SupportPattern::grid) {
      grown = widened_to_lines(grown, o.line_angle, o.line_spacing, past, 0);
      grown = widened_to_lines(grown, o.line_angle + 90, o.line_spacing, past, 0);
    } else {
      grown = widened_to_lines(grown, o.line_angle, o.line_spacing, past, shortest);
    }
    result.contact = std::move(grown);
  }
  return result;
}

// The highest layer whose top is at least `gap` below layer k's bottom, or -1.
long top_support_layer(const std::vector<Layer>& layers, std::size_t k, double gap) {
  for (std::size_t j = k; j-- > 0;) {
    if (layers[j].z_hi <= layers[k].z_lo - gap + kHeight) return static_cast<long>(j);
  }
  return -1;
}

// The lowest layer of the interface under a contact whose support's top is layer t: whole
// layers down from t until they are `thickness` thick at least (rounded up to the layers
// there, as the contact distances are).
std::size_t lowest_interface_layer(const std::vector<Layer>& layers, std::size_t t, double thickness) {
  std::size_t lowest = t;
  while (lowest > 0 && layers[t].z_hi - layers[lowest].z_lo < thickness - kHeight) --lowest;
  return lowest;
}

// Step 4: the columns, from the top down; each layer's support is what comes down from the
// layer above plus the contacts whose top is here, less what must stay clear of the part.
std::vector<clipper::Paths> columns(const std::vector<clipper::Paths>& part, const std::vector<Layer>& layers,
                               const std::vector<clipper::Paths>& tops, const SupportOptions& o) {
  const std::size_t n = layers.size();
  std::vector<clipper::Paths> support(n);
  std::size_t highest = 0;  // one past the highest layer with a contact's top
  for (std::size_t j = 0; j < n; ++j) {
    if (!tops[j].empty()) highest = j + 1;
  }
  // What each layer's support must stay clear of, each layer on its own: the part grown by
  // the XY gap, the part above within the top contact distance and below within the bottom
  // one.
  std::vector<clipper::Paths> clear(highest);
  tbb::parallel_for(std::size_t{0}, highest, [&](std::size_t j) {
    clipper::Paths all = part[j].empty() ? clipper::Paths{} : clipper::offset(part[j], o.xy_gap, ClipperLib::jtRound);
    for (std::size_t i = j + 1; i < n && layers[i].z_lo < layers[j].z_hi + o.top_contact_distance - kHeight; ++i) {
      all.insert(all.end(), part[i].begin(), part[i].end());
    }
    for (std::size_t i = j; i-- > 0 && layers[i].z_hi > layers[j].z_lo - o.bottom_contact_distance + kHeight;) {
      all.insert(all.end(), part[i].begin(), part[i].end());
    }
    clear[j] = std::move(all);
  });
  clipper::Paths coming;
  for (std::size_t j = highest; j-- > 0;) {
    clipper::Paths s = tops[j].empty() ? std::move(coming) : clipper::union_nonzero(coming, tops[j]);
    if (s.empty()) {
      coming.clear();
      continue;
    }
    s = clipper::difference(s, clear[j]);
    // What goes down is straightened (the vertices would pile up layer on layer); what
    // this layer prints is exactly clear of the part.
    coming = clipper::simplified(s, kTolerance);
    support[j] = std::move(s);
  }
  return support;
}

// Step 6.
void plan_raft(SupportPlan& plan, const clipper::Paths& first, const RaftOptions& r) {
  clipper::Paths outline;
  for (const auto& path : clipper::union_nonzero(first)) {
    if (ClipperLib::Orientation(path)) outline.push_back(path);  // holes filled
  }
  if (outline.empty()) return;
  plan.raft_area = from_clipper(clipper::offset(clipper::union_nonzero(outline), std::max(r.margin, 0.0),
                                           ClipperLib::jtRound));
  double z = 0;
  auto add = [&](double thickness, RaftPart part) {
    plan.raft.push_back({{z, z + thickness}, part});
    z += thickness;
  };
  add(r.base_thickness, RaftPart::base);
  for (int i = 0; i < r.interface_layers; ++i) add(r.layer_thickness, RaftPart::interface);
  for (int i = 0; i < r.surface_layers; ++i) add(r.layer_thickness, RaftPart::surface);
  plan.lift = z + std::max(r.air_gap, 0.0);
}

}  // namespace

std::string_view support_pattern_name(SupportPattern pattern) {
  return pattern == SupportPattern::grid ? "grid" : "lines";
}

std::optional<SupportPattern> parse_support_pattern(std::string_view name) {
  if (name == "lines") return SupportPattern::lines;
  if (name == "grid") return SupportPattern::grid;
  return std::nullopt;
}

std::string_view support_placement_name(SupportPlacement placement) {
  switch (placement) {
    case SupportPlacement::none: return "none";
    case SupportPlacement::buildplate: return "buildplate";
    case SupportPlacement::everywhere: return "everywhere";
  }
  return "none";
}

std::optional<SupportPlacement> parse_support_placement(std::string_view name) {
  if (name == "none") return SupportPlacement::none;
  if (name == "buildplate") return SupportPlacement::buildplate;
  if (name == "everywhere") return SupportPlacement::everywhere;
  return std::nullopt;
}

SupportPlan plan_supports(const std::vector<Region>& regions, const std::vector<Layer>& layers,
                          const SupportOptions& options, const RaftOptions& raft) {
  SupportPlan plan;
  const std::size_t n = layers.size();
  const bool supports = options.placement != SupportPlacement::none;
  if (n == 0 || (!supports && !raft.enabled)) return plan;

  std::vector<clipper::Paths> part(n);
  tbb::parallel_for(std::size_t{0}, n, [&](std::size_t i) {
    if (i < regions.size()) part[i] = clipper::union_nonzero(clipper::simplified(to_clipper(regions[i]), kTolerance));
  });

  std::vector<clipper::Paths> support(n), tops(n);
  if (supports) {
    plan.layers.resize(n);
    // Only from the bed: nothing over any part of the layers below (each layer's shadow,
    // the union of those below it, in turn).
    std::vector<clipper::Paths> shadows;
    if (options.placement == SupportPlacement::buildplate) {
      shadows.resize(n);
      for (std::size_t k = 1; k < n; ++k) {
        shadows[k] = clipper::simplified(clipper::union_nonzero(shadows[k - 1], part[k - 1]), kTolerance);
      }
    }
    // Steps 1-3, each layer on its own.
    std::vector<clipper::Paths> contacts(n);
    tbb::parallel_for(std::size_t{1}, std::max<std::size_t>(n, 1), [&](std::size_t k) {
      LayerContacts c = layer_contacts(part, layers, k, options, shadows.empty() ? nullptr : &shadows[k]);
      contacts[k] = std::move(c.contact);
      plan.layers[k].bridges = std::move(c.bridges);
    });
    for (std::size_t k = 1; k < n; ++k) {
      if (contacts[k].empty()) continue;
      const long j = top_support_layer(layers, k, options.top_contact_distance);
      if (j < 0) continue;  // the bed carries it, across the gap
      auto& top = tops[static_cast<std::size_t>(j)];
      top.insert(top.end(), contacts[k].begin(), contacts[k].end());
    }
    // Step 4.
    support = columns(part, layers, tops, options);
    // Step 5: per layer, the contacts above whose interface reaches down to it.
    std::vector<clipper::Paths> under(n);
    if (options.interface_thickness > 0) {
      for (std::size_t t = 0; t < n; ++t) {
        if (tops[t].empty()) continue;
        for (std::size_t j = lowest_interface_layer(layers, t, options.interface_thickness); j <= t; ++j) {
          under[j].insert(under[j].end(), tops[t].begin(), tops[t].end());
        }
      }
    }
    tbb::parallel_for(std::size_t{0}, n, [&](std::size_t j) {
      if (support[j].empty()) return;
      const clipper::Paths interface =
          under[j].empty() ? clipper::Paths{} : clipper::intersection(support[j], under[j]);
      plan.layers[j].interface = from_clipper(interface);
      plan.layers[j].body = from_clipper(interface.empty() ? support[j]
                                                           : clipper::difference(support[j], interface));
    });
  }
  if (raft.enabled) {
    clipper::Paths first = part[0];
    first.insert(first.end(), support[0].begin(), support[0].end());
    plan_raft(plan, first, raft);
  }
  return plan;
}

double support_volume(const SupportPlan& plan, const std::vector<Layer>& layers) {
  double volume = 0;
  for (std::size_t j = 0; j < plan.layers.size() && j < layers.size(); ++j) {
    volume += (area(plan.layers[j].body) + area(plan.layers[j].interface)) * layers[j].thickness();
  }
  const double raft_area = area(plan.raft_area);
  for (const RaftLayer& layer : plan.raft) volume += raft_area * layer.bounds.thickness();
  return volume;
}

}  // namespace geometry
