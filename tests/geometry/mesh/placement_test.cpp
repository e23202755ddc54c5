// Placement: units, scale, exact height, proper rotations for --up, centred on the bed, z = 0.
#include "geometry/mesh/placement.h"

#include <doctest/doctest.h>

namespace placement_test {

using namespace geometry;

namespace {

// A closed box [0,a] x [0,b] x [0,c] shifted by `o`, outward faces: volume a b c.
Mesh box(double a, double b, double c, Vec3 o = {0, 0, 0}) {
  Mesh m;
  for (int i = 0; i < 8; ++i) {
    m.vertices.push_back(o + Vec3{(i & 1) ? a : 0, (i & 2) ? b : 0, (i & 4) ? c : 0});
  }
  // Corner i has x from bit 0, y from bit 1, z from bit 2.
  const std::uint32_t quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                                     {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& q : quads) {
    m.faces.push_back({q[0], q[1], q[2]});
    m.faces.push_back({q[0], q[2], q[3]});
  }
  return m;
}

Vec3 size_of(const Mesh& m) {
  const Box3 b = bounding_box(m);
  return b.max - b.min;
}

}  // namespace

TEST_CASE("test_box_is_outward") { CHECK(signed_volume(box(1, 2, 3)) == 6.0); }

TEST_CASE("units_convert_to_mm") {
  const Mesh m = box(1, 2, 3, {5, 5, 5});
  Placement p;
  p.units_to_mm = 1000;  // metres
  Vec3 s = size_of(place(m, p));
  CHECK(s.x == 1000);
  CHECK(s.y == 2000);
  CHECK(s.z == 3000);
  p.units_to_mm = 25.4;  // inches
  p.scale = 2;
  s = size_of(place(m, p));
  CHECK(s.x == doctest::Approx(50.8).epsilon(1e-15));
  CHECK(s.z == doctest::Approx(152.4).epsilon(1e-15));
}

TEST_CASE("height_scales_uniformly_to_exact_height") {
  Placement p;
  p.units_to_mm = 1000;  // ignored in favour of the height
  p.height = 50;
  const Mesh placed = place(box(0.3, 0.7, 0.2, {-1, 2, 3}), p);
  const Box3 b = bounding_box(placed);
  CHECK(b.min.z == 0);
  CHECK(b.max.z == doctest::Approx(50).epsilon(1e-15));
  const Vec3 s = b.max - b.min;
  CHECK(s.x == doctest::Approx(75).epsilon(1e-14));   // 0.3 / 0.2 * 50
  CHECK(s.y == doctest::Approx(175).epsilon(1e-14));  // 0.7 / 0.2 * 50
}

TEST_CASE("part_centred_on_bed_and_resting_on_z0") {
  Placement p;
  p.center = {110, 95};
  const Mesh placed = place(box(4, 6, 8, {-17, 33, -5}), p);
  const Box3 b = bounding_box(placed);
  CHECK(b.min.z == 0);
  CHECK(b.max.z == 8);
  CHECK((b.min.x + b.max.x) / 2 == 110);
  CHECK((b.min.y + b.max.y) / 2 == 95);
}

TEST_CASE("up_y_is_a_proper_rotation") {
  // The model's Y axis becomes Z: a 1 x 2 x 3 box becomes 1 wide, 3 deep, 2 tall, and its
  // outward faces stay outward (positive volume) because the turn has determinant +1.
  Placement p;
  p.up = Axis::y;
  const Mesh placed = place(box(1, 2, 3), p);
  const Vec3 s = size_of(placed);
  CHECK(s.x == 1);
  CHECK(s.y == 3);
  CHECK(s.z == 2);
  CHECK(signed_volume(placed) == doctest::Approx(6).epsilon(1e-15));
}

TEST_CASE("up_x_is_a_proper_rotation") {
  Placement p;
  p.up = Axis::x;
  const Mesh placed = place(box(1, 2, 3), p);
  const Vec3 s = size_of(placed);
  CHECK(s.x == 3);
  CHECK(s.y == 2);
  CHECK(s.z == 1);
  CHECK(signed_volume(placed) == doctest::Approx(6).epsilon(1e-15));
}

TEST_CASE("up_axis_points_up") {
  // A single marked vertex at the top of the model's up axis ends at the top of the bed.
  for (Axis up : {Axis::x, Axis::y, Axis::z}) {
    Mesh m = box(1, 1, 1);
    const Vec3 top = up == Axis::x ? Vec3{1, 0.5, 0.5}
                     : up == Axis::y ? Vec3{0.5, 1, 0.5} : Vec3{0.5, 0.5, 1};
    m.vertices.push_back(top + Vec3{up == Axis::x ? 1.0 : 0, up == Axis::y ? 1.0 : 0,
                                    up == Axis::z ? 1.0 : 0});
    m.faces.push_back({0, 1, static_cast<std::uint32_t>(m.vertices.size() - 1)});
    Placement p;
    p.up = up;
    const Mesh placed = place(m, p);
    CHECK(placed.vertices.back().z == 2);
    CHECK(bounding_box(placed).max.z == 2);
  }
}

TEST_CASE("empty_mesh_stays_empty") {
  Placement p;
  p.height = 10;
  const Mesh placed = place(Mesh{}, p);
  CHECK(placed.faces.empty());
  CHECK(placed.vertices.empty());
}

TEST_CASE("flat_mesh_placed_without_height_scaling") {
  // Nothing to scale to a height: the size stays, the part still lands on z = 0.
  Mesh m;
  m.vertices = {{0, 0, 7}, {2, 0, 7}, {0, 2, 7}};
  m.faces = {{0, 1, 2}};
  Placement p;
  p.height = 50;
  const Mesh placed = place(m, p);
  CHECK(size_of(placed).x == 2);
  CHECK(bounding_box(placed).max.z == 0);
}

TEST_CASE("faces_flat_up_to_float_noise_come_out_exactly_flat") {
  // The stl-models gearwheel stores its bottom at z = +-5e-17: placed, the whole bottom must
  // sit on exactly z = 0 and the top on exactly the height, or a plane at z = 0 misses it.
  Mesh m = box(10, 10, 8);
  for (Vec3& v : m.vertices) v.z += (v.x > 0 ? 4e-17 : -5e-17) + (v.y > 0 ? 1e-15 : 0);
  const Mesh placed = place(m, Placement{});
  for (const Vec3& v : placed.vertices) CHECK((v.z == 0.0 || v.z == 8.0));
}

}  // namespace placement_test
