#include "geometry/support/overhang.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "geometry/core/clipper.h"

namespace geometry {

namespace {

// Steep pieces narrower than twice this are the offsets' rounding and edges a few microns
// apart, not overhangs (mm).
constexpr double kSliver = 0.01;

}  // namespace

double overhang_reach(double thickness, double angle_degrees, double bead_width) {
  if (!(thickness > 0)) return 0;
  const double angle = std::clamp(angle_degrees, 0.0, 89.0) * std::numbers::pi / 180;
  return std::max(0.0, std::min(thickness * std::tan(angle), bead_width / 2));
}

ClipperLib::Paths without_specks(const ClipperLib::Paths& region, double min_area) {
  if (!(min_area > 0)) return region;
  clipper::Paths kept;
  for (clipper::Paths& island : clipper::islands(region)) {
    if (clipper::area_mm2(island) < min_area) continue;
    kept.insert(kept.end(), std::make_move_iterator(island.begin()),
                std::make_move_iterator(island.end()));
  }
  return kept;
}

ClipperLib::Paths overhang(const ClipperLib::Paths& region, const ClipperLib::Paths& below,
                           double reach, double min_area) {
  if (region.empty()) return {};
  if (below.empty()) return without_specks(clipper::union_nonzero(region), min_area);
  reach = std::max(reach, 0.0);
  const clipper::Paths carried = reach > 0 ? clipper::offset(below, reach) : below;
  clipper::Paths steep = clipper::difference(region, carried);
  if (steep.empty()) return {};
  steep = without_specks(clipper::opening(steep, kSliver), min_area);
  if (steep.empty()) return {};
  if (reach == 0) return steep;
  // Back to the whole overhang beyond the layer below, around the steep pieces only.
  const clipper::Paths around = clipper::intersection(clipper::offset(steep, reach + kSliver), region);
  return without_specks(clipper::difference(around, below), min_area);
}

Region overhang(const Region& region, const Region& below, double reach, double min_area) {
  return from_clipper(overhang(to_clipper(region), to_clipper(below), reach, min_area));
}

}  // namespace geometry
