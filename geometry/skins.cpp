#include "geometry/skins.h"

#include <tbb/parallel_for.h>

#include <algorithm>

#include "geometry/clipper_bridge.h"
#include "geometry/toolpath_clipper.h"

namespace geometry {

namespace {

namespace tc = toolpath_clipper;

// Intersection of regions[first .. first + count - 1]; an index outside the stack is empty.
tc::Paths covered_by_all(const std::vector<tc::Paths>& regions, long first, int count) {
  const long size = static_cast<long>(regions.size());
  if (first < 0 || first + count > size) return {};
  tc::Paths result = regions[first];
  for (long j = first + 1; j < first + count && !result.empty(); ++j) {
    result = tc::intersection(result, regions[j]);
  }
  return result;
}

}  // namespace

std::vector<std::optional<Region>> sparse_cores(const std::vector<Region>& regions,
                                                int top_layers, int bottom_layers) {
  const long n = static_cast<long>(regions.size());
  std::vector<std::optional<Region>> cores(n);
  top_layers = std::max(top_layers, 0);
  bottom_layers = std::max(bottom_layers, 0);
  if (top_layers == 0 && bottom_layers == 0) return cores;
  std::vector<tc::Paths> paths(n);
  tbb::parallel_for(long{0}, n, [&](long i) { paths[i] = tc::union_of(to_clipper(regions[i])); });
  tbb::parallel_for(long{0}, n, [&](long i) {
    tc::Paths core;
    if (top_layers > 0 && bottom_layers > 0) {
      core = tc::intersection(covered_by_all(paths, i + 1, top_layers),
                              covered_by_all(paths, i - bottom_layers, bottom_layers));
    } else if (top_layers > 0) {
      core = covered_by_all(paths, i + 1, top_layers);
    } else {
      core = covered_by_all(paths, i - bottom_layers, bottom_layers);
    }
    cores[i] = from_clipper(core);
  });
  return cores;
}

Skins split_skins(const Region& area, const Region* core, const Region* below,
                  const Region* above, double width) {
  Skins skins;
  const tc::Paths all = tc::union_of(to_clipper(area));
  if (all.empty()) return skins;
  if (!core) {
    skins.sparse = from_clipper(all);
    return skins;
  }
  const double sliver = std::max(width, 0.0) / 4;
  const tc::Paths core_paths = to_clipper(*core);
  tc::Paths solid = tc::opening(tc::difference(all, core_paths), sliver);
  skins.sparse = from_clipper(tc::difference(all, solid));
  if (solid.empty()) return skins;
  tc::Paths bottom, top;
  if (below) bottom = tc::opening(tc::difference(solid, to_clipper(*below)), sliver);
  if (above) {
    top = tc::opening(tc::difference(tc::difference(solid, bottom), to_clipper(*above)), sliver);
  }
  skins.bottom = from_clipper(bottom);
  skins.top = from_clipper(top);
  skins.solid = from_clipper(tc::difference(solid, tc::union_of(bottom, top)));
  return skins;
}

}  // namespace geometry
