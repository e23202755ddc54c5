// The column integrals behind ΔV and the limit: the exact intersection moments of a convex
// polygon with a region (Green's theorem with a Clipper fallback for degenerate cases), and
// the slab volume against closed forms.
#include <doctest/doctest.h>

#include <cmath>
#include <random>

#include "geometry/core/boundary_grid.h"
#include "geometry/core/clipper.h"
#include "geometry/slicing/layer_stack.h"
#include "geometry/slab/slab.h"
#include "geometry/slab/slab_columns.h"
#include "support/solids.h"

namespace slab_columns_test {

using geometry::AreaMoments;
using geometry::Region;
using geometry::Vec2;

namespace {

// The reference: Clipper's intersection on the 1 pm grid, moments from its loops.
AreaMoments clipper_moments(const std::vector<Vec2>& convex, Vec2 origin, const Region& region) {
  const ClipperLib::Paths result = geometry::clipper::intersection(
      {geometry::to_fine_clipper(convex)}, geometry::to_fine_clipper(region));
  AreaMoments m;
  for (const auto& path : result) {
    std::vector<Vec2> loop;
    for (const auto& p : path) loop.push_back(geometry::from_fine_clipper(p));
    const AreaMoments part = geometry::moments_of_loop(loop, origin);
    m.area += part.area;
    m.mx += part.mx;
    m.my += part.my;
  }
  return m;
}

void check_same(const AreaMoments& a, const AreaMoments& b, double scale) {
  CHECK(std::abs(a.area - b.area) <= 1e-8 * scale);
  CHECK(std::abs(a.mx - b.mx) <= 1e-8 * scale * scale);
  CHECK(std::abs(a.my - b.my) <= 1e-8 * scale * scale);
}

// A region on a coarse integer lattice: an outer square with a square hole and an L-shaped
// island, so that lattice triangles hit its corners and run along its edges exactly.
Region lattice_region() {
  return {{{{0, 0}, {8, 0}, {8, 8}, {0, 8}},
           {{2, 2}, {2, 6}, {6, 6}, {6, 2}},
           {{3, 3}, {5, 3}, {5, 4}, {4, 4}, {4, 5}, {3, 5}}}};
}

}  // namespace

TEST_CASE("intersection_moments_match_clipper_on_random_polygons") {
  std::mt19937 random(7);
  std::uniform_real_distribution<double> coordinate(-1, 9), size(0.05, 3);
  const Region region = lattice_region();
  const geometry::BoundaryGrid grid(region);
  for (int trial = 0; trial < 3000; ++trial) {
    // A random triangle or convex quadrilateral (counter-clockwise).
    const Vec2 c{coordinate(random), coordinate(random)};
    const double r = size(random);
    std::vector<Vec2> convex;
    const int corners = 3 + trial % 2;
    double angle = coordinate(random);
    for (int k = 0; k < corners; ++k, angle += 2 * 3.141592653589793 / corners + 0.3 * (k % 2))
      convex.push_back(c + r * Vec2{std::cos(angle), std::sin(angle)});
    if (geometry::signed_area(convex) < 0) std::reverse(convex.begin(), convex.end());
    CAPTURE(trial);
    check_same(geometry::moments_of_intersection(convex, convex[0], grid, region),
               clipper_moments(convex, convex[0], region), 10);
  }
}

TEST_CASE("intersection_moments_match_clipper_in_degenerate_positions") {
  // Triangles with corners on the lattice: corners on the region's corners and edges, edges
  // along its edges, in both directions. Every shape is moved over every lattice translation
  // that makes it meet the region; the region is a union of unit lattice cells, and the
  // translates of a cell tile the plane, so the areas of (shape + t) ∩ region summed over the
  // translations t are area(shape) x area(region) = area(shape) x 51, whatever the shape.
  const Region region = lattice_region();
  const geometry::BoundaryGrid grid(region);
  const double region_area = 64 - 16 + 3;  // the square, less its hole, plus the L
  REQUIRE(geometry::area(region) == doctest::Approx(region_area));
  for (const auto& shape : {std::vector<Vec2>{{0, 0}, {2, 0}, {0, 2}},
                            std::vector<Vec2>{{0, 0}, {1, 0}, {1, 1}, {0, 1}},
                            std::vector<Vec2>{{0, 0}, {3, 1}, {1, 3}},
                            std::vector<Vec2>{{1, 0}, {1, 2}, {-1, 1}}}) {
    double summed = 0;
    for (int x = -3; x <= 9; ++x) {
      for (int y = -3; y <= 9; ++y) {
        std::vector<Vec2> convex;
        for (Vec2 p : shape) convex.push_back(p + Vec2{static_cast<double>(x), static_cast<double>(y)});
        if (geometry::signed_area(convex) < 0) std::reverse(convex.begin(), convex.end());
        CAPTURE(x);
        CAPTURE(y);
        const AreaMoments m = geometry::moments_of_intersection(convex, convex[0], grid, region);
        check_same(m, clipper_moments(convex, convex[0], region), 10);
        summed += m.area;
      }
    }
    // Exact but for the degenerate cases' generic move (1e-10 mm, slab_columns.cpp): measured
    // 1.3e-9 mm^2 at most over the 169 translations.
    CHECK(std::abs(summed - std::abs(geometry::signed_area(shape)) * region_area) <= 1e-7);
  }
}

TEST_CASE("slab_volume_is_the_solids_volume_between_the_planes") {
  // A UV sphere: the volume between two heights is the frustum sum of its bands, which the
  // sections' closed-form areas integrate exactly (quadratic in z between ring heights).
  const solids::Solid sphere = solids::sphere(5, 32, 16, {0, 0, 5});
  const geometry::LayerStack stack(sphere.mesh, geometry::uniform_layers(10, 0.7));
  double total = 0;
  for (std::size_t i = 0; i < stack.size(); ++i) {
    const geometry::SlabColumns columns =
        geometry::slab_columns(geometry::slab_of(stack, i), stack.lower(i));
    total += columns.volume;
    // Simpson on each piece between ring heights is exact for the quadratic area.
    std::vector<double> cuts = stack.vertex_heights_between(stack.layers()[i].z_lo, stack.layers()[i].z_hi);
    cuts.insert(cuts.begin(), stack.layers()[i].z_lo);
    cuts.push_back(std::min(stack.layers()[i].z_hi, 10.0));
    std::sort(cuts.begin(), cuts.end());
    double exact = 0;
    for (std::size_t k = 0; k + 1 < cuts.size(); ++k) {
      const double a = cuts[k], b = cuts[k + 1];
      if (!(b > a)) continue;
      const double e = 1e-9 * (b - a);  // sections just inside the piece (limit conventions)
      exact += (b - a) / 6 *
               (sphere.area(a + e) + 4 * sphere.area((a + b) / 2) + sphere.area(b - e));
    }
    CAPTURE(i);
    CHECK(columns.volume == doctest::Approx(exact).epsilon(1e-7));
  }
  CHECK(total == doctest::Approx(sphere.volume).epsilon(1e-9));
}

TEST_CASE("empty_slab_has_no_columns") {
  const geometry::Slab empty{1, 2, {}};
  const geometry::SlabColumns columns = geometry::slab_columns(empty, Region{});
  CHECK(columns.volume == 0);
  CHECK(columns.facets.empty());
  CHECK(geometry::occupied_volume_inside(columns, lattice_region()) == 0);
}

}  // namespace slab_columns_test
