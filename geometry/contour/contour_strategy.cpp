#include "geometry/contour/contour_strategy.h"

#include "geometry/contour/optimal_height.h"

namespace geometry {

std::string_view contour_name(ContourKind kind) {
  switch (kind) {
    case ContourKind::lower: return "lower";
    case ContourKind::mid: return "mid";
    case ContourKind::optimal_height: return "optimal-height";
    case ContourKind::ma: return "ma";
  }
  return "?";
}

std::optional<ContourKind> parse_contour_kind(std::string_view name) {
  if (name == "lower") return ContourKind::lower;
  if (name == "mid") return ContourKind::mid;
  if (name == "optimal-height" || name == "optimal_height") return ContourKind::optimal_height;
  if (name == "ma") return ContourKind::ma;
  return std::nullopt;
}

Region layer_contour(const LayerStack& stack, std::size_t layer, ContourKind kind,
                     const ContourOptions& options) {
  if (layer >= stack.size()) return {};
  switch (kind) {
    case ContourKind::lower: return stack.lower(layer);
    case ContourKind::mid: return stack.mid(layer);
    case ContourKind::optimal_height: return optimal_height(stack, layer).section;
    case ContourKind::ma: return ma_contour(stack, layer, options.ma);
  }
  return {};
}

}  // namespace geometry
