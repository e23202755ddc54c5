// plan_supports: where supports, bridges and the raft go, for parts made of boxes whose every
// layer's region is known exactly.
#include "geometry/core/point_in_region.h"
#include "geometry/support/support_plan.h"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <vector>

#include "geometry/core/clipper.h"

namespace support_plan_test {

using namespace geometry;

namespace {

Region rectangle(double x0, double y0, double x1, double y1) {
  return Region{{{{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}}}};
}

// Each layer's region, the section at its middle.
std::vector<Region> regions_of(const std::vector<Layer>& layers,
                               const std::function<Region(double)>& section) {
  std::vector<Region> regions;
  for (const Layer& layer : layers) regions.push_back(section(layer.z_mid()));
  return regions;
}

// A T: a 10 x 10 stem, 20 mm tall, under a 50 x 10 x 5 mm bar.
Region t_section(double z) {
  if (z < 20) return rectangle(-5, -5, 5, 5);
  if (z < 25) return rectangle(-25, -5, 25, 5);
  return {};
}

clipper::Paths support_of(const SupportPlan& plan, std::size_t layer) {
  clipper::Paths all = to_clipper(plan.layers[layer].body);
  const clipper::Paths more = to_clipper(plan.layers[layer].interface);
  all.insert(all.end(), more.begin(), more.end());
  return clipper::union_nonzero(all);
}

bool supported_at(const SupportPlan& plan, std::size_t layer, Vec2 p) {
  return point_in_region(plan.layers[layer].body, p) ||
         point_in_region(plan.layers[layer].interface, p);
}

std::size_t layer_from(const std::vector<Layer>& layers, double z_lo) {
  for (std::size_t i = 0; i < layers.size(); ++i) {
    if (std::abs(layers[i].z_lo - z_lo) < 1e-9) return i;
  }
  return layers.size();
}

SupportOptions everywhere() {
  SupportOptions o;
  o.placement = SupportPlacement::everywhere;
  return o;
}

}  // namespace

TEST_CASE("t_wings_are_supported_from_the_bed_to_the_top_contact_distance") {
  const std::vector<Layer> layers = uniform_layers(25, 0.2, 0.2);
  const SupportPlan plan = plan_supports(regions_of(layers, t_section), layers, everywhere());
  REQUIRE(plan.layers.size() == layers.size());
  const std::size_t bar = layer_from(layers, 20), top = layer_from(layers, 19.6);
  REQUIRE(bar < layers.size());
  REQUIRE(top == bar - 2);  // its top at 19.8: 0.2 mm of air under the bar
  for (const Vec2 p : {Vec2{15, 0}, Vec2{-15, 0}, Vec2{24.5, 4.5}, Vec2{5.5, -4.5}}) {
    CAPTURE(p.x);
    CAPTURE(p.y);
    for (std::size_t j = 0; j <= top; ++j) CHECK(supported_at(plan, j, p));
    for (std::size_t j = top + 1; j < layers.size(); ++j) CHECK_FALSE(supported_at(plan, j, p));
    // Dense right under the bar, sparse below.
    CHECK(point_in_region(plan.layers[top].interface, p));
    CHECK(point_in_region(plan.layers[top - 1].interface, p));
    CHECK(point_in_region(plan.layers[top - 2].body, p));
    CHECK(point_in_region(plan.layers[0].body, p));
  }
  CHECK_FALSE(supported_at(plan, 0, {0, 0}));  // the stem
  CHECK(plan.raft.empty());
  CHECK(plan.lift == 0);
}

TEST_CASE("support_keeps_the_xy_gap_from_the_part_beside_it") {
  const std::vector<Layer> layers = uniform_layers(25, 0.2, 0.2);
  const std::vector<Region> regions = regions_of(layers, t_section);
  for (const double gap : {0.2, 0.6}) {
    SupportOptions o = everywhere();
    o.xy_gap = gap;
    const SupportPlan plan = plan_supports(regions, layers, o);
    for (std::size_t j = 0; j < layers.size(); ++j) {
      CAPTURE(j);
      const clipper::Paths near = clipper::offset(to_clipper(regions[j]), gap - 1e-3, ClipperLib::jtRound);
      CHECK(clipper::area_mm2(clipper::intersection(support_of(plan, j), near)) < 1e-9);
    }
  }
}

TEST_CASE("support_keeps_the_top_contact_distance_on_layers_of_any_thickness") {
  // Thicknesses cycling through 0.1, 0.15, 0.25 and 0.3 mm (an adaptive plan's kind).
  std::vector<double> tops;
  const double steps[] = {0.1, 0.15, 0.25, 0.3};
  for (double z = 0; z < 25 - 1e-9;) {
    z = std::min(25.0, z + steps[tops.size() % 4]);
    tops.push_back(z);
  }
  const std::vector<Layer> layers = layers_from_tops(tops);
  const std::vector<Region> regions = regions_of(layers, t_section);
  for (const double distance : {0.0, 0.2, 0.3}) {
    CAPTURE(distance);
    SupportOptions o = everywhere();
    o.top_contact_distance = distance;
    const SupportPlan plan = plan_supports(regions, layers, o);
    double highest = -1;  // the top of the support under the wing
    for (std::size_t j = 0; j < layers.size(); ++j) {
      if (supported_at(plan, j, {15, 0})) highest = layers[j].z_hi;
      // No support under any part layer closer above it than the distance.
      for (std::size_t i = j + 1; i < layers.size() && layers[i].z_lo < layers[j].z_hi + distance - 1e-9; ++i) {
        CAPTURE(j);
        CAPTURE(i);
        CHECK(clipper::area_mm2(clipper::intersection(support_of(plan, j), to_clipper(regions[i]))) < 1e-9);
      }
    }
    // The bar's first layer starts where the layer with a middle past 20 mm does.
    const auto bar = std::find_if(layers.begin(), layers.end(), [](const Layer& l) { return l.z_mid() >= 20; });
    REQUIRE(bar != layers.end());
    const double air = bar->z_lo - highest;
    CHECK(air >= distance - 1e-9);
    CHECK(air < distance + 0.3 + 1e-9);  // within one layer more: whole layers
  }
}

TEST_CASE("interface_is_a_thickness_in_mm_rounded_up_to_whole_layers_on_any_stack") {
  // The T on stacks of 0.1, 0.2, 0.25 and 0.4 mm layers under the bar (0.2 mm in it), the
  // support's top 0.2 mm under the bar at least. The interface: whole layers down from the
  // support's top until they are the thickness at least: 0.4 mm is 4 x 0.1, 2 x 0.2,
  // 2 x 0.25 (0.5 mm) or 1 x 0.4 mm (a count of two layers would be 0.8 mm there); 0.3 mm is
  // 2 x 0.25 or 1 x 0.4; 0.05 mm one layer of any.
  struct Case {
    double layer, interface;
    std::size_t dense;
  };
  for (const Case c : {Case{0.1, 0.4, 4}, Case{0.2, 0.4, 2}, Case{0.25, 0.4, 2}, Case{0.4, 0.4, 1},
                       Case{0.25, 0.3, 2}, Case{0.4, 0.3, 1}, Case{0.1, 0.05, 1}}) {
    CAPTURE(c.layer);
    CAPTURE(c.interface);
    std::vector<double> tops;
    for (int k = 1; k * c.layer < 20 + 1e-9; ++k) tops.push_back(k * c.layer);
    for (int k = 1; k <= 25; ++k) tops.push_back(20 + 0.2 * k);
    const std::vector<Layer> layers = layers_from_tops(tops);
    const std::vector<Region> regions = regions_of(layers, t_section);
    SupportOptions o = everywhere();
    o.interface_thickness = c.interface;
    const SupportPlan plan = plan_supports(regions, layers, o);
    const std::size_t bar = layer_from(layers, 20);
    REQUIRE(bar < layers.size());
    // The support's top: the highest layer ending at least 0.2 mm under the bar.
    std::size_t top = bar - 1;
    while (layers[top].z_hi > 19.8 + 1e-9) --top;
    for (const Vec2 p : {Vec2{15, 0}, Vec2{-20, 3}}) {
      for (std::size_t j = 0; j <= top; ++j) {
        CAPTURE(j);
        CHECK(point_in_region(plan.layers[j].interface, p) == (j + c.dense > top));
        CHECK(point_in_region(plan.layers[j].body, p) == (j + c.dense <= top));
      }
    }
    o.interface_thickness = 0;  // none: all of it sparse
    const SupportPlan sparse = plan_supports(regions, layers, o);
    for (std::size_t j = 0; j <= top; ++j) {
      CHECK(sparse.layers[j].interface.loops.empty());
      CHECK(point_in_region(sparse.layers[j].body, {15, 0}));
    }
  }
}

TEST_CASE("contacts_are_widened_across_the_lines_not_along_them") {
  // A 10 mm square stem, 10 mm tall, under a plate reaching 0.6 mm past it in +y: the
  // overhang, x in [-5, 5], y in [5, 5.6], lies between the body's lines at y = 5 and 7.5
  // (2.5 mm apart along x). Its interface spans that band, line to line and half a bead
  // past (its lines cross the body's and end on them), over the overhang's own extent along
  // the lines: a bead longer would hang past the plate's end for nothing.
  auto section = [](double z) {
    if (z < 10) return rectangle(-5, -5, 5, 5);
    if (z < 12) return rectangle(-5, -5, 5, 5.6);
    return Region{};
  };
  const std::vector<Layer> layers = uniform_layers(12, 0.2, 0.2);
  SupportOptions o = everywhere();
  o.bridge_length = 0;
  const SupportPlan plan = plan_supports(regions_of(layers, section), layers, o);
  const std::size_t top = layer_from(layers, 10) - 2;  // 0.2 mm of air, 2 layers of interface
  const double w = o.bead_width;
  for (const std::size_t j : {top - 1, top}) {
    CAPTURE(j);
    for (const Vec2 p : {Vec2{0, 5.4}, Vec2{-4.95, 6.5}, Vec2{4.95, 7.7}}) CHECK(point_in_region(plan.layers[j].interface, p));
    for (const Vec2 p : {Vec2{5.05, 5.4}, Vec2{-5.05, 6.5}, Vec2{0, 7.5 + w / 2 + 0.02}}) {
      CHECK_FALSE(supported_at(plan, j, p));
    }
    CHECK(area(plan.layers[j].interface) == doctest::Approx(10 * (7.5 + w / 2 + 0.01 - 5.2)).epsilon(0.01));
  }
}

TEST_CASE("buildplate_support_stands_only_on_the_bed_and_everywhere_also_on_the_part") {
  // A 40 mm foot 2 mm tall, a stem, and a 40 mm bar at 10 mm: the bar's wings are over the
  // foot.
  auto section = [](double z) {
    if (z < 2) return rectangle(-20, -5, 20, 5);
    if (z < 10) return rectangle(-5, -5, 5, 5);
    if (z < 12) return rectangle(-20, -5, 20, 5);
    return Region{};
  };
  const std::vector<Layer> layers = uniform_layers(12, 0.2, 0.2);
  const std::vector<Region> regions = regions_of(layers, section);
  SupportOptions o = everywhere();
  o.placement = SupportPlacement::buildplate;
  const SupportPlan bed = plan_supports(regions, layers, o);
  for (std::size_t j = 0; j < layers.size(); ++j) CHECK(clipper::area_mm2(support_of(bed, j)) < 1e-9);

  o.placement = SupportPlacement::everywhere;
  o.bottom_contact_distance = 0.2;
  const SupportPlan part = plan_supports(regions, layers, o);
  double lowest = 1e9;
  for (std::size_t j = 0; j < layers.size(); ++j) {
    if (supported_at(part, j, {15, 0})) lowest = std::min(lowest, layers[j].z_lo);
  }
  CHECK(lowest == doctest::Approx(2.2));  // 0.2 mm of air over the foot's top at 2 mm
}

TEST_CASE("a_span_within_the_bridge_length_is_bridged_not_supported") {
  // Two pillars 12 mm apart, 10 mm tall, joined by a beam 2 mm thick.
  auto section = [](double z) {
    if (z < 10) return Region{{rectangle(-10, -5, -6, 5).loops[0], rectangle(6, -5, 10, 5).loops[0]}};
    if (z < 12) return rectangle(-10, -5, 10, 5);
    return Region{};
  };
  const std::vector<Layer> layers = uniform_layers(12, 0.2, 0.2);
  const std::vector<Region> regions = regions_of(layers, section);
  const std::size_t beam = layer_from(layers, 10);
  SupportOptions o = everywhere();
  o.bridge_length = 15;
  const SupportPlan bridged = plan_supports(regions, layers, o);
  REQUIRE(bridged.layers[beam].bridges.size() == 1);
  const Bridge& b = bridged.layers[beam].bridges[0];
  CHECK(std::min(std::fmod(b.angle, 180.0), 180 - std::fmod(b.angle, 180.0)) < 1e-6);
  CHECK(b.span == doctest::Approx(12).epsilon(0.01));
  CHECK(area(b.area) == doctest::Approx(120).epsilon(1e-6));
  for (std::size_t j = 0; j < layers.size(); ++j) CHECK(clipper::area_mm2(support_of(bridged, j)) < 1e-9);

  o.bridge_length = 10;
  const SupportPlan held = plan_supports(regions, layers, o);
  CHECK(held.layers[beam].bridges.empty());
  CHECK(supported_at(held, beam - 2, {0, 0}));
  CHECK(supported_at(held, 0, {0, 0}));

  o.placement = SupportPlacement::none;  // no support, and no bridges either
  CHECK(plan_supports(regions, layers, o).empty());
}

TEST_CASE("enforcer_supports_a_gentle_slope_and_blocker_keeps_a_wing_bare") {
  // A pyramid step: each layer 0.1 mm wider on every side than the one below (within the
  // reach of 0.2 mm: nothing needs support by the angle).
  const std::vector<Layer> layers = uniform_layers(4, 0.2, 0.2);
  auto gentle = [](double z) { const double h = 5 + z / 2; return rectangle(-h, -h, h, h); };
  const std::vector<Region> regions = regions_of(layers, gentle);
  SupportOptions o = everywhere();
  const SupportPlan plain = plan_supports(regions, layers, o);
  for (std::size_t j = 0; j < layers.size(); ++j) CHECK(clipper::area_mm2(support_of(plain, j)) < 1e-9);
  o.enforcers.push_back({{0, -20, 0}, {20, 20, 10}});  // the +x half
  o.min_area = 0;
  const SupportPlan forced = plan_supports(regions, layers, o);
  double right = 0, left = 0;
  for (std::size_t j = 0; j < layers.size(); ++j) {
    const clipper::Paths s = support_of(forced, j);
    right += clipper::area_mm2(clipper::intersection(s, to_clipper(rectangle(0, -20, 20, 20))));
    left += clipper::area_mm2(clipper::intersection(s, to_clipper(rectangle(-20, -20, 0, 20))));
  }
  CHECK(right > 0);
  CHECK(left < 0.05 * right);  // half a bead across the box's edge, widened along the lines

  const std::vector<Layer> t_layers = uniform_layers(25, 0.2, 0.2);
  SupportOptions b = everywhere();
  b.blockers.push_back({{-30, -10, 0}, {0, 10, 30}});  // over the -x wing
  const SupportPlan blocked = plan_supports(regions_of(t_layers, t_section), t_layers, b);
  CHECK(supported_at(blocked, 50, {15, 0}));
  CHECK_FALSE(supported_at(blocked, 50, {-15, 0}));
}

TEST_CASE("raft_lies_under_the_first_layer_grown_by_its_margin") {
  const std::vector<Layer> layers = uniform_layers(25, 0.2, 0.2);
  RaftOptions raft;
  raft.enabled = true;
  raft.margin = 3;
  raft.base_thickness = 0.3;
  raft.interface_layers = 1;
  raft.surface_layers = 2;
  raft.layer_thickness = 0.2;
  raft.air_gap = 0.2;
  SupportOptions none;
  const SupportPlan plan = plan_supports(regions_of(layers, t_section), layers, none, raft);
  REQUIRE(plan.raft.size() == 4);
  CHECK(plan.raft[0].part == RaftPart::base);
  CHECK(plan.raft[0].bounds.z_lo == 0);
  CHECK(plan.raft[0].bounds.z_hi == doctest::Approx(0.3));
  CHECK(plan.raft[1].part == RaftPart::interface);
  CHECK(plan.raft[3].part == RaftPart::surface);
  CHECK(plan.raft[3].bounds.z_hi == doctest::Approx(0.9));
  CHECK(plan.lift == doctest::Approx(1.1));
  // The stem's 10 mm square grown by 3 mm with round corners: 16^2 less (4 - pi) 3^2.
  CHECK(area(plan.raft_area) == doctest::Approx(256 - (4 - 3.14159265) * 9).epsilon(1e-3));
  CHECK(plan.layers.empty());  // no support asked for
}

TEST_CASE("no_support_and_no_raft_plan_nothing_and_empty_input_is_fine") {
  const std::vector<Layer> layers = uniform_layers(25, 0.2, 0.2);
  CHECK(plan_supports(regions_of(layers, t_section), layers, SupportOptions{}).empty());
  CHECK(plan_supports({}, {}, everywhere()).empty());
  const SupportPlan empty = plan_supports(std::vector<Region>(layers.size()), layers, everywhere());
  for (const LayerSupport& layer : empty.layers) {
    CHECK(layer.body.loops.empty());
    CHECK(layer.interface.loops.empty());
  }
}

TEST_CASE("support_volume_is_the_support_area_times_each_layers_thickness") {
  const std::vector<Layer> layers = uniform_layers(25, 0.2, 0.2);
  const SupportPlan plan = plan_supports(regions_of(layers, t_section), layers, everywhere());
  double expected = 0;
  for (std::size_t j = 0; j < layers.size(); ++j) expected += clipper::area_mm2(support_of(plan, j)) * 0.2;
  CHECK(support_volume(plan, layers) == doctest::Approx(expected).epsilon(1e-9));
  // At least the wings' columns (2 x 20 x 10 mm, 19.8 mm tall) less the XY gap beside the
  // stem, at most that widened to the support lines 2.5 mm apart.
  CHECK(expected > 2 * 19.8 * 10 * 19.8 * 0.98);
  CHECK(expected < 2 * 21 * 15 * 19.8);
}

}  // namespace support_plan_test
