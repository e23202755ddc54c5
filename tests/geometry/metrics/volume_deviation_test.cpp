// Volume deviation ΔV = vol(S △ P) against values derived by hand for polygonal solids whose
// sections are concentric regular n-gons of the same phase (cone, UV sphere, torus): then
// C(z) △ C(h) is a set of bands between nested n-gons and
//   ΔV(C(h)) = sum over boundaries b of ∫ k |rho_b(z)^2 - rho_b(h)^2| dz,  k = n/2 sin(2 pi/n),
// with rho_b linear between profile vertex heights, so Simpson's rule on the pieces split at
// those heights and at the roots rho_b(z) = rho_b(h) is exact. Also against the smooth
// sphere's formula (fine mesh, stated tolerance) and against an independent integration of
// Clipper XOR areas over z for regions that cross the sections.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <numbers>
#include <vector>

#include "geometry/core/clipper.h"
#include "geometry/slicing/layer_stack.h"
#include "geometry/slab/slab.h"
#include "geometry/slab/slab_columns.h"
#include "geometry/metrics/volume_deviation.h"
#include "geometry/metrics/volume_limit.h"
#include "support/solids.h"

namespace volume_deviation_test {

using geometry::Layer;
using geometry::LayerStack;
using geometry::Region;
using geometry::Vec2;

namespace {

constexpr double kPi = std::numbers::pi;

// Radii of the section boundaries of a solid of revolution at height z (the profile's
// crossings with the line at z, sorted), as the solids generator builds it.
std::vector<double> boundary_radii(const std::vector<Vec2>& profile, double z) {
  std::vector<double> rho;
  for (std::size_t i = 0, n = profile.size(); i < n; ++i) {
    Vec2 a = profile[i], b = profile[(i + 1) % n];
    if ((a.y <= z) == (b.y <= z)) continue;
    const double t = (z - a.y) / (b.y - a.y);
    rho.push_back(a.x + t * (b.x - a.x));
  }
  std::sort(rho.begin(), rho.end());
  return rho;
}

// ∫ over [z_lo, z_hi] of k sum_b |rho_b(z)^2 - rho_b(h)^2| dz, exactly (see the file comment).
double exact_nested_deviation(const std::vector<Vec2>& profile, int n, double z_lo, double z_hi,
                              double h) {
  const double k = n / 2.0 * std::sin(2 * kPi / n);
  std::vector<double> cuts{z_lo, z_hi};
  for (Vec2 p : profile)
    if (p.y > z_lo && p.y < z_hi) cuts.push_back(p.y);
  std::sort(cuts.begin(), cuts.end());
  // The region's boundaries (at h, limit from above: just above h inside the profile).
  const std::vector<double> target = boundary_radii(profile, h);
  double total = 0;
  for (std::size_t i = 0; i + 1 < cuts.size(); ++i) {
    const double a = cuts[i], b = cuts[i + 1];
    if (!(b > a)) continue;
    // rho_b is linear on (a, b): read it at two interior heights and extend.
    const double za = a + (b - a) / 3, zb = a + 2 * (b - a) / 3;
    const std::vector<double> ra = boundary_radii(profile, za), rb = boundary_radii(profile, zb);
    REQUIRE(ra.size() == target.size());
    for (std::size_t j = 0; j < ra.size(); ++j) {
      const double slope = (rb[j] - ra[j]) / (zb - za);
      const auto rho = [&](double z) { return ra[j] + slope * (z - za); };
      const auto f = [&](double z) { return k * std::abs(rho(z) * rho(z) - target[j] * target[j]); };
      std::vector<double> pieces{a, b};
      if (slope != 0) {
        const double root = za + (target[j] - ra[j]) / slope;
        if (root > a && root < b) pieces.insert(pieces.begin() + 1, root);
      }
      for (std::size_t p = 0; p + 1 < pieces.size(); ++p) {
        const double u = pieces[p], v = pieces[p + 1];
        total += (v - u) / 6 * (f(u) + 4 * f((u + v) / 2) + f(v));
      }
    }
  }
  return total;
}

std::vector<Vec2> sphere_profile(double radius, int rings, double centre_z) {
  std::vector<Vec2> profile{{0, centre_z - radius}};
  for (int k = rings - 1; k >= 1; --k) {
    const double polar = kPi * k / rings;
    profile.push_back({radius * std::sin(polar), centre_z + radius * std::cos(polar)});
  }
  profile.push_back({0, centre_z + radius});
  return profile;
}

std::vector<Vec2> torus_profile(double major, double minor, int tube_segments, double centre_z) {
  std::vector<Vec2> profile;
  for (int j = 0; j < tube_segments; ++j) {
    const double a = 2 * kPi * j / tube_segments;
    profile.push_back({major + minor * std::cos(a), centre_z + minor * std::sin(a)});
  }
  return profile;
}

// The one rounding in ΔV: the cap term intersects the region with the lower section on
// Clipper's 1 pm grid, which moves their boundaries by at most 0.71 pm; ΔV moves by at most
// that times t times the boundary's length.
double rounding_bound(double t, const Region& region) {
  return 1e-9 * t * geometry::perimeter(region) + 1e-12;
}

double deviation_of(const LayerStack& stack, std::size_t layer, const Region& region) {
  const geometry::Slab slab = geometry::slab_of(stack, layer);
  const geometry::SlabColumns columns = geometry::slab_columns(slab, stack.lower(layer));
  return geometry::volume_deviation(columns, region);
}

// An independent reference: ∫ area(C(z) XOR R) dz by Gauss-Legendre (5 points) on the pieces
// between vertex heights, each halved until two levels agree within 1e-9 mm^3.
double quadrature_deviation(const LayerStack& stack, const Layer& layer, const Region& region) {
  const auto xor_area = [&](double z) {
    return geometry::clipper::area_mm2(geometry::clipper::symmetric_difference(
        geometry::to_clipper(stack.cross_section(z)), geometry::to_clipper(region)));
  };
  static const double x[5] = {0, -0.5384693101056831, 0.5384693101056831, -0.9061798459386640,
                              0.9061798459386640};
  static const double w[5] = {0.5688888888888889, 0.4786286704993665, 0.4786286704993665,
                              0.2369268850561891, 0.2369268850561891};
  const auto gauss = [&](double a, double b) {
    double s = 0;
    for (int i = 0; i < 5; ++i) s += w[i] * xor_area((a + b) / 2 + (b - a) / 2 * x[i]);
    return s * (b - a) / 2;
  };
  std::function<double(double, double, double, int)> adapt = [&](double a, double b,
                                                                  double whole, int depth) {
    const double m = (a + b) / 2, left = gauss(a, m), right = gauss(m, b);
    if (depth > 10 || std::abs(left + right - whole) < 1e-9) return left + right;
    return adapt(a, m, left, depth + 1) + adapt(m, b, right, depth + 1);
  };
  std::vector<double> cuts = stack.vertex_heights_between(layer.z_lo, layer.z_hi);
  cuts.push_back(layer.z_lo);
  cuts.push_back(layer.z_hi);
  std::sort(cuts.begin(), cuts.end());
  cuts.erase(std::unique(cuts.begin(), cuts.end()), cuts.end());
  double total = 0;
  for (std::size_t i = 0; i + 1 < cuts.size(); ++i)
    total += adapt(cuts[i], cuts[i + 1], gauss(cuts[i], cuts[i + 1]), 0);
  return total;
}

Region square(double cx, double cy, double half) {
  return {{{{cx - half, cy - half}, {cx + half, cy - half}, {cx + half, cy + half},
            {cx - half, cy + half}}}};
}

}  // namespace

TEST_CASE("cylinder_deviation_is_zero_for_its_section_and_the_slab_for_nothing") {
  const solids::Solid cylinder = solids::cylinder(5, 10, 48);
  const LayerStack stack(cylinder.mesh, geometry::uniform_layers(10, 0.3));
  const double section_area = solids::regular_polygon_area(48, 5);
  for (std::size_t i : {0u, 7u, 20u}) {
    const double t = stack.layers()[i].thickness();
    CHECK(deviation_of(stack, i, stack.lower(i)) <= rounding_bound(t, stack.lower(i)));
    CHECK(deviation_of(stack, i, Region{}) == doctest::Approx(t * section_area).epsilon(1e-12));
  }
  // The part of the top layer above z = 10 is empty: only the part below counts.
  const Layer top = stack.layers().back();
  CHECK(deviation_of(stack, stack.size() - 1, Region{}) ==
        doctest::Approx((10 - top.z_lo) * section_area).epsilon(1e-12));
}

TEST_CASE("cone_deviation_of_any_section_height_matches_closed_form") {
  // n-gon cone, radius 10, height 20: rho(z) = 10 (1 - z/20), nested similar sections.
  const int n = 64;
  const solids::Solid cone = solids::cone(10, 20, n);
  const LayerStack stack(cone.mesh, geometry::uniform_layers(20, 0.4));
  const double k = n / 2.0 * std::sin(2 * kPi / n);
  const auto rho2 = [](double z) { return std::pow(10 * (1 - z / 20), 2); };
  // ∫ rho^2 dz = -20/3 * 100 (1 - z/20)^3 ... via antiderivative of (1 - z/20)^2.
  const auto big_r = [&](double z) { return -100.0 * 20 / 3 * std::pow(1 - z / 20, 3); };
  for (std::size_t i : {0u, 12u, 48u}) {
    const Layer layer = stack.layers()[i];
    for (double f : {0.0, 0.25, 0.5, 0.8}) {
      const double h = layer.z_lo + f * layer.thickness();
      const double exact = k * ((big_r(h) - big_r(layer.z_lo)) - rho2(h) * (h - layer.z_lo) +
                                rho2(h) * (layer.z_hi - h) - (big_r(layer.z_hi) - big_r(h)));
      CAPTURE(i);
      CAPTURE(f);
      const Region section = stack.cross_section(h);
      CHECK(std::abs(deviation_of(stack, i, section) - exact) <=
            rounding_bound(layer.thickness(), section));
    }
  }
}

TEST_CASE("sphere_lower_and_mid_deviation_match_integration_by_hand") {
  const int n = 48, rings = 24;
  const double radius = 10;
  const solids::Solid sphere = solids::sphere(radius, n, rings, {0, 0, radius});
  const auto profile = sphere_profile(radius, rings, radius);
  const LayerStack stack(sphere.mesh, geometry::uniform_layers(20, 0.5));
  for (std::size_t i = 0; i < stack.size(); i += 3) {
    const Layer layer = stack.layers()[i];
    CAPTURE(i);
    const double lower = exact_nested_deviation(profile, n, layer.z_lo, layer.z_hi, layer.z_lo);
    const double mid = exact_nested_deviation(profile, n, layer.z_lo, layer.z_hi, layer.z_mid());
    const double t = layer.thickness();
    CHECK(std::abs(deviation_of(stack, i, stack.lower(i)) - lower) <=
          rounding_bound(t, stack.lower(i)));
    CHECK(std::abs(deviation_of(stack, i, stack.mid(i)) - mid) <= rounding_bound(t, stack.mid(i)));
  }
}

TEST_CASE("torus_lower_and_mid_deviation_match_integration_by_hand") {
  const int n = 40, m = 16;
  const solids::Solid torus = solids::torus(12, 4, n, m, {0, 0, 4});
  const auto profile = torus_profile(12, 4, m, 4);
  const LayerStack stack(torus.mesh, geometry::uniform_layers(8, 0.35));
  for (std::size_t i = 0; i < stack.size(); ++i) {
    const Layer layer = stack.layers()[i];
    if (layer.z_hi > 8) continue;
    CAPTURE(i);
    const double lower = exact_nested_deviation(profile, n, layer.z_lo, layer.z_hi, layer.z_lo);
    const double mid = exact_nested_deviation(profile, n, layer.z_lo, layer.z_hi, layer.z_mid());
    const double t = layer.thickness();
    CHECK(std::abs(deviation_of(stack, i, stack.lower(i)) - lower) <=
          rounding_bound(t, stack.lower(i)));
    CHECK(std::abs(deviation_of(stack, i, stack.mid(i)) - mid) <= rounding_bound(t, stack.mid(i)));
  }
}

TEST_CASE("fine_sphere_deviation_approaches_the_smooth_formula") {
  // Smooth sphere, layer above the equator: r(z)^2 = R^2 - (z - c)^2 decreases, so for the
  // lower section ΔV = π ∫ (r(z_lo)^2 - r(z)^2) dz = π [((z_hi-c)^3 - (z_lo-c)^3)/3 - (z_lo-c)^2 t].
  // The 256 x 128 mesh is inscribed: its sections lose about (π/n)^2 / ... of the area; 0.5%.
  const double radius = 10;
  const solids::Solid sphere = solids::sphere(radius, 256, 128, {0, 0, radius});
  const LayerStack stack(sphere.mesh, geometry::uniform_layers(20, 0.5));
  for (std::size_t i : {24u, 30u, 36u}) {
    const Layer layer = stack.layers()[i];
    const double a = layer.z_lo - radius, b = layer.z_hi - radius;
    const double smooth = kPi * ((b * b * b - a * a * a) / 3 - a * a * (b - a));
    CAPTURE(i);
    CHECK(deviation_of(stack, i, stack.lower(i)) == doctest::Approx(smooth).epsilon(5e-3));
  }
}

TEST_CASE("deviation_matches_quadrature_of_xor_areas_for_crossing_regions") {
  // Regions whose boundaries cross the sections (a square over a sphere, a shifted disc over a
  // torus): nothing nested, so this exercises the general clipping. The reference integrates
  // Clipper XOR areas between vertex heights with adaptive Gauss-Legendre.
  const solids::Solid sphere = solids::sphere(10, 40, 20, {0, 0, 10});
  const LayerStack sphere_stack(sphere.mesh, geometry::uniform_layers(20, 0.6));
  for (std::size_t i : {1u, 16u}) {
    const Layer layer = sphere_stack.layers()[i];
    for (const Region& region : {square(0, 0, 7.5), square(3, -2, 4)}) {
      CAPTURE(i);
      CHECK(deviation_of(sphere_stack, i, region) ==
            doctest::Approx(quadrature_deviation(sphere_stack, layer, region)).epsilon(1e-6));
    }
  }
  const solids::Solid torus = solids::torus(12, 4, 36, 12, {0, 0, 4});
  const LayerStack torus_stack(torus.mesh, geometry::uniform_layers(8, 0.5));
  for (std::size_t i : {0u, 9u}) {
    const Layer layer = torus_stack.layers()[i];
    Region shifted = torus_stack.cross_section(layer.z_mid() + 0.7);
    for (auto& loop : shifted.loops)
      for (auto& p : loop) p = p + Vec2{0.9, -0.4};
    CAPTURE(i);
    CHECK(deviation_of(torus_stack, i, shifted) ==
          doctest::Approx(quadrature_deviation(torus_stack, layer, shifted)).epsilon(1e-6));
  }
}

TEST_CASE("deviation_handles_regions_on_facet_edges_and_corners") {
  // A box's own section as the region runs exactly along the projection of its top face when
  // that lies inside the slab: every boundary is collinear, the degenerate case of the clipper.
  const solids::Solid box = solids::box({0, 0, 0}, {10, 6, 1.1});
  const LayerStack stack(box.mesh, geometry::uniform_layers(1.1, 0.4));
  const std::size_t top = stack.size() - 1;  // [0.8, 1.2]: the top face at 1.1 lies inside
  CHECK(deviation_of(stack, top, stack.lower(top)) == doctest::Approx(0.1 * 60).epsilon(1e-9));
  CHECK(deviation_of(stack, top, Region{}) == doctest::Approx(0.3 * 60).epsilon(1e-9));
  CHECK(deviation_of(stack, top, square(5, 3, 2)) ==
        doctest::Approx(0.3 * 60 - 0.3 * 16 + 0.1 * 16).epsilon(1e-9));
}

TEST_CASE("a_layer_on_a_sphere_s_equator_has_mid_at_the_volume_limit") {
  // The sphere's equator ring (at 10 + 10 cos(pi / 2)) and the layer's bottom (25 steps of
  // 0.4 mm) are both 10 mm but for an ulp, so clipping its faces leaves corners an ulp apart. The layer's slab has no fold
  // (its band leans inward all round), so mid's section is the region of least ΔV and its ΔV
  // the volume limit (volume_limit.h), computed by another path. The ulp-long edges put mid's
  // ΔV 7.6% above it (0.17647 against 0.16404 mm³).
  const solids::Solid sphere = solids::sphere(10, 48, 24, {0, 0, 10});
  const LayerStack stack(sphere.mesh, geometry::uniform_layers(20, 0.4));
  const std::size_t layer = 25;
  REQUIRE(stack.layers()[layer].z_lo == doctest::Approx(10).epsilon(1e-15));
  const geometry::SlabColumns columns = geometry::slab_columns(geometry::slab_of(stack, layer), stack.lower(layer));
  CHECK(geometry::volume_deviation(columns, stack.mid(layer)) ==
        doctest::Approx(geometry::volume_limit(columns)).epsilon(1e-8));
}

}  // namespace volume_deviation_test
