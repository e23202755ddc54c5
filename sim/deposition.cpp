#include "sim/deposition.h"

#include <algorithm>
#include <cmath>

#include <polyclipping/clipper.hpp>

#include "geometry/core/clipper.h"
#include "printer/bead_model.h"

namespace sim {

namespace {
// Z levels closer than this are one layer (printers step Z in whole microsteps anyway).
constexpr double kLayerTolerance = 1e-3;
}  // namespace

void DepositionRecord::add(double z, geometry::Vec2 start, geometry::Vec2 end, double e,
                           double feedrate) {
  auto at = std::lower_bound(layer_z.begin(), layer_z.end(), z - kLayerTolerance / 2);
  int layer = static_cast<int>(at - layer_z.begin());
  if (at == layer_z.end() || std::abs(*at - z) > kLayerTolerance / 2) {
    layer_z.insert(at, z);
    if (layer + 1 < static_cast<int>(layer_z.size())) {
      // A level below existing ones (rare: a print that goes down): renumber those above.
      for (DepositedMove& move : moves) {
        if (move.layer >= layer) ++move.layer;
      }
    }
  }
  moves.push_back(DepositedMove{layer, layer_z[static_cast<std::size_t>(layer)], start, end, e,
                                feedrate});
}

double DepositionRecord::layer_height(int layer) const {
  if (layer < 0 || layer >= static_cast<int>(layer_z.size())) return 0;
  const auto i = static_cast<std::size_t>(layer);
  return i == 0 ? layer_z[0] : layer_z[i] - layer_z[i - 1];
}

double DepositionRecord::filament_used() const {
  double total = 0;
  for (const DepositedMove& move : moves) total += move.e;
  return total;
}

std::vector<LayerBeads> bead_polygons(const DepositionRecord& record, double filament_diameter) {
  std::vector<LayerBeads> layers(record.layer_z.size());
  for (std::size_t i = 0; i < layers.size(); ++i) {
    layers[i].z = record.layer_z[i];
    layers[i].height = record.layer_height(static_cast<int>(i));
  }
  for (const DepositedMove& move : record.moves) {
    LayerBeads& layer = layers[static_cast<std::size_t>(move.layer)];
    const geometry::Vec2 along = move.end - move.start;
    const double length = std::hypot(along.x, along.y);
    const double h = layer.height;
    if (!(length > 0) || !(h > 0)) continue;
    const double width = printer::bead_width(move.e, length, h, filament_diameter);
    if (!(width > 0)) continue;
    const geometry::Vec2 side = (width / 2 / length) * geometry::Vec2{-along.y, along.x};
    Bead bead;
    bead.width = width;
    bead.outline = {move.start - side, move.end - side, move.end + side, move.start + side};
    layer.beads.push_back(std::move(bead));
  }
  return layers;
}

geometry::Region printed_region(const LayerBeads& layer) {
  ClipperLib::Paths paths;
  paths.reserve(layer.beads.size());
  for (const Bead& bead : layer.beads) paths.push_back(geometry::to_clipper(bead.outline));
  ClipperLib::Clipper clipper;
  clipper.AddPaths(paths, ClipperLib::ptSubject, true);
  ClipperLib::PolyTree tree;
  clipper.Execute(ClipperLib::ctUnion, tree, ClipperLib::pftNonZero, ClipperLib::pftNonZero);
  return geometry::from_clipper(tree);
}

}  // namespace sim
