// slice_mesh against the closed forms of the test solids (tests/support/solids.h).
#include "geometry/slicing/slicer.h"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "geometry/core/clipper.h"
#include "geometry/slicing/layer_stack.h"
#include "geometry/mesh/placement.h"
#include "geometry/core/polygon.h"
#include "geometry/mesh/repair.h"
#include "geometry/mesh/stl_io.h"
#include "support/solids.h"

namespace slicer_test {

using namespace solids;
using geometry::Region;
using geometry::Vec2;

namespace {

std::vector<double> loop_areas(const Region& region) {
  std::vector<double> areas;
  for (const auto& loop : region.loops) areas.push_back(geometry::signed_area(loop));
  std::sort(areas.begin(), areas.end());
  return areas;
}

// The slice equals the polygonal closed form: area and perimeter to 1e-9 relative, and the
// same loops with the same orientation (compared by their signed areas).
void check_section(const Solid& solid, const Region& got, double z) {
  CAPTURE(z);
  const double scale = std::max(1.0, solid.area(z));
  CHECK(geometry::area(got) == doctest::Approx(solid.area(z)).epsilon(1e-9).scale(scale));
  CHECK(geometry::perimeter(got) == doctest::Approx(solid.perimeter(z)).epsilon(1e-9));
  const std::vector<double> got_areas = loop_areas(got);
  const std::vector<double> want_areas = loop_areas(solid.section(z));
  REQUIRE(got_areas.size() == want_areas.size());
  for (std::size_t i = 0; i < got_areas.size(); ++i) {
    CHECK(got_areas[i] == doctest::Approx(want_areas[i]).epsilon(1e-9));
  }
  for (const auto& loop : got.loops) {
    REQUIRE(loop.size() >= 3);
    for (std::size_t i = 0; i < loop.size(); ++i) {
      CHECK_FALSE(loop[i] == loop[(i + 1) % loop.size()]);  // no repeated (closing) point
    }
  }
}

// Every vertex height (planes exactly through vertices, edges and horizontal faces), a point
// inside every band between them, and one below and one above the part.
std::vector<double> probe_heights(const geometry::Mesh& mesh) {
  std::vector<double> z;
  for (const auto& v : mesh.vertices) z.push_back(v.z);
  std::sort(z.begin(), z.end());
  z.erase(std::unique(z.begin(), z.end()), z.end());
  std::vector<double> heights = z;
  for (std::size_t i = 0; i + 1 < z.size(); ++i) {
    heights.push_back(0.5 * (z[i] + z[i + 1]));
    heights.push_back(0.9 * z[i] + 0.1 * z[i + 1]);
  }
  heights.push_back(z.front() - 1);
  heights.push_back(z.back() + 1);
  return heights;
}

void check_all_heights(const Solid& solid) {
  const std::vector<double> heights = probe_heights(solid.mesh);
  const std::vector<Region> sections = geometry::slice_mesh(solid.mesh, heights);
  REQUIRE(sections.size() == heights.size());
  for (std::size_t i = 0; i < heights.size(); ++i) check_section(solid, sections[i], heights[i]);
}

}  // namespace

TEST_CASE("cube_cut_at_bottom_is_full_square_and_at_top_empty") {
  const Solid c = cube(10);
  const std::vector<double> heights{0, 10};
  const auto sections = geometry::slice_mesh(c.mesh, heights);
  REQUIRE(sections[0].loops.size() == 1);
  CHECK(geometry::signed_area(sections[0].loops[0]) == doctest::Approx(100).epsilon(1e-15));
  CHECK(sections[1].loops.empty());
}

TEST_CASE("cube_sections_match_closed_form") { check_all_heights(cube(10)); }
TEST_CASE("box_sections_match_closed_form") { check_all_heights(box({-3, 1, -2}, {4, 6, 5})); }
TEST_CASE("cylinder_sections_match_closed_form") {
  check_all_heights(cylinder(7.5, 20, 64, {3, -4, 1}));
}
TEST_CASE("sphere_sections_match_closed_form") { check_all_heights(sphere(12, 48, 24, {0, 0, 12})); }
TEST_CASE("cone_sections_match_closed_form") { check_all_heights(cone(6, 15, 40)); }
TEST_CASE("frustum_sections_match_closed_form") {
  check_all_heights(frustum(3, 8, 5, 17));
  check_all_heights(frustum(8, 3, 5, 17));
}
TEST_CASE("torus_sections_match_closed_form") { check_all_heights(torus(20, 6, 48, 16, {0, 0, 6})); }
TEST_CASE("cube_with_hole_sections_match_closed_form") {
  check_all_heights(cube_with_square_hole(20, 8));
  check_all_heights(cube_with_round_hole(20, 7, 36));
}

TEST_CASE("torus_equator_is_ccw_outer_and_cw_hole") {
  const Solid t = torus(20, 6, 48, 16);
  const double z = 0;
  const auto sections = geometry::slice_mesh(t.mesh, std::vector<double>{z});
  REQUIRE(sections[0].loops.size() == 2);
  const auto areas = loop_areas(sections[0]);
  CHECK(areas[0] == doctest::Approx(-regular_polygon_area(48, 14)).epsilon(1e-9));
  CHECK(areas[1] == doctest::Approx(regular_polygon_area(48, 26)).epsilon(1e-9));
}

TEST_CASE("cube_with_hole_has_ccw_outer_and_cw_hole") {
  const Solid c = cube_with_square_hole(20, 8);
  const auto sections = geometry::slice_mesh(c.mesh, std::vector<double>{5});
  REQUIRE(sections[0].loops.size() == 2);
  const auto areas = loop_areas(sections[0]);
  CHECK(areas[0] == doctest::Approx(-64).epsilon(1e-12));
  CHECK(areas[1] == doctest::Approx(400).epsilon(1e-12));
}

TEST_CASE("plane_through_vertices_only_gives_the_equator_polygon") {
  // Every equator vertex is exactly on the plane; the limit from above is the equator n-gon.
  const Solid b = bipyramid(5, 7, 0, 4, 10);
  const auto sections = geometry::slice_mesh(b.mesh, std::vector<double>{4, 0, 10});
  REQUIRE(sections[0].loops.size() == 1);
  CHECK(sections[0].loops[0].size() == 7);
  CHECK(geometry::signed_area(sections[0].loops[0]) ==
        doctest::Approx(regular_polygon_area(7, 5)).epsilon(1e-12));
  CHECK(sections[1].loops.empty());  // the bottom apex: a section that shrinks to a point
  CHECK(sections[2].loops.empty());  // the top apex
  check_all_heights(b);
}

TEST_CASE("plane_through_horizontal_edges_gives_the_full_width") {
  const Solid d = diamond_prism(12, 3, 5, 4);
  const auto sections = geometry::slice_mesh(d.mesh, std::vector<double>{5, 1, 9});
  REQUIRE(sections[0].loops.size() == 1);
  CHECK(geometry::area(sections[0]) == doctest::Approx(12 * 6).epsilon(1e-12));
  CHECK(sections[1].loops.empty());  // the bottom ridge: a section that shrinks to a segment
  CHECK(sections[2].loops.empty());
  check_all_heights(d);
}

TEST_CASE("plane_through_horizontal_face_gives_the_section_above") {
  const Solid step = stepped_box({20, 12}, 5, {8, 6}, 7);
  const auto up = geometry::slice_mesh(step.mesh, std::vector<double>{5});
  CHECK(geometry::area(up[0]) == doctest::Approx(48).epsilon(1e-12));
  check_all_heights(step);

  const Solid overhang = stepped_box({8, 6}, 5, {20, 12}, 7);
  const auto down = geometry::slice_mesh(overhang.mesh, std::vector<double>{5});
  CHECK(geometry::area(down[0]) == doctest::Approx(240).epsilon(1e-12));
  check_all_heights(overhang);
}

TEST_CASE("plane_through_a_notch_tip_leaves_no_slit") {
  // The notch's bottom edge touches the plane from above: in the limit the two sides meet
  // along a slit of zero width, which the section must not contain (no spike, no extra loop).
  const Solid prism = lying_prism({{0, 0}, {10, 0}, {10, 6}, {7, 6}, {5, 3}, {3, 6}, {0, 6}}, 0, 8);
  const auto flat = geometry::slice_mesh(prism.mesh, std::vector<double>{3});
  REQUIRE(flat[0].loops.size() == 1);
  CHECK(geometry::signed_area(flat[0].loops[0]) == doctest::Approx(80).epsilon(1e-12));
  CHECK(geometry::perimeter(flat[0]) == doctest::Approx(36).epsilon(1e-12));
  check_all_heights(prism);

  // Revolved, the notch tip is a ring of vertices: the two loops through it cancel.
  const Solid ring = revolve({{0, 0}, {9, 0}, {9, 10}, {7, 10}, {5, 5}, {3, 10}, {0, 10}}, 24);
  const auto round = geometry::slice_mesh(ring.mesh, std::vector<double>{5});
  REQUIRE(round[0].loops.size() == 1);
  CHECK(geometry::signed_area(round[0].loops[0]) ==
        doctest::Approx(regular_polygon_area(24, 9)).epsilon(1e-12));
  check_all_heights(ring);
}

TEST_CASE("rod_inside_tube_gives_outer_hole_and_island") {
  const Solid nested = combine(tube(6, 8, 10, 24), cylinder(3, 10, 24));
  const auto sections = geometry::slice_mesh(nested.mesh, std::vector<double>{5});
  REQUIRE(sections[0].loops.size() == 3);
  const auto areas = loop_areas(sections[0]);
  CHECK(areas[0] == doctest::Approx(-regular_polygon_area(24, 6)).epsilon(1e-12));
  CHECK(areas[1] == doctest::Approx(regular_polygon_area(24, 3)).epsilon(1e-12));
  CHECK(areas[2] == doctest::Approx(regular_polygon_area(24, 8)).epsilon(1e-12));
  check_all_heights(nested);
}

TEST_CASE("a_section_is_the_same_whichever_order_the_faces_come_in") {
  // Loops in the order of, and starting at, their least crossing edge (plane_section.cpp), so
  // the faces' order in the file changes nothing: a rod in a tube (three loops) cut between
  // vertices, where loops close through a table of segment starts, and through a ring of its
  // vertices (its bottom, cut from above), where they are chained the general way.
  const Solid nested = combine(tube(6, 8, 10, 24), cylinder(3, 10, 24));
  geometry::Mesh shuffled = nested.mesh;
  std::reverse(shuffled.faces.begin(), shuffled.faces.end());
  std::rotate(shuffled.faces.begin(), shuffled.faces.begin() + 17, shuffled.faces.end());
  const std::vector<double> heights{3.3, 0};
  const auto a = geometry::slice_mesh(nested.mesh, heights);
  const auto b = geometry::slice_mesh(shuffled, heights);
  REQUIRE(a.size() == b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    CAPTURE(heights[i]);
    CHECK(a[i].loops == b[i].loops);
  }
  CHECK(a[0].loops.size() == 3);
  CHECK(a[1].loops.size() == 3);
}

TEST_CASE("heights_in_any_order_keep_their_order") {
  const Solid c = cone(6, 12, 16);
  const std::vector<double> heights{9, std::numeric_limits<double>::quiet_NaN(), 3, 12, 3, -1,
                                    std::numeric_limits<double>::infinity(), 0};
  const auto sections = geometry::slice_mesh(c.mesh, heights);
  REQUIRE(sections.size() == heights.size());
  for (std::size_t i = 0; i < heights.size(); ++i) {
    CAPTURE(i);
    const double want = std::isfinite(heights[i]) ? c.area(heights[i]) : 0.0;
    CHECK(geometry::area(sections[i]) == doctest::Approx(want).epsilon(1e-12));
  }
}

TEST_CASE("empty_input_gives_empty_sections") {
  CHECK(geometry::slice_mesh(geometry::Mesh{}, std::vector<double>{0, 1}).size() == 2);
  CHECK(geometry::slice_mesh(geometry::Mesh{}, std::vector<double>{0, 1})[1].loops.empty());
  CHECK(geometry::slice_mesh(cube(1).mesh, std::vector<double>{}).empty());
  // A face with a vertex index out of range is no surface at all.
  geometry::Mesh broken = cube(1).mesh;
  broken.faces.push_back({0, 1, 99});
  const auto sections = geometry::slice_mesh(broken, std::vector<double>{0.5});
  CHECK(geometry::area(sections[0]) == doctest::Approx(1).epsilon(1e-12));
}

TEST_CASE("open_chain_is_closed_by_a_straight_line") {
  // Without one side triangle the cylinder is open; its chain at mid-height ends on that
  // triangle's two crossing edges, and the closing line is exactly the missing segment.
  Solid c = cylinder(5, 10, 12);
  const auto it = std::find_if(c.mesh.faces.begin(), c.mesh.faces.end(), [&](const auto& f) {
    const auto& v = c.mesh.vertices;
    return std::min({v[f[0]].z, v[f[1]].z, v[f[2]].z}) == 0 &&
           std::max({v[f[0]].z, v[f[1]].z, v[f[2]].z}) == 10;
  });
  REQUIRE(it != c.mesh.faces.end());
  c.mesh.faces.erase(it);
  const auto sections = geometry::slice_mesh(c.mesh, std::vector<double>{5});
  REQUIRE(sections[0].loops.size() == 1);
  CHECK(geometry::area(sections[0]) == doctest::Approx(c.area(5)).epsilon(1e-12));
}

TEST_CASE("unshared_vertices_give_no_loops") {
  // Chaining is by mesh edge, never by coordinates: a soup whose corners were not merged
  // (repair.h merges them) has no edge in common between faces, so no loop forms.
  const Solid c = cube(10);
  geometry::Mesh soup;
  for (const auto& f : c.mesh.faces) {
    const auto base = static_cast<std::uint32_t>(soup.vertices.size());
    for (auto v : f) soup.vertices.push_back(c.mesh.vertices[v]);
    soup.faces.push_back({base, base + 1, base + 2});
  }
  CHECK(geometry::slice_mesh(soup, std::vector<double>{5})[0].loops.empty());
}

namespace {

// The paper's part: the bunny read, repaired and placed like --up y --units m --height 50.
geometry::Mesh paper_bunny() {
  const auto facets = geometry::read_stl(MAHOST_DATA_DIR "/bunny.stl");
  geometry::Placement placement;
  placement.units_to_mm = 1000;
  placement.up = geometry::Axis::y;
  placement.height = 50;
  return geometry::place(geometry::repair(facets), placement);
}

// Area under the non-zero fill rule, by Clipper's union: equal to the sum of the loops'
// signed areas only when no loop overlaps another with the wrong orientation.
double union_area(const Region& region) {
  return geometry::clipper::area_mm2(geometry::clipper::union_nonzero(geometry::to_clipper(region)));
}

}  // namespace

TEST_CASE("bunny_sections_are_valid_regions_even_through_its_vertices") {
  const geometry::Mesh bunny = paper_bunny();
  REQUIRE(bunny.faces.size() > 69000);
  // 334 layer mid-heights, and 334 planes exactly through vertices of the mesh.
  std::vector<double> heights;
  for (const auto& layer : geometry::uniform_layers(50, 0.15)) heights.push_back(layer.z_mid());
  for (std::size_t i = 0; i < 334; ++i) {
    heights.push_back(bunny.vertices[(i * 7919) % bunny.vertices.size()].z);
  }
  const auto sections = geometry::slice_mesh(bunny, heights);
  double volume = 0;
  for (std::size_t i = 0; i < heights.size(); ++i) {
    CAPTURE(heights[i]);
    const double a = geometry::area(sections[i]);
    if (heights[i] < 49.999) CHECK(a > 0);
    // Clipper rounds to 1 nm: over a ~100 mm outline that moves the area by ~1e-4 mm^2.
    CHECK(union_area(sections[i]) == doctest::Approx(a).epsilon(1e-6).scale(1.0));
    if (i < 334) volume += a * 0.15;
  }
  // Midpoint rule over 0.15 mm layers: the repaired mesh's volume to well within 0.1 %.
  CHECK(volume == doctest::Approx(geometry::signed_volume(bunny)).epsilon(1e-3));
}

}  // namespace slicer_test
