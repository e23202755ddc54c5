// The optimal-height contour (paper §3.1, eq. 7): the cross-section at the height h in
// [z_lo, z_hi] whose prism has the least volume deviation ΔV(h) = vol(S_i △ C(h) x [z_lo, z_hi]).
//
// ΔV(h) need not be convex (the paper's CATIA experiment used simulated annealing for that
// reason, 90 s per slice), so the search first scans `coarse_samples` equally spaced heights
// (both ends included), then narrows the bracket around the best of them by Brent's search
// (Boost's brent_find_minima: parabolic steps where ΔV is smooth, golden-section ones where
// not) until it is shorter than `tolerance`. A minimum between two coarse samples that is not in the best
// sample's bracket can be missed; the coarse scan makes that a minimum narrower than t/8.
//
// Each evaluation is SectionDeviation below: no section is built but the best one.
//
// Input: the layer stack, a layer index, and the slab's columns (slab_columns.h) for it.
// Output: the best height found, its ΔV (mm^3, SectionDeviation's: the metric's
// volume_deviation of the section, which rounds it to 1 nm, agrees to ~1e-8 relative), its
// section, and how many heights were tried.
// Zero-thickness or out-of-range layer: h = z_lo, the section there, no search.
#pragma once

#include <array>
#include <cstddef>
#include <vector>

#include "geometry/contour/contour_input.h"
#include "geometry/core/boundary_grid.h"
#include "geometry/slicing/layer_stack.h"
#include "geometry/core/polygon.h"
#include "geometry/slab/slab_columns.h"

namespace geometry {

// ΔV(h) = vol(S_i △ C(h) x [z_lo, z_hi]) for every height h of one slab, without building C(h).
// Walking up a column from z_lo, every facet of the slab's surface above it toggles inside and
// outside (slab_columns.h): the section's indicator at h (from above) is
//   [C(z_lo)] + sum over facets f with z_f <= h of s_f,
// so with f_h the part of facet f's projection where z_f <= h (a convex polygon: a facet cut
// by a line),
//   area C(h)        = area C(z_lo) + sum_f s_f area(f_h)
//   ∫ over C(h) of occ = ∫ over C(z_lo) of occ + t sum_f s_f area(f_h ∩ C(z_lo))
//                      + sum_f ∫ over f_h of w_f + sum over overlapping f != g of s_f s_g ∫ over f_h ∩ g of w_g,
// and ΔV(h) = vol(S_i) + t area C(h) - 2 ∫ over C(h) of occ. Facets wholly below h add
// constants (sums over prefixes of the facets by z_max), those wholly above nothing. A facet
// that h cuts, wholly inside or outside C(z_lo) and of no fold, adds t s_f (1 - 2 [f in C(z_lo)])
// area(f_h) - 2 ∫ over f_h of w_f: between two of its corners' heights area(f_h) is quadratic
// in h and the integral cubic (its derivative is (z_hi - h) times area's), so the constructor
// turns each such facet into a polynomial per piece (one to three clips of it a piece) and
// operator() only sums the pieces h lies in. The facets of a fold or that C(z_lo) crosses (a
// few per layer) are clipped at every h; a fold facet's projection is intersected with each
// of its partners' (SlabColumns::overlapping) once, here, and f_h ∩ g is that cut at h.
// The same value as volume_deviation(columns, cross_section(h)) to floating point (that one
// rounds the section to 1 nm and its intersection with C(z_lo) to 1 pm), for h in
// [z_lo, z_hi); at h = z_hi the section from above belongs to the next slab and has to be
// built. The pieces agree with clipping every cut facet at h to ~1e-11 relative on the
// bunny's layers.
// Cost: the constructor clips each facet once per corner and once per piece besides its
// moments in C(z_lo), and intersects each fold pair once; operator() sums the pieces that
// hold h, clips the few facets left and cuts their fold pairs' intersections. The
// figures measured and the way not taken are in optimal_height.cpp.
// Input: the slab's columns, mm. Output of operator(): mm^3, >= 0.
class SectionDeviation {
 public:
  explicit SectionDeviation(const SlabColumns& columns);
  ~SectionDeviation();
  SectionDeviation(SectionDeviation&&) noexcept;
  double operator()(double h) const;

 private:
  struct Facet;
  // A facet's share of ΔV for h in [z0, z1): q0 + q1 d + q2 d^2 + q3 d^3, d = h - z0.
  struct Piece {
    double z0 = 0, z1 = 0;
    std::array<double, 4> q{};
  };
  void add_pieces(const Facet& facet);
  std::vector<Facet> facets_;
  std::vector<int> by_top_;     // facets by z_max
  std::vector<int> by_bottom_;  // the clipped ones (folds, crossing C(z_lo)) by z_min
  std::vector<Piece> pieces_;   // the others' pieces, by z0
  std::vector<double> prefix_area_, prefix_occupied_;  // sums over by_top_'s prefixes
  BoundaryGrid lower_grid_;
  const Region* lower_;
  double z_hi_, thickness_, volume_;
  double lower_area_ = 0, occupied_lower_ = 0;  // area C(z_lo), ∫ over C(z_lo) of occ
};

struct OptimalHeightOptions {
  int coarse_samples = 9;    // heights scanned first, ends included (>= 3)
  double tolerance = 1e-4;   // mm: the final bracket's length
};

struct OptimalHeight {
  double height = 0;
  double volume_deviation = 0;
  Region section;
  int evaluations = 0;
};

OptimalHeight optimal_height(const LayerStack& stack, std::size_t layer,
                             const SlabColumns& columns, const OptimalHeightOptions& options = {});

// The search alone, with the slab's SectionDeviation built already (from the same columns):
// the height and its ΔV, the section left empty, for a caller that may have the section at
// that height (best_contour.h has mid's). A layer of no thickness: h = z_lo and its ΔV.
OptimalHeight optimal_height_search(const LayerStack& stack, std::size_t layer,
                                    const SlabColumns& columns,
                                    const SectionDeviation& deviation_at,
                                    const OptimalHeightOptions& options = {});

// The same, building the slab's columns itself.
OptimalHeight optimal_height(const LayerStack& stack, std::size_t layer,
                             const OptimalHeightOptions& options = {});

// The strategy "optimal-height" (contour_strategy.h): the best section and its height, with
// the reference's columns where it has them, else columns of the reference's slab, else its
// own; options.optimal.
ContourResult optimal_height_strategy(const ContourInput& input);

}  // namespace geometry
