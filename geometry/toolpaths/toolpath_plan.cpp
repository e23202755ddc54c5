#include "geometry/toolpaths/toolpath_plan.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>

#include "geometry/toolpaths/bead_spacing.h"
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

// The paths of an island laid out by shares `share` wide (see plan_island); the infill
// overlap is a fraction of the bead's width.
Island plan_shares(const clipper::Paths& island, std::size_t layer, double share, double width,
                   const ToolpathOptions& o, const Region* core, const Region* below,
                   const Region* above) {
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
  const double angle = o.infill_angle;
  // One set of solid lines for all solid pieces, so that they meet edge to edge; infill at
  // 100% is solid too.
  std::vector<SolidPiece> solid;
  for (auto [piece, role] : {std::pair{&skins.bottom, PathRole::bottom_skin},
                             std::pair{&skins.top, PathRole::top_skin},
                             std::pair{&skins.solid, PathRole::solid_infill},
                             std::pair{&skins.sparse, PathRole::sparse_infill}}) {
    if (role == PathRole::sparse_infill && o.infill_density < 100) continue;
    if (!piece->loops.empty()) solid.push_back({std::move(*piece), role});
  }
  std::vector<ExtrusionPath> solid_paths = solid_infill(solid, share, angle, layer, o.infill_lines);
  for (PathRole role : {PathRole::bottom_skin, PathRole::top_skin, PathRole::solid_infill,
                        PathRole::sparse_infill}) {
    std::vector<ExtrusionPath> group;
    for (ExtrusionPath& path : solid_paths) {
      if (path.role == role) group.push_back(std::move(path));
    }
    result.groups.push_back(std::move(group));
  }
  if (o.infill_density < 100) {
    result.groups.push_back(sparse_infill(skins.sparse, share, o.infill_density,
                                          o.infill_pattern, angle, layer, o.infill_lines));
  }
  std::erase_if(result.groups, [](const auto& group) { return group.empty(); });
  return result;
}

// The island's paths for beads `width` wide on a layer `height` thick. Everything is laid
// out by shares (bead_spacing.h): the strips each bead fills, side by side without overlap,
// in the island shrunk by half what a bead's rounded sides add to its share, so that a bead
// at the edge has its rounded side on the island's edge (the outer wall's centre line lies
// w/2 in). Each path is then widened to the bead that fills its share.
Island plan_island(const clipper::Paths& island, std::size_t layer, double width, double height,
                   const ToolpathOptions& o, const Region* core, const Region* below,
                   const Region* above) {
  const double share = bead_spacing(width, height);
  const double sides = width - share;  // the rounded sides' reach past the share, both sides
  const clipper::Paths shared = sides > 0 ? clipper::offset(island, -sides / 2) : island;
  Island result = plan_shares(shared, layer, share, width, o, core, below, above);
  for (auto& group : result.groups) {
    for (ExtrusionPath& path : group) {
      // A whole share is a whole bead, exactly as wide as the profile says.
      path.width = path.width == share ? width : bead_width_for_spacing(path.width, height);
    }
  }
  return result;
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

}  // namespace

std::vector<LayerToolpaths> plan_toolpaths(const std::vector<Region>& regions,
                                           const std::vector<Layer>& layers,
                                           const ToolpathOptions& options,
                                           const LayerDone& on_layer_done) {
  const ToolpathOptions o = sane(options);
  const std::size_t n = layers.size();
  // Every layer's region, simplified, then cleaned and split into islands by one non-zero
  // union (simplifying first: the union has half the vertices to sweep): a layer past the
  // given regions is empty.
  std::vector<std::vector<clipper::Paths>> island_paths(n);
  std::vector<Region> region(n), outline(n);
  tbb::parallel_for(std::size_t{0}, n, [&](std::size_t i) {
    if (i >= regions.size()) return;
    island_paths[i] = clipper::islands(clipper::simplified(to_clipper(regions[i]), kSimplifyTolerance));
    clipper::Paths all;
    for (const clipper::Paths& island : island_paths[i]) {
      for (const auto& path : island) {
        region[i].loops.push_back(from_clipper(path));
        all.push_back(path);
      }
    }
    outline[i] = from_clipper(clipper::simplified(all, kSkinTolerance));
  });
  // Skins need the neighbours' regions: every layer's core first, then the layers in parallel.
  const std::vector<std::optional<Region>> cores = sparse_cores(
      outline, layers, {o.top_layers, o.bottom_layers, o.top_thickness, o.bottom_thickness});
  const bool top_skins = o.top_layers > 0 || o.top_thickness > 0;
  const bool bottom_skins = o.bottom_layers > 0 || o.bottom_thickness > 0;
  const Region nothing;

  std::vector<std::vector<Island>> islands(n);
  std::vector<ExtrusionPath> skirt_paths;
  std::atomic<std::size_t> done{0};
  tbb::parallel_for(std::size_t{0}, n, [&](std::size_t i) {
    const double width = i == 0 ? o.first_layer_width : o.extrusion_width;
    const double height = layers[i].z_hi - layers[i].z_lo;
    const Region* core = cores[i] ? &*cores[i] : nullptr;
    const Region* below = bottom_skins ? (i > 0 ? &outline[i - 1] : &nothing) : nullptr;
    const Region* above = top_skins ? (i + 1 < n ? &outline[i + 1] : &nothing) : nullptr;
    for (const clipper::Paths& island : island_paths[i]) {
      islands[i].push_back(plan_island(island, i, width, height, o, core, below, above));
    }
    if (i == 0) skirt_paths = skirt(region[0], width, o.skirt_loops, o.skirt_distance);
    if (on_layer_done) on_layer_done(++done);
  });

  // Order: sequential, since each layer starts where the one below ended.
  // Aligned seams remember where the layer below had them, so that they line up.
  std::vector<LayerToolpaths> plan(n);
  Vec2 position = n > 0 ? front_left(region[0]) : Vec2{};
  std::vector<Seam> below, laid;
  for (std::size_t i = 0; i < n; ++i) {
    plan[i].z_lo = layers[i].z_lo;
    plan[i].z_hi = layers[i].z_hi;
    std::vector<ExtrusionPath>& out = plan[i].paths;
    laid.clear();
    if (i == 0) append_nearest_first(std::move(skirt_paths), o.seam, position, out);
    std::vector<Island>& left = islands[i];
    while (!left.empty()) {
      std::size_t next = 0;
      double nearest = std::numeric_limits<double>::infinity();
      for (std::size_t k = 0; k < left.size(); ++k) {
        if (left[k].groups.empty()) continue;
        const auto start = nearest_start(left[k].groups.front(), o.seam, position);
        if (start && start->distance < nearest) { nearest = start->distance; next = k; }
      }
      for (auto& group : left[next].groups) {
        append_nearest_first(std::move(group), o.seam, position, out, &below, &laid);
      }
      left.erase(left.begin() + static_cast<std::ptrdiff_t>(next));
    }
    std::swap(below, laid);
  }
  tbb::parallel_for(std::size_t{0}, n, [&](std::size_t i) {
    mark_retractions(plan[i].paths, region[i], o.retract_min_travel);
  });
  return plan;
}

}  // namespace geometry
