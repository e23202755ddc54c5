#include "geometry/toolpaths/skins.h"

#include <tbb/parallel_for.h>

#include <algorithm>

#include "geometry/core/clipper.h"

namespace geometry {

namespace {

}  // namespace

std::vector<std::optional<Region>> sparse_cores(const std::vector<Region>& regions,
                                                int top_layers, int bottom_layers) {
  const long n = static_cast<long>(regions.size());
  std::vector<std::optional<Region>> cores(n);
  top_layers = std::max(top_layers, 0);
  bottom_layers = std::max(bottom_layers, 0);
  if (top_layers == 0 && bottom_layers == 0) return cores;
  // core_i is the intersection of the window regions[i - bottom .. i + top]: layer i itself
  // is in it too, which changes nothing inside layer i. Windows of 2^k layers come from
  // halves of 2^(k-1) (a sparse table), so a window of any length L costs log2(L) + 1
  // intersections per layer rather than L - 1.
  const long length = bottom_layers + top_layers + 1;
  // (Every window is at least two layers, so each span below comes out of an intersection,
  // which takes its inputs with the non-zero rule: no cleaning needed first.)
  std::vector<clipper::Paths> span(n);  // span[i]: regions[i .. i + 2^k - 1]
  tbb::parallel_for(long{0}, n, [&](long i) { span[i] = to_clipper(regions[i]); });
  long width = 1;
  for (; 2 * width <= length; width *= 2) {
    std::vector<clipper::Paths> wider(n);
    tbb::parallel_for(long{0}, n, [&](long i) {
      if (i + width < n) wider[i] = clipper::intersection(span[i], span[i + width]);
    });
    span = std::move(wider);
  }
  tbb::parallel_for(long{0}, n, [&](long i) {
    const long first = i - bottom_layers, last = i + top_layers;
    // A window reaching past either end of the stack covers nothing.
    if (first < 0 || last >= n) {
      cores[i] = Region{};
      return;
    }
    const long second = last - width + 1;  // the two spans overlap: together they are exact
    cores[i] = from_clipper(second == first ? span[first]
                                            : clipper::intersection(span[first], span[second]));
  });
  return cores;
}

Skins split_skins(const Region& area, const Region* core, const Region* below,
                  const Region* above, double width) {
  Skins skins;
  const clipper::Paths all = to_clipper(area);  // the booleans below take it non-zero as it is
  if (all.empty()) return skins;
  if (!core) {
    skins.sparse = from_clipper(all);
    return skins;
  }
  const double sliver = std::max(width, 0.0) / 4;
  const clipper::Paths core_paths = to_clipper(*core);
  clipper::Paths solid = clipper::opening(clipper::difference(all, core_paths), sliver);
  skins.sparse = from_clipper(clipper::difference(all, solid));
  if (solid.empty()) return skins;
  clipper::Paths bottom, top;
  if (below) bottom = clipper::opening(clipper::difference(solid, to_clipper(*below)), sliver);
  if (above) {
    top = clipper::opening(clipper::difference(clipper::difference(solid, bottom), to_clipper(*above)), sliver);
  }
  skins.bottom = from_clipper(bottom);
  skins.top = from_clipper(top);
  skins.solid = from_clipper(clipper::difference(solid, clipper::union_nonzero(bottom, top)));
  return skins;
}

}  // namespace geometry
