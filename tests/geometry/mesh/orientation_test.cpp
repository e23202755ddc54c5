// Orientation: rotations, the support volume estimate and the resting face chosen, against
// closed forms.
#include "geometry/mesh/orientation.h"

#include <doctest/doctest.h>

#include <cmath>

#include "geometry/mesh/placement.h"
#include "support/solids.h"

namespace orientation_test {

using namespace geometry;

namespace {

void check_near(Vec3 a, Vec3 b) {
  CHECK(a.x == doctest::Approx(b.x).epsilon(1e-12).scale(1));
  CHECK(a.y == doctest::Approx(b.y).epsilon(1e-12).scale(1));
  CHECK(a.z == doctest::Approx(b.z).epsilon(1e-12).scale(1));
}

// A T: a 10 x 10 x 20 mm stem under a 50 x 10 x 5 mm bar, two boxes touching along the
// stem's top (the bar's underside, two 20 x 10 mm wings, is what overhangs; over the stem
// it faces the stem's top).
Mesh tee() {
  solids::Solid stem = solids::box({-5, -5, 0}, {5, 5, 20});
  solids::Solid bar = solids::box({-25, -5, 20}, {25, 5, 25});
  return solids::combine(std::move(stem), std::move(bar)).mesh;
}

Vec3 size_of(const Mesh& mesh) {
  const Box3 box = bounding_box(mesh);
  return box.max - box.min;
}

}  // namespace

TEST_CASE("rotation_about_an_axis_is_right_handed") {
  check_near(apply(rotation_about({0, 0, 1}, 90), {1, 0, 0}), {0, 1, 0});
  check_near(apply(rotation_about({1, 0, 0}, 90), {0, 1, 0}), {0, 0, 1});
  check_near(apply(rotation_about({0, 2, 0}, 90), {0, 0, 1}), {1, 0, 0});
  // 120 degrees about (1, 1, 1) cycles the axes.
  check_near(apply(rotation_about({1, 1, 1}, 120), {1, 0, 0}), {0, 1, 0});
  CHECK(rotation_about({0, 0, 0}, 90).identity());
  CHECK(rotation_about({0, 0, 1}, 0).identity());
}

TEST_CASE("rotations_compose_right_to_left_and_give_back_their_axis_and_angle") {
  const Rotation x = rotation_about({1, 0, 0}, 90), z = rotation_about({0, 0, 1}, 90);
  // First x, then z: +Y goes to +Z, and stays.
  check_near(apply(z * x, {0, 1, 0}), {0, 0, 1});
  // First z, then x: +Y goes to -X, and stays.
  check_near(apply(x * z, {0, 1, 0}), {-1, 0, 0});
  const AxisAngle aa = axis_angle(rotation_about({0, 3, 4}, 37));
  CHECK(aa.degrees == doctest::Approx(37));
  check_near(aa.axis, {0, 0.6, 0.8});
}

TEST_CASE("rotated_mesh_keeps_its_volume_and_outward_facets") {
  const solids::Solid box = solids::box({0, 0, 0}, {30, 20, 10});
  const Mesh turned = rotated(box.mesh, rotation_about({1, 2, 3}, 47));
  CHECK(signed_volume(turned) == doctest::Approx(6000));
}

TEST_CASE("estimate_is_each_overhang_projected_times_its_height") {
  // A box overhangs nowhere.
  CHECK(support_volume_estimate(solids::box({0, 0, 0}, {30, 20, 10}).mesh, 50) == 0);
  // The T: two 20 x 10 wings 20 mm up (the bar's underside over the stem stands on it).
  CHECK(support_volume_estimate(tee(), 50) == doctest::Approx(2 * 200 * 20).epsilon(1e-6));
  // A cone standing on its tip (apex down): its flank leans 45 degrees from vertical, so
  // at 50 it needs nothing and at 40 all of it: its volume under the flank's projection,
  // the cylinder less the cone, pi r^2 h (1 - 1/3) for the polygon's area.
  const solids::Solid cone = solids::frustum(0, 10, 10, 64);
  const double disc = solids::regular_polygon_area(64, 10);
  CHECK(support_volume_estimate(cone.mesh, 50) == doctest::Approx(0).scale(1));
  // Measured down the centre lines of a grid of 0.2 mm cells (20 mm across / 256, at
  // least 0.2): within a few cells' share of the disc's edge.
  CHECK(support_volume_estimate(cone.mesh, 40) == doctest::Approx(disc * 10 * 2.0 / 3).epsilon(0.003));
}

TEST_CASE("costed_estimate_is_the_material_the_support_lays_in_each_column") {
  // The support's figures: 0.2 mm gaps, 0.4 mm of interface at 80%, a body of 0.45 mm lines
  // 2.5 mm apart (an 18% share).
  SupportCost cost;
  cost.body_share = 0.45 / 2.5;
  cost.interface_share = 0.8;
  cost.interface_thickness = 0.4;
  cost.top_gap = 0.2;
  cost.bottom_gap = 0.2;
  // Per mm^2 of column: nothing within the gaps, then interface, then body.
  CHECK(cost.per_area(0.1, false) == 0);
  CHECK(cost.per_area(0.5, false) == doctest::Approx(0.8 * 0.3));
  CHECK(cost.per_area(0.5, true) == doctest::Approx(0.8 * 0.1));
  CHECK(cost.per_area(10, false) == doctest::Approx(0.8 * 0.4 + 0.18 * 9.4));
  CHECK(cost.per_area(10, true) == doctest::Approx(0.8 * 0.4 + 0.18 * 9.2));
  // The T as given: two 20 x 10 mm wings 20 mm over the bed.
  CHECK(support_volume_estimate(tee(), 50, cost) ==
        doctest::Approx(400 * (0.8 * 0.4 + 0.18 * 19.4)).epsilon(1e-6));
  // A T with a 1 mm stem needs a twentieth of the tall one's column volume, but its columns
  // are nearly all interface: a third of the tall one's material, not a twentieth.
  solids::Solid stem = solids::box({-5, -5, 0}, {5, 5, 1});
  solids::Solid bar = solids::box({-25, -5, 1}, {25, 5, 6});
  const Mesh low = solids::combine(std::move(stem), std::move(bar)).mesh;
  CHECK(support_volume_estimate(low, 50) == doctest::Approx(400).epsilon(1e-6));
  CHECK(support_volume_estimate(low, 50, cost) ==
        doctest::Approx(400 * (0.8 * 0.4 + 0.18 * 0.4)).epsilon(1e-6));
  // Support standing on the part leaves the gap over it too. The T 1 mm over a plate as
  // wide (meshes only concatenated: no faces shared between the T and the plate): the wings'
  // columns 5 mm tall, the stem's 1 mm.
  solids::Solid plate = solids::box({-25, -5, 0}, {25, 5, 15});
  solids::Solid neck = solids::box({-5, -5, 16}, {5, 5, 20});
  solids::Solid top = solids::box({-25, -5, 20}, {25, 5, 25});
  const Mesh held =
      solids::combine(std::move(plate), solids::combine(std::move(neck), std::move(top))).mesh;
  const double wings = 400 * (0.8 * 0.4 + 0.18 * 4.2), under_stem = 100 * (0.8 * 0.4 + 0.18 * 0.2);
  CHECK(support_volume_estimate(held, 50, cost) ==
        doctest::Approx(wings + under_stem).epsilon(1e-6));
}

TEST_CASE("orient_auto_lays_a_t_on_its_side_and_keeps_a_box_lowest") {
  const OrientResult t = orient_for_least_support(tee());
  CHECK(t.input.support_volume == doctest::Approx(8000).epsilon(1e-6));
  CHECK(t.chosen.support_volume == doctest::Approx(0).scale(1));
  CHECK(t.chosen.height == doctest::Approx(10));  // on its 50 x 25 front or back face
  CHECK(std::abs(t.chosen.down.y) == doctest::Approx(1));
  CHECK(t.stable_faces >= 2);
  const Mesh laid = place(rotated(tee(), t.chosen.rotation), Placement{});
  CHECK(size_of(laid).z == doctest::Approx(10));
  CHECK(support_volume_estimate(laid, 50) == doctest::Approx(0).scale(1));

  // A box turned any way goes back down onto a largest face: no support, least height.
  const Mesh box = rotated(solids::box({0, 0, 0}, {30, 20, 10}).mesh, rotation_about({1, 2, 0}, 33));
  const OrientResult b = orient_for_least_support(box);
  CHECK(b.input.support_volume > 0);
  CHECK(b.chosen.support_volume == doctest::Approx(0).scale(1));
  CHECK(b.chosen.height == doctest::Approx(10));
  CHECK(b.chosen.face_area == doctest::Approx(600));
}

TEST_CASE("orient_auto_turns_a_part_that_needs_support_only_for_a_clear_saving") {
  // A ball needs support under it whichever face it rests on, about alike on each: with a
  // margin that asks a face for more than its all back, it stays as given, reported so.
  const Mesh ball = solids::sphere(10, 24, 12, {0, 0, 10}).mesh;
  OrientOptions options;
  const OrientResult free = orient_for_least_support(ball, options);
  CHECK(free.input.support_volume > 0);
  CHECK(free.chosen.support_volume > 0);
  options.turn_margin = 1e9;
  const OrientResult kept = orient_for_least_support(ball, options);
  CHECK(kept.chosen.rotation.identity());
  CHECK(kept.chosen.support_volume == free.input.support_volume);
  CHECK(kept.chosen.height == doctest::Approx(free.input.height));
  // And with no margin, a face whose estimate is the least is taken even when as given is
  // within 10% of it.
  options.turn_margin = 0;
  const OrientResult strict = orient_for_least_support(ball, options);
  CHECK(strict.chosen.support_volume <= free.chosen.support_volume);
  CHECK(strict.chosen.support_volume < strict.input.support_volume);
  CHECK_FALSE(strict.chosen.rotation.identity());
  // The T, on its side, needs nothing: a saving of everything is clear whatever the margin.
  CHECK_FALSE(orient_for_least_support(tee(), options).chosen.rotation.identity());
  // A part that needs no support as given still goes down onto its least height.
  const Mesh standing = solids::box({0, 0, 0}, {10, 20, 30}).mesh;
  const OrientResult laid = orient_for_least_support(standing, options);
  CHECK(laid.chosen.height == doctest::Approx(10));
}

TEST_CASE("orient_auto_turns_a_cone_off_its_tip") {
  // Apex down a cone cannot stand; on its base it needs no support.
  const Mesh tip_down = rotated(solids::cone(10, 10, 64).mesh, rotation_about({1, 0, 0}, 180));
  const OrientResult o = orient_for_least_support(tip_down);
  CHECK(o.chosen.down.z == doctest::Approx(1));  // the base, up as given, goes down
  CHECK(o.chosen.support_volume == doctest::Approx(0).scale(1));
}

TEST_CASE("orient_auto_of_nothing_keeps_the_orientation") {
  const OrientResult o = orient_for_least_support(Mesh{});
  CHECK(o.chosen.rotation.identity());
  CHECK(o.stable_faces == 0);
}

}  // namespace orientation_test
