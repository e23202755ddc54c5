#include "geometry/metrics/volume_deviation.h"

#include <algorithm>

namespace geometry {

double volume_deviation(const SlabColumns& columns, const Region& region,
                        const BoundaryGrid& region_grid) {
  const double inside = occupied_volume_inside(columns, region, region_grid);
  const double deviation = columns.volume + columns.thickness() * area(region) - 2 * inside;
  // Exact arithmetic would never go below 0; rounding can, by ~1e-12 of the slab's volume.
  return std::max(deviation, 0.0);
}

double volume_deviation(const SlabColumns& columns, const Region& region) {
  return volume_deviation(columns, region, BoundaryGrid(region));
}

}  // namespace geometry
