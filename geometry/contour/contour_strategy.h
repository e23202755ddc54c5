// Contour strategies: which planar region R_i a layer extrudes (DESIGN.md §2).
//
// The printer deposits the prism R_i x [z_lo, z_hi]; a strategy picks R_i from the slab.
//   lower           cross-section at z_lo (the paper's "traditional" baseline)
//   mid             cross-section at the layer's middle (PrusaSlicer, Slic3r, CuraEngine)
//   optimal-height  the cross-section at the height minimising the volume deviation (§3.1)
//   ma              the paper's medial-axis contour of the slab's boundary pair (§3.2-3.3)
// Every strategy returns a valid Region (no self-intersections); an empty slab gives an
// empty Region.
#pragma once

#include <cstddef>
#include <optional>
#include <string_view>

#include "geometry/slicing/layer_stack.h"
#include "geometry/contour/ma_contour.h"
#include "geometry/core/polygon.h"

namespace geometry {

enum class ContourKind { lower, mid, optimal_height, ma };

std::string_view contour_name(ContourKind kind);
std::optional<ContourKind> parse_contour_kind(std::string_view name);

struct ContourOptions {
  MaOptions ma;
};

Region layer_contour(const LayerStack& stack, std::size_t layer, ContourKind kind,
                     const ContourOptions& options = {});

}  // namespace geometry
