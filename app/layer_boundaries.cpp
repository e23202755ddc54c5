// Explicit layer boundaries; see layer_boundaries.h.
#include "app/layer_boundaries.h"

#include <algorithm>
#include <cmath>

#include <fmt/core.h>

#include "printer/error.h"
#include "printer/layer_tops.h"

namespace app {

namespace {
constexpr double kTolerance = 1e-6;  // mm
}  // namespace

BoundaryLayers boundary_layers(const std::string& argument, double part_height,
                               double max_uncovered) {
  std::vector<double> tops = printer::read_layer_tops(argument);
  BoundaryLayers result;
  // Keep the first top at or above the part's top; the ones after it start above it.
  const auto covering =
      std::find_if(tops.begin(), tops.end(), [&](double z) { return z >= part_height - kTolerance; });
  if (covering != tops.end()) {
    result.above_part = static_cast<std::size_t>(tops.end() - covering) - 1;
    tops.erase(covering + 1, tops.end());
  } else {
    result.uncovered = part_height - tops.back();
    if (!(result.uncovered < max_uncovered)) {
      throw printer::ConfigError(fmt::format(
          "--boundaries {}: the layers end at {:g} mm but the part is {:.3f} mm tall; add layer "
          "tops up to at least {:.3f} mm",
          argument, tops.back(), part_height, part_height));
    }
    result.notes.push_back(fmt::format("--boundaries {}: the layers end at {:g} mm, {:.3f} mm "
                                       "below the part's top: that much of it is left out",
                                       argument, tops.back(), result.uncovered));
  }
  if (result.above_part > 0) {
    result.notes.push_back(fmt::format("--boundaries {}: {} layer top{} above the part's top "
                                       "({:.3f} mm) left out",
                                       argument, result.above_part,
                                       result.above_part == 1 ? "" : "s", part_height));
  }
  result.layers = geometry::layers_from_tops(tops);
  return result;
}

std::string describe_layers(const std::vector<geometry::Layer>& layers) {
  if (layers.empty()) return "0 layers";
  double thinnest = layers[0].thickness(), thickest = thinnest;
  for (const geometry::Layer& layer : layers) {
    thinnest = std::min(thinnest, layer.thickness());
    thickest = std::max(thickest, layer.thickness());
  }
  const auto mm = [](double v) { return std::round(v * 1e6) / 1e6; };
  if (thickest - thinnest <= kTolerance) {
    return fmt::format("{} layer{} of {:g} mm", layers.size(), layers.size() == 1 ? "" : "s",
                       mm(thinnest));
  }
  return fmt::format("{} layers, {:g} to {:g} mm thick", layers.size(), mm(thinnest), mm(thickest));
}

}  // namespace app
