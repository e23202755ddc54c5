// An STL's stored normals against the repaired part: right ones agree, flipped ones are
// counted, zero ones have no direction, and a file whose vertex order is inside out but whose
// normals point out agrees once repair has turned it (the peers' way: neither decides alone).
#include <vector>

#include <doctest/doctest.h>

#include "geometry/mesh/repair.h"
#include "geometry/mesh/stored_normals.h"
#include "support/solids.h"

namespace stored_normals_test {

using namespace geometry;

namespace {

std::vector<Triangle> facets_of(const Mesh& mesh, bool reversed = false) {
  std::vector<Triangle> out;
  for (const auto& f : mesh.faces) {
    Triangle t{{mesh.vertices[f[0]], mesh.vertices[f[1]], mesh.vertices[f[2]]}};
    if (reversed) std::swap(t.v[1], t.v[2]);
    out.push_back(t);
  }
  return out;
}

Vec3 outward(const Triangle& t) { return cross(t.v[1] - t.v[0], t.v[2] - t.v[0]); }

}  // namespace

TEST_CASE("normals_are_compared_with_the_repaired_orientation") {
  const Mesh cube = solids::cube(10).mesh;
  const std::vector<Triangle> facets = facets_of(cube);
  std::vector<Vec3> normals;
  for (const Triangle& t : facets) normals.push_back(outward(t));
  SUBCASE("right normals agree") {
    const StoredNormals n = compare_stored_normals(facets, normals, repair(facets));
    CHECK(n.facets == 12);
    CHECK(n.compared == 12);
    CHECK(n.disagreeing == 0);
    CHECK(n.no_direction == 0);
  }
  SUBCASE("three flipped normals are counted") {
    for (int i = 0; i < 3; ++i) normals[i] = -1.0 * normals[i];
    CHECK(compare_stored_normals(facets, normals, repair(facets)).disagreeing == 3);
  }
  SUBCASE("zero and NaN normals have no direction") {
    normals[0] = {0, 0, 0};
    normals[1] = {std::nan(""), 0, 1};
    const StoredNormals n = compare_stored_normals(facets, normals, repair(facets));
    CHECK(n.no_direction == 2);
    CHECK(n.compared == 10);
    CHECK(n.disagreeing == 0);
  }
  SUBCASE("an inside-out file with outward normals agrees after repair") {
    const std::vector<Triangle> inside_out = facets_of(cube, true);
    RepairReport report;
    const Mesh repaired = repair(inside_out, &report);
    CHECK(report.faces_reoriented == 12);
    CHECK(compare_stored_normals(inside_out, normals, repaired).disagreeing == 0);
    // And the vertex order's own normals, which point in, disagree with the repaired part.
    std::vector<Vec3> inward;
    for (const Triangle& t : inside_out) inward.push_back(outward(t));
    CHECK(compare_stored_normals(inside_out, inward, repaired).disagreeing == 12);
  }
}

TEST_CASE("facets_at_a_vertex_the_repair_split_are_compared") {
  // Two cubes touching at one corner: the repair splits that vertex in two, each copy at the
  // same place, and the facets of both cubes there are found by where their corners lie.
  const Mesh pair = solids::combine(solids::box({0, 0, 0}, {10, 10, 10}),
                                    solids::box({10, 10, 10}, {20, 20, 20})).mesh;
  const std::vector<Triangle> facets = facets_of(pair);
  std::vector<Vec3> normals;
  for (const Triangle& t : facets) normals.push_back(outward(t));
  normals[0] = -1.0 * normals[0];
  RepairReport report;
  const Mesh repaired = repair(facets, &report);
  REQUIRE(report.non_manifold_vertices_split == 1);
  const StoredNormals n = compare_stored_normals(facets, normals, repaired);
  CHECK(n.compared == 24);
  CHECK(n.disagreeing == 1);
}

TEST_CASE("empty_input_gives_zeros") {
  const StoredNormals n = compare_stored_normals({}, {}, Mesh{});
  CHECK(n.facets == 0);
  CHECK(n.compared == 0);
}

}  // namespace stored_normals_test
