// The volume a section contour leaves between its walls and the model's surface, from the
// mesh alone: the layer plan's measure of total error (layer_plan.h), exact for every
// candidate slab at the cost of a few sums.
//
// For a slab [a, b] printed with the model's section at its middle m (the mid contour), a
// point of the plane lies in C(z) △ C(m) exactly when its vertical line crosses the surface an
// odd number of times between heights z and m (the solid's inside flips at each crossing). So
// the area of C(z) △ C(m) is at most the area of the surface between z and m seen from above,
// P(z) - P(m) in absolute value, where P(z) is the area seen from above of all the surface
// below z (each facet counted whether it faces up or down; a horizontal facet all at its
// height). Integrating over the slab:
//   U(a, b) = ∫_a^b |P(z) - P(m)| dz = Q(a) + Q(b) - 2 Q(m),   Q(z) = ∫ P up to z,
// since P only grows. U ≥ ΔV of mid (volume_deviation.h), with equality wherever the surface
// between each height of the slab and its middle lies in one sheet over every point (any
// slope, a sphere's cap, a twisted wall; not where the surface turns back between the two, at
// a sphere's equator or a fin's edge a little off the middle, where U counts both sheets).
//
// A facet of corner heights z0 <= z1 <= z2 and area A seen from above has the share of it below
// z that a triangle has below a line parallel to one side: (z - z0)^2 / ((z2 - z0)(z1 - z0)) up
// to z1, 1 - (z2 - z)^2 / ((z2 - z0)(z2 - z1)) from there; its integral is a cubic, and z - the
// facet's mean corner height above z2. So Q(z) sums the facets below z by prefix sums and those
// spanning z one by one.
//
// Input: a mesh (mm). Output: mm^3 (U), mm^2·mm (Q). An empty mesh: 0.
#pragma once

#include <cstddef>
#include <vector>

#include "geometry/mesh/mesh.h"
#include "geometry/plan/slab_bound.h"

namespace geometry {

class SweptVolume {
 public:
  explicit SweptVolume(const Mesh& mesh);

  // Q(z), mm^3.
  double integral_below(double z) const;

  // U(z_lo, z_hi), mm^3 (>= 0).
  double operator()(double z_lo, double z_hi) const;

 private:
  struct Facet {
    double z0 = 0, z1 = 0, z2 = 0;  // corner heights, ascending
    double area = 0;                // seen from above, mm^2
  };
  std::vector<Facet> facets_;
  // Facets ordered by their top z2, with running sums of area and of area x mean height.
  std::vector<double> tops_, area_sum_, moment_sum_;
  FacetsByHeight by_height_;
};

}  // namespace geometry
