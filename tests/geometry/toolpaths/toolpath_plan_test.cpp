// plan_toolpaths: coverage of the region by the rebuilt beads, order, travel, determinism.
#include "geometry/toolpaths/toolpath_plan.h"

#include <doctest/doctest.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <numbers>

#include "geometry/toolpaths/bead_coverage.h"
#include "geometry/toolpaths/toolpath_shapes.h"
#include "geometry/slicing/layer_stack.h"
#include "geometry/mesh/placement.h"
#include "geometry/mesh/repair.h"
#include "geometry/mesh/stl_io.h"
#include "support/solids.h"

namespace toolpath_plan_test {

using namespace geometry;
using namespace toolpath_shapes;

namespace {

// One layer 0.2 mm thick: every point is a bottom (and top) surface, so all of it is solid.
std::vector<LayerToolpaths> single_layer(const Region& region, ToolpathOptions options = {}) {
  options.skirt_loops = 0;
  options.first_layer_width = options.extrusion_width;
  return plan_toolpaths({region}, {Layer{0, 0.2}}, options);
}

void check_covered(const Region& region, const std::vector<ExtrusionPath>& paths) {
  const auto c = bead_coverage::coverage(region, paths);
  INFO("inside " << c.inside << " outside " << c.outside << " double " << c.double_coverage
               << " paths " << paths.size());
  CHECK(c.inside >= 0.98);
  CHECK(c.outside <= 0.02);
}

}  // namespace

TEST_CASE("solid_layer_covers_square") {
  const Region square{{rectangle(0, 0, 20, 20)}};
  const auto plan = single_layer(square);
  REQUIRE(plan.size() == 1);
  check_covered(square, plan[0].paths);
}

TEST_CASE("solid_layer_covers_disc") {
  const Region disc{{circle({5, 5}, 10)}};
  check_covered(disc, single_layer(disc)[0].paths);
}

TEST_CASE("solid_layer_covers_square_with_hole") {
  const Region holed{{rectangle(0, 0, 20, 20), reversed(circle({10, 10}, 4))}};
  check_covered(holed, single_layer(holed)[0].paths);
}

TEST_CASE("solid_layer_covers_strip_narrower_than_two_widths") {
  for (double w : {0.5, 0.6, 0.8, 0.85}) {
    CAPTURE(w);
    const Region strip{{rectangle(0, 0, 15, w)}};
    check_covered(strip, single_layer(strip)[0].paths);
  }
}

TEST_CASE("solid_layer_covers_region_thinner_than_one_width") {
  for (double w : {0.2, 0.3, 0.4}) {
    CAPTURE(w);
    const Region strip{{rectangle(0, 0, 15, w)}};
    const auto paths = single_layer(strip)[0].paths;
    REQUIRE(!paths.empty());
    for (const auto& p : paths) CHECK(p.role == PathRole::thin_wall);
    check_covered(strip, paths);
  }
}

namespace {

// Every layer of a box-like stack: `count` layers 0.2 mm thick with the same region.
std::vector<Layer> layers_of(std::size_t count, double t = 0.2) {
  std::vector<Layer> layers;
  for (std::size_t i = 0; i < count; ++i) layers.push_back({i * t, (i + 1) * t});
  return layers;
}

int rank(PathRole role) {
  switch (role) {
    case PathRole::skirt: return 0;
    case PathRole::inner_wall: return 1;
    case PathRole::outer_wall: return 2;
    case PathRole::thin_wall: return 3;
    default: return 4;  // skins and infill
  }
}

bool same(const std::vector<LayerToolpaths>& a, const std::vector<LayerToolpaths>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (a[i].z_lo != b[i].z_lo || a[i].z_hi != b[i].z_hi) return false;
    if (a[i].paths.size() != b[i].paths.size()) return false;
    for (std::size_t k = 0; k < a[i].paths.size(); ++k) {
      const auto& p = a[i].paths[k];
      const auto& q = b[i].paths[k];
      if (p.role != q.role || p.width != q.width || p.retract_before != q.retract_before ||
          p.points.size() != q.points.size())
        return false;
      for (std::size_t j = 0; j < p.points.size(); ++j)
        if (!(p.points[j] == q.points[j])) return false;
    }
  }
  return true;
}

}  // namespace

TEST_CASE("empty_regions_give_layers_without_paths") {
  const auto layers = layers_of(4);
  const auto plan = plan_toolpaths({Region{}, Region{}}, layers, ToolpathOptions{});
  REQUIRE(plan.size() == 4);
  for (std::size_t i = 0; i < 4; ++i) {
    CHECK(plan[i].z_lo == layers[i].z_lo);
    CHECK(plan[i].z_hi == layers[i].z_hi);
    CHECK(plan[i].paths.empty());
  }
  CHECK(plan_toolpaths({}, {}, ToolpathOptions{}).empty());
}

TEST_CASE("island_prints_inner_walls_then_outer_wall_then_infill") {
  const std::vector<Region> regions(10, Region{{rectangle(0, 0, 20, 20)}});
  ToolpathOptions options;
  options.perimeters = 3;
  const auto plan = plan_toolpaths(regions, layers_of(10), options);
  for (const auto& layer : plan) {
    int walls = 0, last = 0;
    for (const auto& p : layer.paths) {
      CHECK(rank(p.role) >= last);
      last = rank(p.role);
      if (p.role == PathRole::inner_wall || p.role == PathRole::outer_wall) {
        ++walls;
        CHECK(is_closed(p));
        CHECK(signed_area(loop_of(p)) > 0);
      }
    }
    CHECK(walls == 3);
  }
}

TEST_CASE("skirt_goes_first_on_the_first_layer_only") {
  const std::vector<Region> regions(3, Region{{rectangle(0, 0, 20, 20)}});
  ToolpathOptions options;
  options.skirt_loops = 2;
  const auto plan = plan_toolpaths(regions, layers_of(3), options);
  REQUIRE(plan[0].paths.size() > 2);
  CHECK(plan[0].paths[0].role == PathRole::skirt);
  CHECK(plan[0].paths[1].role == PathRole::skirt);
  CHECK(plan[0].paths[2].role != PathRole::skirt);
  for (std::size_t i = 1; i < 3; ++i)
    for (const auto& p : plan[i].paths) CHECK(p.role != PathRole::skirt);
}

TEST_CASE("first_layer_uses_first_layer_width") {
  const std::vector<Region> regions(3, Region{{rectangle(0, 0, 20, 20)}});
  ToolpathOptions options;
  options.extrusion_width = 0.42;
  options.first_layer_width = 0.6;
  const auto plan = plan_toolpaths(regions, layers_of(3), options);
  // Walls at the given width; solid lines as wide as they are apart, which for ~30 lines
  // across the square is within 2% of it (gap fills, short, have their own width).
  for (std::size_t i : {0u, 1u}) {
    const double w = i == 0 ? 0.6 : 0.42;
    int walls = 0, lines = 0;
    for (const auto& p : plan[i].paths) {
      if (p.role == PathRole::outer_wall || p.role == PathRole::inner_wall) {
        ++walls;
        CHECK(p.width == w);
      } else if (p.role != PathRole::thin_wall && length(p.points) > 10) {
        ++lines;
        CHECK(p.width == doctest::Approx(w).epsilon(0.02));
      }
    }
    CHECK(walls == 2);
    CHECK(lines >= 1);
  }
}

TEST_CASE("islands_print_one_after_the_other_nearest_first") {
  // Three squares in a row, the nozzle starting at the front-left: left, middle, right, each
  // finished before the next begins, and every move between them retracts.
  const Region row{{rectangle(0, 0, 10, 10), rectangle(60, 0, 70, 10), rectangle(30, 0, 40, 10)}};
  ToolpathOptions options;
  options.skirt_loops = 0;
  const auto plan = plan_toolpaths({row}, layers_of(1), options);
  const auto& paths = plan[0].paths;
  REQUIRE(!paths.empty());
  auto island = [](const ExtrusionPath& p) {
    const double x = p.points.front().x;
    return x < 20 ? 0 : x < 50 ? 1 : 2;
  };
  int current = island(paths[0]), changes = 0;
  CHECK(current == 0);
  for (std::size_t i = 1; i < paths.size(); ++i) {
    if (island(paths[i]) != current) {
      CHECK(island(paths[i]) == current + 1);
      CHECK(paths[i].retract_before);
      current = island(paths[i]);
      ++changes;
    }
  }
  CHECK(changes == 2);
  CHECK(current == 2);
}

TEST_CASE("a_layer_of_one_island_retracts_only_at_the_layer_change") {
  // Every travel within a square stays inside it: none retracts, however long; the first
  // path of each layer does (the layer change). The infill lines are joined into zig-zags,
  // so there are few travels at all.
  const std::vector<Region> regions(8, Region{{rectangle(0, 0, 30, 30)}});
  for (InfillPattern pattern : {InfillPattern::rectilinear, InfillPattern::grid}) {
    ToolpathOptions options;
    options.infill_pattern = pattern;
    options.skirt_loops = 0;
    const auto plan = plan_toolpaths(regions, layers_of(8), options);
    for (const auto& layer : plan) {
      REQUIRE(!layer.paths.empty());
      CHECK(layer.paths[0].retract_before);
      int zigzags = 0;
      for (std::size_t k = 1; k < layer.paths.size(); ++k) {
        CHECK(!layer.paths[k].retract_before);
        zigzags += rank(layer.paths[k].role) == 4 && length(layer.paths[k].points) > 10;
      }
      // A convex area: one zig-zag per set of lines (and short gap fills where the lines
      // meet the walls at an angle: see infill.h).
      CHECK(zigzags >= 1);
      CHECK(zigzags <= 2);
    }
  }
}

TEST_CASE("aligned_seams_line_up_layer_over_layer") {
  // A box whose back edge tilts one way on even layers and the other on odd ones: the
  // sharper rear corner flips sides every layer, yet every outer wall starts at the corner
  // the first layer chose, within a bead.
  std::vector<Region> regions;
  for (int i = 0; i < 12; ++i) {
    const double tilt = i % 2 ? -0.2 : 0.2;
    regions.push_back(Region{{Loop{{0, 0}, {20, 0}, {20, 10 + std::max(tilt, 0.0)},
                                   {0, 10 + std::max(-tilt, 0.0)}}}});
  }
  ToolpathOptions options;
  options.skirt_loops = 0;
  const auto plan = plan_toolpaths(regions, layers_of(12), options);
  std::vector<Vec2> seams;
  for (const auto& layer : plan) {
    for (const auto& p : layer.paths) {
      if (p.role == PathRole::outer_wall) seams.push_back(p.points.front());
    }
  }
  REQUIRE(seams.size() == 12);
  for (Vec2 s : seams) CHECK(std::hypot(s.x - seams[0].x, s.y - seams[0].y) < options.extrusion_width);
}

namespace {

// 20 mm square for 10 layers, 10 mm square for 10 more, then 20 mm again for 10.
std::vector<Region> stepped_regions() {
  std::vector<Region> regions;
  for (int i = 0; i < 30; ++i) {
    const double side = i >= 10 && i < 20 ? 10 : 20;
    regions.push_back(Region{{rectangle(0, 0, side, side)}});
  }
  return regions;
}

}  // namespace

TEST_CASE("stepped_part_gets_top_skin_on_the_lower_step_and_bottom_skin_over_air") {
  // 20 mm square for 10 layers, 10 mm square for 10 more, then 20 mm again for 10 (an
  // overhang): top skin on layer 9 outside the upper step, bottom skin on layer 20 outside
  // the column, only sparse infill in the middle of each part.
  const std::vector<Region> regions = stepped_regions();
  ToolpathOptions options;
  options.skirt_loops = 0;
  const auto plan = plan_toolpaths(regions, layers_of(30), options);
  auto roles_outside_column = [&](std::size_t layer, PathRole role) {
    int n = 0;
    for (const auto& p : plan[layer].paths) {
      if (p.role != role) continue;
      for (Vec2 v : p.points) n += v.x > 10.5 || v.y > 10.5;
    }
    return n;
  };
  auto count = [&](std::size_t layer, PathRole role) {
    int n = 0;
    for (const auto& p : plan[layer].paths) n += p.role == role;
    return n;
  };
  CHECK(roles_outside_column(9, PathRole::top_skin) > 0);
  CHECK(count(9, PathRole::bottom_skin) == 0);
  CHECK(roles_outside_column(20, PathRole::bottom_skin) > 0);
  CHECK(count(20, PathRole::top_skin) == 0);
  CHECK(count(0, PathRole::bottom_skin) > 0);
  CHECK(count(29, PathRole::top_skin) > 0);
  for (std::size_t i : {5u, 15u, 25u}) {
    CHECK(count(i, PathRole::sparse_infill) > 0);
    CHECK(count(i, PathRole::top_skin) + count(i, PathRole::bottom_skin) +
              count(i, PathRole::solid_infill) == 0);
  }
}

TEST_CASE("only_the_layers_marked_planned_get_paths_and_they_are_the_full_plans") {
  // The stepped part above: layers 0, 9 (top skin outside the column), 20 (bottom skin over
  // air) and 29 planned alone lay what the whole plan lays there (seams may start elsewhere,
  // so by length per role); the others get nothing.
  const std::vector<Region> regions = stepped_regions();
  ToolpathOptions options;
  const auto full = plan_toolpaths(regions, layers_of(30), options);
  options.planned.assign(30, 0);
  for (std::size_t i : {0u, 9u, 20u, 29u}) options.planned[i] = 1;
  const auto some = plan_toolpaths(regions, layers_of(30), options);
  REQUIRE(some.size() == full.size());
  const auto length_of = [](const LayerToolpaths& layer, PathRole role) {
    double total = 0;
    for (const auto& p : layer.paths) {
      if (p.role != role) continue;
      for (std::size_t k = 1; k < p.points.size(); ++k) total += length(p.points[k] - p.points[k - 1]);
    }
    return total;
  };
  for (std::size_t i = 0; i < 30; ++i) {
    CAPTURE(i);
    if (!options.planned[i]) {
      CHECK(some[i].paths.empty());
      continue;
    }
    CHECK(some[i].paths.size() == full[i].paths.size());
    for (PathRole role : {PathRole::outer_wall, PathRole::inner_wall, PathRole::top_skin,
                          PathRole::bottom_skin, PathRole::sparse_infill, PathRole::skirt}) {
      CHECK(length_of(some[i], role) == doctest::Approx(length_of(full[i], role)).epsilon(1e-9));
    }
  }
  CHECK(length_of(some[9], PathRole::top_skin) > 0);
  CHECK(length_of(some[20], PathRole::bottom_skin) > 0);
}

TEST_CASE("sparse_layer_line_length_follows_density") {
  // In the middle of a 40 mm box: the infill area inside 2 walls is the square of side
  // 40 - 4 w grown by the overlap; its lines (at 45 and 135 degrees) total about
  // area * density / w. The connectors between them run along the area's edge, half a bead
  // in (axis-parallel here): at most once round it per set of lines.
  const std::vector<Region> regions(20, Region{{rectangle(0, 0, 40, 40)}});
  ToolpathOptions options;
  const double w = options.extrusion_width;
  const double side = 40 - 4 * w + 2 * options.infill_overlap * w;
  for (double density : {15.0, 30.0}) {
    CAPTURE(density);
    options.infill_density = density;
    const auto plan = plan_toolpaths(regions, layers_of(20), options);
    double lines = 0, connectors = 0;
    for (const auto& p : plan[10].paths) {
      if (p.role != PathRole::sparse_infill) continue;
      for (std::size_t i = 0; i + 1 < p.points.size(); ++i) {
        const Vec2 d = p.points[i + 1] - p.points[i];
        const double piece = std::hypot(d.x, d.y);
        if (std::abs(std::abs(d.x) - std::abs(d.y)) < 1e-9 * piece) {
          lines += piece;
        } else {
          connectors += piece;
          CHECK((std::abs(d.x) < 1e-9 || std::abs(d.y) < 1e-9));
        }
      }
    }
    const double expected = side * side * density / 100 / w;
    CHECK(std::abs(lines - expected) <= 2 * side * std::sqrt(2.0));  // one line each way
    CHECK(connectors <= 2 * 4 * (side - w));
    CHECK(connectors >= 0.5 * 4 * (side - w));  // zig-zags: about half the edge per set
  }
}

TEST_CASE("sparse_lines_of_layers_of_different_thicknesses_stack") {
  // A 40 mm box on layers of 0.15 and 0.4 mm by turns (an adaptive plan's): every layer's
  // sparse lines (45 and 135 degrees, the grid) lie on the lines of the layer below, as on
  // uniform layers; a share per layer thickness (0.418 and 0.364 mm for a 0.45 mm bead) set
  // them 4.18 and 3.64 mm apart, where most of a thin layer's lines lay over the gaps. Each
  // line is known by x - y (45 degrees) or x + y (135 degrees), constant along it.
  std::vector<double> tops{0.3};
  for (int i = 0; i < 15; ++i) tops.push_back(tops.back() + (i % 2 ? 0.4 : 0.15));
  const std::vector<Layer> layers = layers_from_tops(tops);
  const std::vector<Region> regions(layers.size(), Region{{rectangle(0, 0, 40, 40)}});
  ToolpathOptions options;
  options.infill_pattern = InfillPattern::grid;
  const auto plan = plan_toolpaths(regions, layers, options);
  const auto lines_of = [&](std::size_t k) {
    std::vector<double> keys;
    for (const auto& p : plan[k].paths) {
      if (p.role != PathRole::sparse_infill) continue;
      for (std::size_t i = 0; i + 1 < p.points.size(); ++i) {
        const Vec2 a = p.points[i], d = p.points[i + 1] - a;
        if (std::abs(std::abs(d.x) - std::abs(d.y)) > 1e-9 * std::hypot(d.x, d.y)) continue;  // a connector
        keys.push_back(d.x * d.y > 0 ? a.x - a.y : a.x + a.y + 1000);
      }
    }
    return keys;
  };
  std::size_t checked = 0;
  for (std::size_t k = 5; k + 4 < layers.size(); ++k) {  // clear of the three skins each end
    CAPTURE(k);
    const std::vector<double> below = lines_of(k - 1), here = lines_of(k);
    REQUIRE(here.size() > 10);
    for (double key : here) {
      const bool stacked = std::any_of(below.begin(), below.end(), [&](double b) { return std::abs(b - key) < 1e-6; });
      CHECK(stacked);
      checked += stacked;
    }
  }
  CHECK(checked > 50);
}

TEST_CASE("plan_is_the_same_on_one_thread_and_on_many") {
  std::vector<Region> regions;
  for (int i = 0; i < 24; ++i) {
    regions.push_back(Region{{circle({0, 0}, 8 + 0.2 * i, 120), reversed(circle({1, 0}, 3, 60)),
                              rectangle(12 + 0.1 * i, -3, 20, 3)}});
  }
  const auto layers = layers_of(24);
  const ToolpathOptions options;
  const auto many = plan_toolpaths(regions, layers, options);
  std::vector<LayerToolpaths> one;
  tbb::task_arena single(1);
  single.execute([&] { one = plan_toolpaths(regions, layers, options); });
  CHECK(same(many, one));
  CHECK(same(many, plan_toolpaths(regions, layers, options)));
}

TEST_CASE("layer_progress_is_reported_once_per_layer") {
  const std::vector<Region> regions(12, Region{{rectangle(0, 0, 10, 10)}});
  std::atomic<std::size_t> calls{0}, highest{0};
  plan_toolpaths(regions, layers_of(12), ToolpathOptions{}, [&](std::size_t done) {
    ++calls;
    std::size_t seen = highest.load();
    while (done > seen && !highest.compare_exchange_weak(seen, done)) {}
  });
  CHECK(calls == 12);
  CHECK(highest == 12);
}

TEST_CASE("out_of_range_options_are_clamped_not_fatal") {
  const std::vector<Region> regions(3, Region{{rectangle(0, 0, 10, 10)}});
  ToolpathOptions options;
  options.extrusion_width = -1;
  options.first_layer_width = 0;
  options.perimeters = -2;
  options.infill_density = 400;
  options.top_layers = -1;
  options.skirt_loops = -3;
  const auto plan = plan_toolpaths(regions, layers_of(3), options);
  REQUIRE(plan.size() == 3);
  for (const auto& layer : plan)
    for (const auto& p : layer.paths) CHECK(p.width > 0);
}

TEST_CASE("solid_layers_of_sphere_and_holed_cube_are_covered") {
  // Sections of the closed-form solids at each layer's middle; the 3 bottom and 3 top layers
  // are all solid, so their beads must cover each layer's region.
  for (const auto& solid : {solids::sphere(10, 96, 48, {0, 0, 10}),
                            solids::cube_with_round_hole(20, 5, 64)}) {
    const auto layers = layers_of(100);
    std::vector<Region> regions;
    for (const Layer& l : layers) regions.push_back(solid.section(l.z_mid()));
    ToolpathOptions options;
    options.skirt_loops = 0;
    const auto plan = plan_toolpaths(regions, layers, options);
    std::size_t top = 0;
    while (top + 1 < regions.size() && !regions[top + 1].loops.empty()) ++top;
    for (std::size_t i : {std::size_t{0}, std::size_t{1}, std::size_t{2}, top - 2, top - 1, top}) {
      CAPTURE(i);
      check_covered(regions[i], plan[i].paths);
    }
  }
}

TEST_CASE("every_sphere_section_is_covered_even_by_beads_cut_square_at_their_ends") {
  // A 20 mm sphere, all solid (100% lines), to the poles, where sections are discs of a few
  // beads. Beads read as segment x width with square-cut ends, as the G-code reader reads
  // them: the lines' ends do not count their round blob, so the infill must reach the
  // curved inner wall by its connectors and gap fill (lines cut square against a curve leave
  // 2.4% bare on two of these sections).
  const auto sphere = solids::sphere(10, 96, 48, {0, 0, 10});
  const auto layers = layers_of(100);
  std::vector<Region> regions;
  for (const Layer& l : layers) regions.push_back(sphere.section(l.z_mid()));
  ToolpathOptions options;
  options.skirt_loops = 0;
  options.first_layer_width = options.extrusion_width;
  options.infill_density = 100;
  options.infill_pattern = InfillPattern::rectilinear;
  const auto plan = plan_toolpaths(regions, layers, options);
  int sections = 0;
  for (std::size_t i = 0; i < plan.size(); ++i) {
    if (!(area(regions[i]) > 0)) continue;
    ++sections;
    CAPTURE(i);
    CAPTURE(area(regions[i]));
    const auto c = bead_coverage::coverage(regions[i], plan[i].paths, bead_coverage::Ends::cut);
    CHECK(c.inside >= 0.98);
    CHECK(c.outside <= 0.02);
  }
  CHECK(sections == 100);
}

TEST_CASE("solid_plan_covers_the_bunny_layer_by_layer") {
  // The paper's part (bunny, Y up, metres, 50 mm tall), mid sections at 0.15 mm, every layer
  // made solid (skins 1000 layers deep, 100% lines): the beads must fill each section. The
  // losses are the specks and tips narrower than the smallest bead (w/4), which matter only
  // on the smallest sections (the base's first two layers, the ear tips).
  Placement placement;
  placement.units_to_mm = 1000;
  placement.up = Axis::y;
  placement.height = 50;
  const Mesh mesh = place(repair(read_stl(MAHOST_DATA_DIR "/bunny.stl")), placement);
  const LayerStack stack(mesh, uniform_layers(50, 0.15));
  std::vector<Region> regions(stack.size());
  for (std::size_t i = 0; i < stack.size(); ++i) regions[i] = stack.mid(i);
  ToolpathOptions options;
  options.skirt_loops = 0;
  options.infill_density = 100;
  options.infill_pattern = InfillPattern::rectilinear;
  options.top_layers = options.bottom_layers = 1000;
  const auto plan = plan_toolpaths(regions, stack.layers(), options);
  REQUIRE(plan.size() == 334);
  double total = 0, inside = 0, outside = 0;
  for (std::size_t i = 0; i < plan.size(); ++i) {
    const double a = area(regions[i]);
    if (a <= 0) continue;
    CAPTURE(i);
    CAPTURE(a);
    const auto c = bead_coverage::coverage(regions[i], plan[i].paths);
    total += a;
    inside += c.inside * a;
    outside += c.outside * a;
    if (a < 4 * options.extrusion_width * options.extrusion_width) {
      // A speck under two beads square (the base's first layer touches down on 0.16 mm^2)
      // cannot be drawn to a share of itself; it may only spill half a bead's square.
      CHECK(c.outside * a <= 0.5 * options.extrusion_width * options.extrusion_width);
      continue;
    }
    CHECK(c.outside <= 0.05);
    CHECK(c.inside >= (a >= 10 ? 0.95 : 0.9));
  }
  MESSAGE("bunny, solid: " << inside / total << " of the section area covered, "
                           << outside / total << " laid outside");
  CHECK(inside / total >= 0.99);
  CHECK(outside / total <= 0.01);
}

// The support body's zig-zag connectors: laid under an edge that carries something
// in the layer above (the interface's loop; a wider body's line ends), not in a body that
// only goes on up. Lines 2.5 mm apart in a 20 x 10 mm body; separate lines are two points
// each, a zig-zag more.
TEST_CASE("a_support_column_repeated_layer_over_layer_plans_each_layer_as_if_alone") {
  // A table: four legs, the support between them the same on layers 0-8 (copied from the
  // layer below where it repeats it), its interface on 9, the top on 10. Layers 2, 5 and 7
  // planned alone (nothing below them planned to copy from) lay what the whole plan lays.
  const Region legs{{rectangle(0, 0, 4, 4), rectangle(36, 0, 40, 4), rectangle(0, 26, 4, 30),
                     rectangle(36, 26, 40, 30)}};
  const Region between{{rectangle(-2, -2, 42, 32), reversed(rectangle(-0.2, -0.2, 4.2, 4.2)),
                        reversed(rectangle(35.8, -0.2, 40.2, 4.2)),
                        reversed(rectangle(-0.2, 25.8, 4.2, 30.2)),
                        reversed(rectangle(35.8, 25.8, 40.2, 30.2))}};
  const std::vector<Layer> layers = layers_of(11);
  std::vector<Region> part(layers.size(), legs);
  part[10] = Region{{rectangle(-2, -2, 42, 32)}};
  SupportPlan plan;
  plan.layers.resize(layers.size());
  for (std::size_t i = 0; i < 9; ++i) plan.layers[i].body = between;
  plan.layers[9].interface = between;
  ToolpathOptions o;
  const std::vector<LayerToolpaths> full = plan_toolpaths(part, layers, o, plan);
  o.planned.assign(layers.size(), 0);
  for (std::size_t i : {2u, 5u, 7u}) o.planned[i] = 1;
  const std::vector<LayerToolpaths> alone = plan_toolpaths(part, layers, o, plan);
  REQUIRE(alone.size() == full.size());
  // Each path's points, whichever way round it is laid and wherever a loop starts (the
  // order of travel differs): sorted, and the paths sorted.
  const auto support_of = [](const LayerToolpaths& layer) {
    const auto before = [](Vec2 a, Vec2 b) { return a.x != b.x ? a.x < b.x : a.y < b.y; };
    std::vector<std::vector<Vec2>> paths;
    for (const ExtrusionPath& path : layer.paths) {
      if (path.role != PathRole::support) continue;
      std::vector<Vec2> points = path.points;
      std::sort(points.begin(), points.end(), before);
      paths.push_back(std::move(points));
    }
    std::sort(paths.begin(), paths.end(), [&](const auto& a, const auto& b) {
      return std::lexicographical_compare(a.begin(), a.end(), b.begin(), b.end(), before);
    });
    return paths;
  };
  for (std::size_t i : {2u, 5u, 7u}) {
    CAPTURE(i);
    const auto a = support_of(alone[i]), b = support_of(full[i]);
    REQUIRE(!a.empty());
    CHECK(a == b);
  }
}

TEST_CASE("support_body_lines_are_joined_only_under_what_stands_on_their_edge") {
  const Region narrow{{rectangle(0, 0, 20, 10)}}, wide{{rectangle(0, 0, 20, 14)}};
  std::vector<Layer> layers;
  for (int k = 0; k < 6; ++k) layers.push_back({0.2 * k, 0.2 * (k + 1)});
  SupportPlan plan;
  plan.layers.resize(layers.size());
  // 0, 1: the same body; 2 under a wider 3; 3 under 4, the same; 4 under the interface (5).
  plan.layers[0].body = narrow;
  plan.layers[1].body = narrow;
  plan.layers[2].body = narrow;
  plan.layers[3].body = wide;
  plan.layers[4].body = wide;
  plan.layers[5].interface = wide;
  ToolpathOptions o;
  o.support.sheath = false;
  const std::vector<Region> part(layers.size());
  const std::vector<LayerToolpaths> planned = plan_toolpaths(part, layers, o, plan);
  REQUIRE(planned.size() == layers.size());
  const auto joined = [&](std::size_t layer) {
    std::size_t lines = 0, zigzags = 0;
    for (const ExtrusionPath& path : planned[layer].paths) {
      if (path.role != PathRole::support) continue;
      ++lines;
      if (path.points.size() > 2) ++zigzags;
    }
    CAPTURE(layer);
    CHECK(lines > 0);
    return zigzags;
  };
  CHECK(joined(0) == 0);
  CHECK(joined(1) == 0);
  CHECK(joined(2) > 0);   // the wider body above: its line ends past these
  CHECK(joined(3) == 0);  // the same body above
  CHECK(joined(4) > 0);   // under the interface's loop
  // Off, never.
  o.support.connectors = false;
  const std::vector<LayerToolpaths> separate = plan_toolpaths(part, layers, o, plan);
  for (const LayerToolpaths& layer : separate) {
    for (const ExtrusionPath& path : layer.paths) {
      if (path.role == PathRole::support) CHECK(path.points.size() == 2);
    }
  }
}

}  // namespace toolpath_plan_test
