#include "geometry/contour/contour_strategy.h"

#include <stdexcept>

#include "geometry/contour/best_contour.h"
#include "geometry/contour/ma_contour.h"
#include "geometry/contour/optimal_height.h"
#include "geometry/contour/section_contours.h"

namespace geometry {

namespace {

// The strategies: one entry each, in the order --help lists them. The colours are
// matplotlib's first five (the paper's figures use the same family).
constexpr ContourStrategy kStrategies[] = {
    {"lower", "the section at the layer's bottom, the paper's baseline", "#1f77b4",
     lower_strategy, [](const Layer& layer) { return layer.z_lo; }},
    {"mid", "the section at the layer's middle, as other slicers print", "#2ca02c",
     mid_strategy, [](const Layer& layer) { return layer.z_mid(); }},
    {"optimal-height", "the section with the least volume deviation", "#ff7f0e",
     optimal_height_strategy},
    {"ma", "the paper's medial-axis contour of the slab", "#d62728", ma_strategy},
    {"best", "per layer the least distance error of mid, optimal-height and ma", "#9467bd",
     best_strategy},
};

bool same_name(std::string_view name, std::string_view asked) {
  if (name.size() != asked.size()) return false;
  for (std::size_t i = 0; i < name.size(); ++i) {
    if (name[i] != (asked[i] == '_' ? '-' : asked[i])) return false;
  }
  return true;
}

}  // namespace

std::span<const ContourStrategy> contour_strategies() { return kStrategies; }

const ContourStrategy* find_contour_strategy(std::string_view name) {
  for (const ContourStrategy& strategy : kStrategies) {
    if (same_name(strategy.name, name)) return &strategy;
  }
  return nullptr;
}

const ContourStrategy& contour_strategy(std::string_view name) {
  const ContourStrategy* strategy = find_contour_strategy(name);
  if (!strategy) throw std::logic_error("no contour strategy named " + std::string(name));
  return *strategy;
}

std::string contour_names(std::string_view separator) {
  std::string names;
  for (const ContourStrategy& strategy : kStrategies) {
    if (!names.empty()) names += separator;
    names += strategy.name;
  }
  return names;
}

Region layer_contour(const LayerStack& stack, std::size_t layer, const ContourStrategy& strategy,
                     const ContourOptions& options, double mid_distance) {
  if (layer >= stack.size()) return {};
  return strategy.contour({stack, layer, options, nullptr, mid_distance}).region;
}

}  // namespace geometry
