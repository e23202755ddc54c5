#include "geometry/toolpaths/toolpath_plan.h"

#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>

#include "geometry/toolpaths/bead_spacing.h"
#include "geometry/toolpaths/brim.h"
#include "geometry/core/clipper.h"
#include "geometry/toolpaths/infill.h"
#include "geometry/toolpaths/perimeters.h"
#include "geometry/toolpaths/skins.h"
#include "geometry/toolpaths/skirt.h"

namespace geometry {

namespace {

// Region edges are straightened within this: far finer than a printer's step (12.5 um at 80
// steps/mm) or the bead, and it halves the vertices of a section of a fine mesh, which every
// offset and boolean below pays for. (Not coarser: a chord cuts inside a convex edge, and on
// a section a few mm across the beads then leave a sliver along all of it: at 12.5 um, 1%
// of a 10 mm^2 sphere section.)
constexpr double kSimplifyTolerance = 0.005;  // mm

// Where skins begin and end is decided on the regions straightened within this: a skin's
// edge lies inside the part, under or over another layer, where tens of micrometres are
// nothing (and skins narrower than half a bead go to their neighbours anyway), and the
// intersections of seven layers' regions for every layer cost a third as much.
constexpr double kSkinTolerance = 0.05;  // mm

// Below this a bead is not a bead: keeps a zero or negative width from making endless lines.
constexpr double kMinWidth = 0.01;  // mm

// Bridge lines reach this many beads past the unsupported area into its anchors, so that
// both their ends, and the zig-zags' connectors, lie on the layer below.
constexpr double kBridgeAnchor = 2;
// A bridge's piece of an island smaller than this is nothing to lay (mm^2).
constexpr double kNoBridge = 1e-4;
// A body that grows by more than this area past the layer below's, grown by the slack, has
// line ends reaching past the lines below (mm^2, mm): the layer below gets its connectors.
constexpr double kBodyGrowthArea = 0.01;
constexpr double kBodyGrowthSlack = 0.01;

// Whether two layers are as thick, to a nanometre: z_hi - z_lo rounds differently up the
// stack, and layers that differ by that much plan alike.
bool same_thickness(const Layer& a, const Layer& b) {
  return std::abs(a.thickness() - b.thickness()) < 1e-6;
}

// The share the sparse infill's lines are spaced by on every layer: a bead's at the part's
// median layer thickness. Each layer's lines must stack on the layer below's (sparse_infill
// lays them on a grid fixed in the part's frame), and their spacing follows the share: on
// layers of their own thicknesses (adaptive layers) a share of its own per layer
// (0.418 mm at 0.15 mm, 0.364 at 0.4, for a 0.45 mm bead: grid lines 4.18 and 3.64 mm apart
// at 20%) laid a thin layer's lines between a thick one's (the stepped tiers adaptive at 0.3
// mm: 29.1 mm of them unsupported). The beads stay the profile's width, so the infill is a
// little denser on thinner layers and sparser on thicker ones (20.5% at 0.15 mm and 17.9% at
// 0.4 for 20% at a median of 0.2). On uniform layers, the layers' own share.
double sparse_infill_share(const std::vector<Layer>& layers, double width) {
  if (layers.empty()) return bead_spacing(width, 0);
  std::vector<double> thicknesses;
  thicknesses.reserve(layers.size());
  for (const Layer& layer : layers) thicknesses.push_back(layer.thickness());
  const auto middle = thicknesses.begin() + static_cast<std::ptrdiff_t>((thicknesses.size() - 1) / 2);
  std::nth_element(thicknesses.begin(), middle, thicknesses.end());
  return bead_spacing(width, *middle);
}

ToolpathOptions sane(ToolpathOptions o) {
  auto width = [](double w, double fallback) {
    return std::isfinite(w) && w > 0 ? std::max(w, kMinWidth) : fallback;
  };
  o.extrusion_width = width(o.extrusion_width, ToolpathOptions{}.extrusion_width);
  o.first_layer_width = width(o.first_layer_width, o.extrusion_width);
  o.perimeters = std::max(o.perimeters, 0);
  o.infill_density = std::isfinite(o.infill_density) ? std::clamp(o.infill_density, 0.0, 100.0)
                                                     : 0.0;
  if (!std::isfinite(o.infill_angle)) o.infill_angle = 0;
  o.infill_overlap = std::isfinite(o.infill_overlap) ? std::clamp(o.infill_overlap, 0.0, 1.0)
                                                     : 0.0;
  o.top_layers = std::max(o.top_layers, 0);
  o.bottom_layers = std::max(o.bottom_layers, 0);
  o.top_thickness = std::isfinite(o.top_thickness) ? std::max(o.top_thickness, 0.0) : 0.0;
  o.bottom_thickness =
      std::isfinite(o.bottom_thickness) ? std::max(o.bottom_thickness, 0.0) : 0.0;
  o.skirt_loops = std::max(o.skirt_loops, 0);
  if (!std::isfinite(o.skirt_distance)) o.skirt_distance = 0;
  if (std::isnan(o.retract_min_travel)) o.retract_min_travel = 0;
  return o;
}

// One island's paths in groups printed in this order; within a group the travel order picks.
struct Island {
  std::vector<std::vector<ExtrusionPath>> groups;
};

// The bridges' pieces of the infill area, each reaching into the anchors, taken out of the
// skins (and of sparse infill over the air), with the angle it is laid at.
std::vector<std::pair<Region, double>> take_bridges(const std::vector<Bridge>& bridges,
                                                    const clipper::Paths& area, double width,
                                                    Skins& skins) {
  std::vector<std::pair<Region, double>> pieces;
  clipper::Paths taken;
  for (const Bridge& bridge : bridges) {
    clipper::Paths piece =
        clipper::intersection(clipper::offset(to_clipper(bridge.area), kBridgeAnchor * width), area);
    if (!taken.empty()) piece = clipper::difference(piece, taken);
    if (clipper::area_mm2(piece) < kNoBridge) continue;
    taken.insert(taken.end(), piece.begin(), piece.end());
    pieces.emplace_back(from_clipper(piece), bridge.angle);
  }
  if (!taken.empty()) {
    for (Region* skin : {&skins.bottom, &skins.top, &skins.solid, &skins.sparse}) {
      if (!skin->loops.empty()) skin->loops = from_clipper(clipper::difference(to_clipper(*skin), taken)).loops;
    }
  }
  return pieces;
}

// The skins' solid lines, one group per role (bottom, top, solid, and sparse at 100%): one
// set of lines for all solid pieces, so that they meet edge to edge. Takes the skins' areas.
void add_solid_groups(Skins& skins, std::size_t layer, double share, const ToolpathOptions& o,
                      Island& result) {
  std::vector<SolidPiece> solid;
  for (auto [piece, role] : {std::pair{&skins.bottom, PathRole::bottom_skin},
                             std::pair{&skins.top, PathRole::top_skin},
                             std::pair{&skins.solid, PathRole::solid_infill},
                             std::pair{&skins.sparse, PathRole::sparse_infill}}) {
    if (role == PathRole::sparse_infill && o.infill_density < 100) continue;
    if (!piece->loops.empty()) solid.push_back({std::move(*piece), role});
  }
  std::vector<ExtrusionPath> solid_paths =
      solid_infill(solid, share, o.infill_angle, layer, o.infill_lines);
  for (PathRole role : {PathRole::bottom_skin, PathRole::top_skin, PathRole::solid_infill,
                        PathRole::sparse_infill}) {
    std::vector<ExtrusionPath> group;
    for (ExtrusionPath& path : solid_paths) {
      if (path.role == role) group.push_back(std::move(path));
    }
    result.groups.push_back(std::move(group));
  }
}

// Sparse infill's lines in `sparse`, spaced as for shares `sparse_share` wide, with the lines
// along the edge of the core above; laid as the layer's own bead (`share`).
std::vector<ExtrusionPath> sparse_lines(const Region& sparse, std::size_t layer, double share,
                                        double sparse_share, const ToolpathOptions& o,
                                        const Region* core_above) {
  std::vector<ExtrusionPath> lines = sparse_infill(sparse, sparse_share, o.infill_density,
                                                   o.infill_pattern, o.infill_angle, layer,
                                                   o.infill_lines);
  if (core_above) {
    for (ExtrusionPath& edge : skin_edge_lines(sparse, *core_above, sparse_share, o.infill_density,
                                               o.infill_pattern, o.infill_angle, layer)) {
      lines.push_back(std::move(edge));
    }
  }
  for (ExtrusionPath& path : lines) {
    if (path.width == sparse_share) path.width = share;
  }
  return lines;
}

// The paths of an island laid out by shares `share` wide (see plan_island), its sparse
// infill's lines spaced as for shares `sparse_share` wide; the infill overlap is a fraction of
// the bead's width.
Island plan_shares(const clipper::Paths& island, std::size_t layer, double share,
                   double sparse_share, double width,
                   const ToolpathOptions& o, const Region* core, const Region* below,
                   const Region* above, const Region* core_above,
                   const std::vector<Bridge>* bridges) {
  Island result;
  Perimeters walls = perimeters(island, share, o.perimeters);
  // Innermost wall first, outer wall last: the outer surface is laid against walls already
  // there, so it stays where the model says.
  for (auto k = walls.walls.size(); k-- > 0;) result.groups.push_back(std::move(walls.walls[k]));
  result.groups.push_back(std::move(walls.thin_walls));

  // Infill reaches into the innermost wall by the overlap (at most a bead: it stays inside
  // the walls), or without walls up to the island's edge.
  clipper::Paths area = to_clipper(walls.infill_area);
  area = o.perimeters > 0 ? clipper::offset(area, o.infill_overlap * width)
                          : clipper::union_nonzero(area);
  Skins skins = split_skins(from_clipper(area), core, below, above, share);
  if (bridges && !bridges->empty()) {
    for (const auto& [piece, bridge_angle] : take_bridges(*bridges, area, width, skins)) {
      // Layer index 0: the lines run at the bridge's angle itself.
      result.groups.push_back(solid_infill(piece, share, bridge_angle, 0, PathRole::bridge,
                                           o.infill_lines));
    }
  }
  add_solid_groups(skins, layer, share, o, result);
  if (o.infill_density < 100) {
    result.groups.push_back(sparse_lines(skins.sparse, layer, share, sparse_share, o, core_above));
  }
  std::erase_if(result.groups, [](const auto& group) { return group.empty(); });
  return result;
}

// The island's paths for beads `width` wide on a layer `height` thick. Everything is laid
// out by shares (bead_spacing.h): the strips each bead fills, side by side without overlap,
// in the island shrunk by half what a bead's rounded sides add to its share, so that a bead
// at the edge has its rounded side on the island's edge (the outer wall's centre line lies
// w/2 in); the sparse infill's lines spaced by the part's one `sparse_share`
// (sparse_infill_share). Each path is then widened to the bead that fills its share.
Island plan_island(const clipper::Paths& island, std::size_t layer, double width, double height,
                   double sparse_share, const ToolpathOptions& o, const Region* core,
                   const Region* below, const Region* above, const Region* core_above,
                   const std::vector<Bridge>* bridges) {
  const double share = bead_spacing(width, height);
  // A layer as thick as the median (to the rounding of z_hi - z_lo) spaces its lines by its own.
  if (std::abs(sparse_share - share) < 1e-9) sparse_share = share;
  const double sides = width - share;  // the rounded sides' reach past the share, both sides
  const clipper::Paths shared = sides > 0 ? clipper::offset(island, -sides / 2) : island;
  Island result = plan_shares(shared, layer, share, sparse_share, width, o, core, below, above,
                              core_above, bridges);
  for (auto& group : result.groups) {
    for (ExtrusionPath& path : group) {
      // A whole share is a whole bead, exactly as wide as the profile says.
      path.width = path.width == share ? width : bead_width_for_spacing(path.width, height);
    }
  }
  return result;
}

// What the layers' part plans are made of (plan_island's inputs), to find layers that plan
// alike.
struct PartInputs {
  const std::vector<std::vector<clipper::Paths>>& islands;
  const std::vector<Region>& outline;
  const std::vector<std::optional<Region>>& cores;
  const std::vector<Layer>& layers;
  const ToolpathOptions& o;
  const SupportPlan& support;

  // Whether layer k gets paths at all (o.planned; every layer when it is empty).
  bool planned(std::size_t k) const { return k >= o.planned.size() || o.planned[k] != 0; }

  // Whether layers i and j plan their parts alike: the same islands, bead, thickness, core
  // and neighbours (what the skins are cut by), no bridges on either. (Their parity too,
  // which the caller sees to: the solid lines turn every layer.)
  bool alike(std::size_t i, std::size_t j) const {
    auto width = [&](std::size_t k) { return k == 0 ? o.first_layer_width : o.extrusion_width; };
    auto bridged = [&](std::size_t k) {
      return k < support.layers.size() && !support.layers[k].bridges.empty();
    };
    auto below = [&](std::size_t k) { return k > 0 ? &outline[k - 1] : nullptr; };
    auto above = [&](std::size_t k) { return k + 1 < layers.size() ? &outline[k + 1] : nullptr; };
    auto core = [&](std::size_t k) { return cores[k] ? &*cores[k] : nullptr; };
    auto same = [](const Region* a, const Region* b) {
      return a == b || (a && b && a->loops == b->loops);
    };
    auto core_above = [&](std::size_t k) { return k + 1 < layers.size() ? core(k + 1) : nullptr; };
    return islands[i] == islands[j] && width(i) == width(j) && same_thickness(layers[i], layers[j]) &&
           !bridged(i) && !bridged(j) && same(core(i), core(j)) && same(below(i), below(j)) &&
           same(above(i), above(j)) && same(core_above(i), core_above(j));
  }
};

// For every layer, the layer whose part plan it copies, itself if none: that of the layer
// two below (the same parity) when the two plan alike and it is planned. A prism's layers all
// copy two. (A layer left unplanned is its own, and nothing copies it.)
std::vector<std::size_t> plan_sources(const PartInputs& inputs) {
  std::vector<std::size_t> source(inputs.layers.size());
  for (std::size_t i = 0; i < source.size(); ++i) {
    const bool copies = i >= 2 && inputs.planned(i) && inputs.planned(source[i - 2]) &&
                        inputs.alike(i, i - 2);
    source[i] = copies ? source[i - 2] : i;
  }
  return source;
}

Vec2 front_left(const Region& region) {
  Vec2 corner{0, 0};
  bool any = false;
  for (const Loop& loop : region.loops) {
    for (Vec2 p : loop) {
      corner = any ? Vec2{std::min(corner.x, p.x), std::min(corner.y, p.y)} : p;
      any = true;
    }
  }
  return corner;
}

const LayerSupport* support_at(const SupportPlan& support, std::size_t i) {
  return i < support.layers.size() ? &support.layers[i] : nullptr;
}

// The support's bead on layer i: on the bed (layer 0 without a raft) the first layer's width.
double support_bead(std::size_t i, bool raft, const ToolpathOptions& o) {
  return i == 0 && !raft ? o.first_layer_width : o.extrusion_width;
}

// Every layer's region, simplified, then cleaned and split into islands by one non-zero
// union (simplifying first: the union has half the vertices to sweep): a layer past the
// given regions is empty. `outline` is the region straightened for the skins.
struct LayerRegions {
  std::vector<std::vector<clipper::Paths>> islands;
  std::vector<Region> region, outline;
};

LayerRegions layer_regions(const std::vector<Region>& regions, std::size_t n) {
  LayerRegions parts;
  parts.islands.resize(n);
  parts.region.resize(n);
  parts.outline.resize(n);
  tbb::parallel_for(std::size_t{0}, n, [&](std::size_t i) {
    if (i >= regions.size()) return;
    parts.islands[i] = clipper::islands(clipper::simplified(to_clipper(regions[i]), kSimplifyTolerance));
    clipper::Paths all;
    for (const clipper::Paths& island : parts.islands[i]) {
      for (const auto& path : island) {
        parts.region[i].loops.push_back(from_clipper(path));
        all.push_back(path);
      }
    }
    parts.outline[i] = from_clipper(clipper::simplified(all, kSkinTolerance));
  });
  return parts;
}

// Skins need the neighbours' regions: every layer's sparse core (skins.h), before the layers
// are planned. A planned layer needs the core of the layer above too (its skin edges,
// skin_edge_lines).
std::vector<std::optional<Region>> layer_cores(const std::vector<Region>& outline,
                                               const std::vector<Layer>& layers,
                                               const ToolpathOptions& o) {
  std::vector<char> with_cores = o.planned;
  for (std::size_t i = with_cores.size(); i-- > 1;) {
    with_cores[i] = with_cores[i] || with_cores[i - 1];
  }
  return sparse_cores(outline, layers, {o.top_layers, o.bottom_layers, o.top_thickness, o.bottom_thickness},
                      with_cores);
}

// The support's sheath (support_paths.h) on each layer, the ring its beads make and the
// interface's loop, each layer's own, in parallel. A layer whose support is the one below's to
// the bit, and its beads and thickness too, as in a column's straight run (a table's layers
// under its top), repeats it: the same sheath and rings, copied. All empty without supports.
struct SupportRings {
  std::vector<char> repeats;
  std::vector<SupportSheath> sheath;
  std::vector<clipper::Paths> ring, interface_ring;
};

SupportRings support_rings(const SupportPlan& support, const std::vector<Layer>& layers,
                           const ToolpathOptions& o, bool raft) {
  const std::size_t n = layers.size();
  SupportRings rings;
  rings.repeats.assign(n, 0);
  for (std::size_t i = 1; i < n; ++i) {
    const LayerSupport* held = support_at(support, i);
    const LayerSupport* below = support_at(support, i - 1);
    rings.repeats[i] = held && below && held->body.loops == below->body.loops &&
                       held->interface.loops == below->interface.loops &&
                       support_bead(i, raft, o) == support_bead(i - 1, raft, o) &&
                       same_thickness(layers[i], layers[i - 1]);
  }
  if (support.layers.empty()) return rings;
  rings.sheath.resize(n);
  rings.ring.resize(n);
  rings.interface_ring.resize(n);
  tbb::parallel_for(std::size_t{0}, n, [&](std::size_t i) {
    const LayerSupport* held = support_at(support, i);
    if (rings.repeats[i] || !held || (held->body.loops.empty() && held->interface.loops.empty())) {
      return;
    }
    const clipper::Paths interface = to_clipper(held->interface);
    clipper::Paths all = to_clipper(held->body);
    all.insert(all.end(), interface.begin(), interface.end());
    all = clipper::union_nonzero(all);
    // The sheath's bead, and the interface's loop's: where a loop fits (a part narrower
    // than a bead gets none), less what lies inside it.
    const double w = o.extrusion_width;
    rings.sheath[i] = support_sheath(all, held->body, support_bead(i, raft, o), o.support);
    rings.ring[i] = rings.sheath[i].beads;
    if (!interface.empty()) {
      rings.interface_ring[i] = clipper::difference(clipper::opening(interface, w / 2), clipper::offset(interface, -w));
    }
  });
  for (std::size_t i = 1; i < n; ++i) {
    if (!rings.repeats[i]) continue;
    rings.sheath[i] = rings.sheath[i - 1];
    rings.ring[i] = rings.ring[i - 1];
    rings.interface_ring[i] = rings.interface_ring[i - 1];
  }
  return rings;
}

// Where each layer offers a sheath something to rest on: its part, and its own sheath as far
// as that is laid, which is as far as the layer below offers (so a sheath never stands on one
// that was left out). In turn, layer by layer. Empty without supports.
std::vector<clipper::Paths> sheath_carriers(const SupportPlan& support,
                                            const std::vector<Region>& region,
                                            const SupportRings& rings, double width) {
  if (support.layers.empty()) return {};
  const std::size_t n = region.size();
  std::vector<clipper::Paths> carries(n);
  for (std::size_t i = 0; i < n; ++i) {
    // What the layer below offered it, offered again on the same part and support.
    if (rings.repeats[i] && i >= 2 && carries[i - 1] == carries[i - 2] &&
        region[i].loops == region[i - 1].loops) {
      carries[i] = carries[i - 1];
      continue;
    }
    clipper::Paths offered = to_clipper(region[i]);
    if (!rings.ring[i].empty()) {
      const clipper::Paths laid = i == 0 ? rings.ring[i]
                                         : clipper::intersection(rings.ring[i], clipper::offset(carries[i - 1], width / 2));
      offered.insert(offered.end(), laid.begin(), laid.end());
    }
    offered.insert(offered.end(), rings.interface_ring[i].begin(), rings.interface_ring[i].end());
    carries[i] = clipper::union_nonzero(offered);
  }
  return carries;
}

// Each layer's part, of those o.planned marks: planned, or copied from a layer that plans it
// alike (plan_sources); the planned layers first, in parallel, then the copies.
std::vector<std::vector<Island>> plan_parts(const PartInputs& inputs, const LayerDone& on_layer_done) {
  const ToolpathOptions& o = inputs.o;
  const std::vector<Layer>& layers = inputs.layers;
  const std::size_t n = layers.size();
  const bool top_skins = o.top_layers > 0 || o.top_thickness > 0;
  const bool bottom_skins = o.bottom_layers > 0 || o.bottom_thickness > 0;
  const double sparse_share = sparse_infill_share(layers, o.extrusion_width);
  const Region nothing;
  const std::vector<std::size_t> source = plan_sources(inputs);
  std::vector<std::vector<Island>> islands(n);
  std::atomic<std::size_t> done{0};
  tbb::parallel_for(std::size_t{0}, n, [&](std::size_t i) {
    if (!inputs.planned(i)) {
      if (on_layer_done) on_layer_done(++done);
      return;
    }
    if (source[i] != i) return;
    const double width = i == 0 ? o.first_layer_width : o.extrusion_width;
    const double height = layers[i].z_hi - layers[i].z_lo;
    const Region* core = inputs.cores[i] ? &*inputs.cores[i] : nullptr;
    const Region* below = bottom_skins ? (i > 0 ? &inputs.outline[i - 1] : &nothing) : nullptr;
    const Region* above = top_skins ? (i + 1 < n ? &inputs.outline[i + 1] : &nothing) : nullptr;
    const LayerSupport* held = support_at(inputs.support, i);
    const std::vector<Bridge>* bridges = held ? &held->bridges : nullptr;
    const Region* core_above = i + 1 < n && inputs.cores[i + 1] ? &*inputs.cores[i + 1] : nullptr;
    for (const clipper::Paths& island : inputs.islands[i]) {
      islands[i].push_back(plan_island(island, i, width, height, sparse_share, o, core, below,
                                       above, core_above, bridges));
    }
    if (on_layer_done) on_layer_done(++done);
  });
  tbb::parallel_for(std::size_t{0}, n, [&](std::size_t i) {
    if (!inputs.planned(i) || source[i] == i) return;
    islands[i] = islands[source[i]];
    if (on_layer_done) on_layer_done(++done);
  });
  return islands;
}

// The support's islands of each planned layer (the body and the interface, each an island of
// its own in the nearest-first order), and where travels need no retraction: the part, with
// its support where there is any.
struct SupportLayers {
  std::vector<std::vector<Island>> islands;
  std::vector<Region> travel_region;
};

SupportLayers plan_support_layers(const PartInputs& inputs, const std::vector<Region>& region,
                                  const SupportRings& rings,
                                  const std::vector<clipper::Paths>& carries, bool raft) {
  const SupportPlan& support = inputs.support;
  const ToolpathOptions& o = inputs.o;
  const std::vector<Layer>& layers = inputs.layers;
  const std::size_t n = layers.size();
  // The body's zig-zag connectors run along its edge: they are laid where something stands
  // on that edge in the layer above, the interface's loop or the body's own line ends where
  // the body grows (a line end reaching past the one below rests on its connector), and
  // nowhere else (a body that only goes on up, or narrows, has its lines on the lines below:
  // connectors there are filament that carries nothing; 9% of the T's support).
  const auto body_connected = [&](std::size_t i) {
    const LayerSupport* held = support_at(support, i);
    const LayerSupport* up = i + 1 < n ? support_at(support, i + 1) : nullptr;
    if (!held || !up) return false;
    if (!up->interface.loops.empty()) return true;
    if (up->body.loops.empty()) return false;
    const clipper::Paths grown = clipper::difference(
        to_clipper(up->body), clipper::offset(to_clipper(held->body), kBodyGrowthSlack));
    return clipper::area_mm2(grown) > kBodyGrowthArea;
  };
  SupportLayers result;
  result.islands.resize(n);
  result.travel_region.resize(n);
  // A layer that repeats the one below (above), stands on what that one stood on and has what
  // that one had above it (so its connectors are laid alike) on the same part: a copy of that
  // one's, after the others.
  std::vector<char> copies(n, 0);
  for (std::size_t i = 2; i + 1 < n; ++i) {
    copies[i] = rings.repeats[i] && rings.repeats[i + 1] && inputs.planned(i) && inputs.planned(i - 1) &&
                carries[i - 1] == carries[i - 2] && region[i].loops == region[i - 1].loops;
  }
  tbb::parallel_for(std::size_t{0}, n, [&](std::size_t i) {
    if (!inputs.planned(i) || copies[i]) return;
    const LayerSupport* held = support_at(support, i);
    const double height = layers[i].thickness();
    result.travel_region[i] = region[i];
    if (held && !(held->body.loops.empty() && held->interface.loops.empty())) {
      const double bead = support_bead(i, raft, o);
      // What carries a sheath here: the layer below's sheath where it is laid, and its part;
      // on the bed or the raft, anything.
      std::optional<Region> carried;
      if (i > 0) carried = from_clipper(carries[i - 1]);
      SupportPathOptions body_options = o.support;
      body_options.connectors = o.support.connectors && body_connected(i);
      for (auto paths : {support_body_paths(held->body, bead, body_options, rings.sheath[i], carried ? &*carried : nullptr),
                         support_interface_paths(held->interface, bead, height, o.support)}) {
        if (!paths.empty()) result.islands[i].push_back(Island{{std::move(paths)}});
      }
      clipper::Paths all = to_clipper(region[i]);
      for (const Region* r : {&held->body, &held->interface}) {
        const clipper::Paths more = to_clipper(*r);
        all.insert(all.end(), more.begin(), more.end());
      }
      result.travel_region[i] = from_clipper(clipper::union_nonzero(all));
    }
  });
  for (std::size_t i = 0; i < n; ++i) {
    if (copies[i]) {
      result.islands[i] = result.islands[i - 1];
      result.travel_region[i] = result.travel_region[i - 1];
    }
  }
  return result;
}

// The raft's layers' paths (support_paths.h), each its own.
std::vector<std::vector<ExtrusionPath>> raft_layer_paths(const SupportPlan& support, const ToolpathOptions& o) {
  const std::size_t r = support.raft.size();
  std::vector<std::vector<ExtrusionPath>> raft_layers(r);
  tbb::parallel_for(std::size_t{0}, r, [&](std::size_t k) {
    const RaftLayer& layer = support.raft[k];
    const double width = k == 0 ? o.first_layer_width : o.extrusion_width;
    raft_layers[k] = raft_paths(support.raft_area, layer.part, k, width,
                                layer.bounds.thickness(), o.support);
  });
  return raft_layers;
}

// The first printed layer's skirt loops, then its brim, round `first` (the raft, or the part's
// first layer and its support).
std::vector<ExtrusionPath> skirt_and_brim(const Region& first, const ToolpathOptions& o) {
  const double width = o.first_layer_width;
  std::vector<ExtrusionPath> paths = brim(first, width, o.brim_width);
  const double extent = brim_extent(width, o.brim_width);
  const Region around =
      extent > 0 ? from_clipper(clipper::offset(to_clipper(first), extent, ClipperLib::jtRound)) : first;
  std::vector<ExtrusionPath> loops = skirt(around, width, o.skirt_loops, o.skirt_distance);
  paths.insert(paths.begin(), std::make_move_iterator(loops.begin()), std::make_move_iterator(loops.end()));
  return paths;
}

// The layers' paths in printing order: sequential, since each layer starts where the one
// below ended, from `start`; the skirt and brim first on the first layer printed, then each
// layer's islands nearest first. Aligned seams remember where the layer below had them, so
// that they line up.
std::vector<LayerToolpaths> order_layers(const SupportPlan& support, const std::vector<Layer>& layers,
                                         const ToolpathOptions& o,
                                         std::vector<std::vector<ExtrusionPath>> raft_layers,
                                         std::vector<ExtrusionPath> skirt_paths,
                                         std::vector<std::vector<Island>> islands, Vec2 start) {
  const std::size_t r = raft_layers.size(), n = layers.size();
  std::vector<LayerToolpaths> plan(r + n);
  Vec2 position = start;
  std::vector<Seam> below, laid;
  for (std::size_t k = 0; k < r; ++k) {
    plan[k].z_lo = support.raft[k].bounds.z_lo;
    plan[k].z_hi = support.raft[k].bounds.z_hi;
    if (k == 0) append_nearest_first(std::move(skirt_paths), o.seam, position, plan[k].paths);
    append_nearest_first(std::move(raft_layers[k]), o.seam, position, plan[k].paths);
  }
  for (std::size_t i = 0; i < n; ++i) {
    plan[r + i].z_lo = layers[i].z_lo + support.lift;
    plan[r + i].z_hi = layers[i].z_hi + support.lift;
    std::vector<ExtrusionPath>& out = plan[r + i].paths;
    laid.clear();
    if (i == 0 && r == 0) append_nearest_first(std::move(skirt_paths), o.seam, position, out);
    std::vector<Island>& left = islands[i];
    while (!left.empty()) {
      std::size_t next = 0;
      double nearest = std::numeric_limits<double>::infinity();
      for (std::size_t k = 0; k < left.size(); ++k) {
        if (left[k].groups.empty()) continue;
        const auto start_at = nearest_start(left[k].groups.front(), o.seam, position);
        if (start_at && start_at->distance < nearest) { nearest = start_at->distance; next = k; }
      }
      for (auto& group : left[next].groups) {
        append_nearest_first(std::move(group), o.seam, position, out, &below, &laid);
      }
      left.erase(left.begin() + static_cast<std::ptrdiff_t>(next));
    }
    std::swap(below, laid);
  }
  return plan;
}

}  // namespace

std::vector<LayerToolpaths> plan_toolpaths(const std::vector<Region>& regions,
                                           const std::vector<Layer>& layers,
                                           const ToolpathOptions& options,
                                           const LayerDone& on_layer_done) {
  return plan_toolpaths(regions, layers, options, SupportPlan{}, on_layer_done);
}

std::vector<LayerToolpaths> plan_toolpaths(const std::vector<Region>& regions,
                                           const std::vector<Layer>& layers,
                                           const ToolpathOptions& options,
                                           const SupportPlan& support,
                                           const LayerDone& on_layer_done) {
  const ToolpathOptions o = sane(options);
  const std::size_t n = layers.size();
  const bool raft = !support.raft.empty();
  const LayerRegions parts = layer_regions(regions, n);
  const std::vector<std::optional<Region>> cores = layer_cores(parts.outline, layers, o);
  const SupportRings rings = support_rings(support, layers, o, raft);
  const PartInputs inputs{parts.islands, parts.outline, cores, layers, o, support};
  // What each layer offers the sheath above, a chain up the stack, beside the parts' plans,
  // which need none of it. Sized first: in a cancelled task group (a slice given up on while
  // it samples layers for an estimate) TBB may skip either, and what follows still indexes
  // them.
  std::vector<clipper::Paths> carries(support.layers.empty() ? 0 : n);
  std::vector<std::vector<Island>> islands(n);
  tbb::parallel_invoke([&] { carries = sheath_carriers(support, parts.region, rings, o.extrusion_width); },
                       [&] { islands = plan_parts(inputs, on_layer_done); });
  SupportLayers held = plan_support_layers(inputs, parts.region, rings, carries, raft);
  for (std::size_t i = 0; i < n; ++i) {
    for (Island& island : held.islands[i]) islands[i].push_back(std::move(island));
  }
  const Region* first = raft ? &support.raft_area : n > 0 ? &held.travel_region[0] : nullptr;
  std::vector<LayerToolpaths> plan =
      order_layers(support, layers, o, raft_layer_paths(support, o),
                   first ? skirt_and_brim(*first, o) : std::vector<ExtrusionPath>{}, std::move(islands),
                   first ? front_left(*first) : Vec2{});
  const std::size_t r = support.raft.size();
  tbb::parallel_for(std::size_t{0}, r + n, [&](std::size_t k) {
    const Region& where = k < r ? support.raft_area : held.travel_region[k - r];
    mark_retractions(plan[k].paths, where, o.retract_min_travel);
  });
  return plan;
}

}  // namespace geometry
