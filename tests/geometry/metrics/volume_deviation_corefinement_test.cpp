// Volume deviation against CGAL's corefinement booleans (the one place that uses them: the
// header is slow to compile, and the booleans take about a second per slab of the bunny):
//   ΔV = vol(S) + vol(P) - 2 vol(S ∩ P),
// S = model ∩ (box x [z_lo, z_hi]) and S ∩ P = model ∩ P, P the layer's prism, each computed
// by PMP::corefine_and_compute_intersection and measured by PMP::volume. That is eq. (1) of
// the paper evaluated the way the paper did it in CATIA, fully independently of the column
// integrals of slab_columns.h.
//
// CGAL's interval arithmetic needs the FPU's rounding mode respected: -frounding-math, which
// CGAL's CMake target adds to the geometry library but not to the test executable.
#pragma GCC optimize("rounding-math")

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/corefinement.h>
#include <CGAL/Polygon_mesh_processing/measure.h>
#include <CGAL/Surface_mesh.h>

#include <doctest/doctest.h>

#include <map>
#include <utility>

#include <string>
#include <vector>

#include "geometry/contour/contour_strategy.h"
#include "geometry/metrics/extruded_layers.h"
#include "geometry/slicing/layer_stack.h"
#include "geometry/mesh/placement.h"
#include "geometry/mesh/repair.h"
#include "geometry/slab/slab.h"
#include "geometry/slab/slab_columns.h"
#include "geometry/mesh/stl_io.h"
#include "geometry/metrics/volume_deviation.h"
#include "support/build_kind.h"
#include "support/solids.h"

namespace volume_deviation_corefinement_test {

namespace PMP = CGAL::Polygon_mesh_processing;
using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using SurfaceMesh = CGAL::Surface_mesh<Kernel::Point_3>;
using geometry::LayerStack;
using geometry::Region;

namespace {

SurfaceMesh to_surface_mesh(const geometry::Mesh& mesh) {
  SurfaceMesh out;
  std::vector<SurfaceMesh::Vertex_index> vertices;
  vertices.reserve(mesh.vertices.size());
  for (const geometry::Vec3& v : mesh.vertices) vertices.push_back(out.add_vertex({v.x, v.y, v.z}));
  for (const auto& f : mesh.faces) out.add_face(vertices[f[0]], vertices[f[1]], vertices[f[2]]);
  return out;
}

// vol(model ∩ other) by corefinement; copies, since corefinement refines its inputs.
double intersection_volume(const SurfaceMesh& model, const SurfaceMesh& other) {
  SurfaceMesh a = model, b = other, result;
  REQUIRE(PMP::corefine_and_compute_intersection(a, b, result));
  return PMP::volume(result);
}

// The prism region x [z_lo, z_hi] exactly as given, one closed shell (the layered-part
// exporter puts its vertices on a grid, which this comparison to 1e-7 must not see): caps
// from the region's triangulation, one wall quad per loop edge.
geometry::Mesh exact_prism(const geometry::Layer& layer, const Region& region) {
  geometry::Mesh mesh;
  const geometry::RegionTriangulation faces = geometry::triangulate_region(region);
  const auto n = static_cast<std::uint32_t>(faces.points.size());
  for (geometry::Vec2 p : faces.points) mesh.vertices.push_back({p.x, p.y, layer.z_lo});
  for (geometry::Vec2 p : faces.points) mesh.vertices.push_back({p.x, p.y, layer.z_hi});
  for (const auto& t : faces.triangles) {
    mesh.faces.push_back({n + t[0], n + t[1], n + t[2]});
    mesh.faces.push_back({t[0], t[2], t[1]});
  }
  std::map<std::pair<double, double>, std::uint32_t> index;
  for (std::uint32_t k = 0; k < n; ++k) index[{faces.points[k].x, faces.points[k].y}] = k;
  for (const geometry::Loop& loop : region.loops) {
    for (std::size_t j = 0, m = loop.size(); j < m && m >= 3; ++j) {
      const geometry::Vec2 a = loop[j], b = loop[(j + 1) % m];
      if (a == b) continue;
      const std::uint32_t ia = index.at({a.x, a.y}), ib = index.at({b.x, b.y});
      mesh.faces.push_back({ia, ib, n + ib});
      mesh.faces.push_back({ia, n + ib, n + ia});
    }
  }
  return mesh;
}

double corefinement_deviation(const geometry::Mesh& model, const geometry::Layer& layer,
                              const Region& region) {
  const geometry::Box3 box = geometry::bounding_box(model);
  const Region around{{{{box.min.x - 1, box.min.y - 1}, {box.max.x + 1, box.min.y - 1},
                        {box.max.x + 1, box.max.y + 1}, {box.min.x - 1, box.max.y + 1}}}};
  const SurfaceMesh solid = to_surface_mesh(model);
  const SurfaceMesh slab_box = to_surface_mesh(exact_prism(layer, around));
  const geometry::Mesh prism_mesh = exact_prism(layer, region);
  const double slab = intersection_volume(solid, slab_box);
  const double prism = geometry::signed_volume(prism_mesh);
  const double common = intersection_volume(solid, to_surface_mesh(prism_mesh));
  return slab + prism - 2 * common;
}

double column_deviation(const LayerStack& stack, std::size_t layer, const Region& region) {
  return geometry::volume_deviation(
      geometry::slab_columns(geometry::slab_of(stack, layer), stack.lower(layer)), region);
}

Region square(double cx, double cy, double half) {
  return {{{{cx - half, cy - half}, {cx + half, cy - half}, {cx + half, cy + half},
            {cx - half, cy + half}}}};
}

}  // namespace

TEST_CASE("deviation_matches_corefinement_on_sphere_and_torus_slabs") {
  const solids::Solid sphere = solids::sphere(10, 48, 24, {0, 0, 10});
  const LayerStack sphere_stack(sphere.mesh, geometry::uniform_layers(20, 0.45));
  for (std::size_t i : {3u, 22u}) {
    const geometry::Layer layer = sphere_stack.layers()[i];
    for (const Region& region : {square(1, -0.5, 6), sphere_stack.mid(i)}) {
      CAPTURE(i);
      CHECK(column_deviation(sphere_stack, i, region) ==
            doctest::Approx(corefinement_deviation(sphere.mesh, layer, region)).epsilon(1e-7));
    }
  }
  const solids::Solid torus = solids::torus(12, 4, 40, 16, {0, 0, 4});
  const LayerStack torus_stack(torus.mesh, geometry::uniform_layers(8, 0.5));
  for (std::size_t i : {1u, 8u}) {
    const geometry::Layer layer = torus_stack.layers()[i];
    Region shifted = torus_stack.lower(i);
    for (auto& loop : shifted.loops)
      for (auto& p : loop) p = p + geometry::Vec2{0.6, 0.3};
    CAPTURE(i);
    CHECK(column_deviation(torus_stack, i, shifted) ==
          doctest::Approx(corefinement_deviation(torus.mesh, layer, shifted)).epsilon(1e-7));
  }
}

// CGAL's corefinement of the bunny's slabs takes 100 s under ASan (most of the sanitizer
// run's tail on 2 cores) and checks no code of ours the sphere and torus above do not: release
// build only.
TEST_CASE("deviation_matches_corefinement_on_bunny_slabs" * test_support::release_build_only()) {
  geometry::Placement placement;
  placement.units_to_mm = 1000;
  placement.up = geometry::Axis::y;
  placement.height = 50;
  const geometry::Mesh bunny = geometry::place(
      geometry::repair(geometry::read_stl(std::string(MAHOST_DATA_DIR) + "/bunny.stl")), placement);
  const geometry::Box3 box = geometry::bounding_box(bunny);
  const LayerStack stack(bunny, geometry::uniform_layers(box.max.z - box.min.z, 0.15));
  for (std::size_t i : {60u, 200u, 310u}) {
    CAPTURE(i);
    const geometry::Layer layer = stack.layers()[i];
    for (const char* kind : {"lower", "ma"}) {
      CAPTURE(kind);
      const Region region = geometry::layer_contour(stack, i, geometry::contour_strategy(kind));
      CHECK(column_deviation(stack, i, region) ==
            doctest::Approx(corefinement_deviation(bunny, layer, region)).epsilon(1e-7));
    }
  }
}

}  // namespace volume_deviation_corefinement_test
