// Wavefront OBJ read to triangles: a cube of quads in every corner notation exporters use,
// with negative indices, its volume the closed form; and bad lines refused naming the line.
#include <string>

#include <doctest/doctest.h>

#include "geometry/core/error.h"
#include "geometry/mesh/model_io.h"
#include "geometry/mesh/obj_io.h"
#include "geometry/mesh/repair.h"

namespace obj_io_test {

using namespace geometry;

namespace {

// A 10 mm cube of six quads, counter-clockwise from outside, with texture coordinates and
// normals (skipped), comments, groups and a material: what Blender and MeshLab write.
const std::string kCube = R"(# cube
mtllib cube.mtl
o Cube
v 0 0 0
v 10 0 0
v 10 10 0
v 0 10 0
v 0 0 10
v 10 0 10
v 10 10 10
v 0 10 10 1.0
vt 0 0
vn 0 0 -1
g faces
usemtl plastic
s off
f 1/1/1 4/1/1 3/1/1 2/1/1
f 5//1 6//1 7//1 8//1
f 1/1 2/1 6/1 5/1
f 2 3 7 6
f -6 -5 -1 -2
f 4 1 5 8  # the last face
l 1 2
)";

std::string refusal(const std::string& text) {
  try {
    read_obj_text(text, "part.obj");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("a_cube_of_quads_reads_to_twelve_triangles_and_its_volume") {
  const auto triangles = read_obj_text(kCube, "cube.obj");
  CHECK(triangles.size() == 12);
  RepairReport report;
  repair(triangles, &report);
  CHECK(report.closed);
  CHECK(report.volume == doctest::Approx(1000));
  CHECK(report.faces_reoriented == 0);
  // Read by name: the extension says OBJ.
  const ModelFile file = read_model_bytes(kCube, "CUBE.OBJ");
  CHECK(file.format == ModelFormat::obj);
  CHECK(!file.units_recorded);
  CHECK(file.triangles.size() == 12);
}

TEST_CASE("a_polygon_becomes_the_fan_of_its_first_corner") {
  const auto triangles = read_obj_text("v 0 0 0\nv 1 0 0\nv 2 1 0\nv 1 2 0\nv 0 1 0\nf 1 2 3 4 5\n", "p.obj");
  REQUIRE(triangles.size() == 3);
  CHECK(triangles[2].v[1].x == 1);
  CHECK(triangles[2].v[2].y == 1);
}

TEST_CASE("bad_lines_are_refused_naming_the_line") {
  CHECK(refusal("v 0 0\n") == "part.obj: a vertex needs three numbers (line 1)");
  CHECK(refusal("v 0 0 zero\n") == "part.obj: a vertex needs three numbers, not 'zero' (line 1)");
  CHECK(refusal("v 0 0 nan\nv 1 0 0\n") == "part.obj: a vertex coordinate is NaN or infinite (line 1)");
  CHECK(refusal("v 0 0 0\nv 1 0 0\nf 1 2\n") == "part.obj: a face needs three corners, not 2 (line 3)");
  CHECK(refusal("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n") ==
        "part.obj: face corner 3 names vertex 4, but 3 vertices are read so far (line 4)");
  CHECK(refusal("v 0 0 0\nf 1 -2 1\n") == "part.obj: face corner 2 names vertex -2, but 1 vertices are read so far (line 2)");
  CHECK(refusal("v 0 0 0\nf a b c\n") == "part.obj: a face corner must start with a vertex number, not 'a' (line 2)");
  CHECK(refusal("v 0 0 0\n") == "part.obj: OBJ with no faces (1 vertices): there is nothing to print");
}

}  // namespace obj_io_test
