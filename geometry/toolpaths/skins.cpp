#include "geometry/toolpaths/skins.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "geometry/core/clipper.h"

namespace geometry {

namespace {

}  // namespace

std::vector<std::optional<Region>> sparse_cores(const std::vector<Region>& regions,
                                                int top_layers, int bottom_layers) {
  std::vector<Layer> layers(regions.size());
  for (std::size_t i = 0; i < layers.size(); ++i) layers[i] = {double(i), double(i + 1)};
  return sparse_cores(regions, layers, {top_layers, bottom_layers, 0, 0});
}

std::vector<std::optional<Region>> sparse_cores(const std::vector<Region>& regions,
                                                const std::vector<Layer>& layers,
                                                const SkinDepth& depth,
                                                const std::vector<char>& wanted) {
  const long n = static_cast<long>(std::min(regions.size(), layers.size()));
  std::vector<std::optional<Region>> cores(regions.size());
  const int top_layers = std::max(depth.top_layers, 0);
  const int bottom_layers = std::max(depth.bottom_layers, 0);
  const double top_thickness = std::isfinite(depth.top_thickness) ? std::max(depth.top_thickness, 0.0) : 0;
  const double bottom_thickness =
      std::isfinite(depth.bottom_thickness) ? std::max(depth.bottom_thickness, 0.0) : 0;
  if (top_layers == 0 && bottom_layers == 0 && top_thickness == 0 && bottom_thickness == 0) {
    return cores;
  }
  // Each layer's window: the layers [first, last] whose regions must all cover a point for it
  // to be sparse. By thickness, the layers above reaching less than top_thickness over the
  // layer's top and the layers below less than bottom_thickness under its bottom; beyond the
  // stack's top (or the bed) is a layer that covers nothing.
  constexpr double kTolerance = 1e-6;  // mm: sums of layer thicknesses are not exact
  std::vector<long> first(n), last(n);
  long top_reach = 0, bottom_reach = 0;  // indices that only move up as i does
  for (long i = 0; i < n; ++i) {
    long above = top_layers;
    if (top_thickness > 0) {
      top_reach = std::max(top_reach, i + 1);
      const double limit = layers[i].z_hi + top_thickness - kTolerance;
      while (top_reach < n && layers[top_reach].z_lo < limit) ++top_reach;
      // top_reach: the first layer starting at or past the limit (n: beyond the stack, which
      // counts when the stack's top is below the limit).
      long reach = top_reach - 1;
      if (top_reach == n && layers[n - 1].z_hi < limit) reach = n;
      above = std::max(above, reach - i);
    }
    long below = bottom_layers;
    if (bottom_thickness > 0) {
      const double limit = layers[i].z_lo - bottom_thickness + kTolerance;
      while (bottom_reach < i && !(layers[bottom_reach].z_hi > limit)) ++bottom_reach;
      // bottom_reach: the lowest layer ending above the limit; the bed (layer -1) counts when
      // the layer starts less than bottom_thickness over the stack's bottom.
      long reach = std::min(bottom_reach, i);
      if (reach == 0 && layers[0].z_lo > limit) reach = -1;
      below = std::max(below, i - reach);
    }
    first[i] = i - below;
    last[i] = i + above;
  }
  // Layer i gets a core of its own: wanted, and its window inside the stack (a window reaching
  // past either end covers nothing).
  const auto has_core = [&](long i) {
    const bool is_wanted = static_cast<std::size_t>(i) >= wanted.size() || wanted[i] != 0;
    return is_wanted && first[i] >= 0 && last[i] < n;
  };
  // core_i is the intersection of the window regions[first .. last]: layer i itself is in it
  // too, which changes nothing inside layer i. Windows of 2^k layers come from halves of
  // 2^(k-1) (a sparse table), so a window of any length L costs log2(L) + 1 intersections per
  // layer rather than L - 1. Each wanted window takes two spans of its level (they overlap:
  // together they are exact), and a span its two halves: only those are made.
  // (A window of two or more layers comes out of an intersection, which takes its inputs
  // with the non-zero rule: no cleaning needed first.)
  const auto level_of = [&](long i) {
    std::size_t level = 0;
    while ((2L << level) <= last[i] - first[i] + 1) ++level;
    return level;
  };
  // The second of window i's two spans (the first starts at first[i]).
  const auto second_of = [&](long i) { return last[i] - (1L << level_of(i)) + 1; };
  std::size_t levels = 1;
  for (long i = 0; i < n; ++i) {
    if (has_core(i)) levels = std::max(levels, level_of(i) + 1);
  }
  std::vector<std::vector<char>> needed(levels, std::vector<char>(n, 0));  // [k][i]
  for (long i = 0; i < n; ++i) {
    if (!has_core(i)) continue;
    needed[level_of(i)][first[i]] = 1;
    needed[level_of(i)][second_of(i)] = 1;
  }
  for (std::size_t k = levels; k-- > 1;) {
    const long half = 1L << (k - 1);
    for (long i = 0; i < n; ++i) {
      if (needed[k][i]) needed[k - 1][i] = needed[k - 1][i + half] = 1;
    }
  }
  // spans[k][i]: the intersection of regions[i .. i + 2^k - 1].
  std::vector<std::vector<clipper::Paths>> spans(levels, std::vector<clipper::Paths>(n));
  tbb::parallel_for(long{0}, n, [&](long i) {
    if (needed[0][i]) spans[0][i] = to_clipper(regions[i]);
  });
  for (std::size_t k = 1; k < levels; ++k) {
    const long half = 1L << (k - 1);
    tbb::parallel_for(long{0}, n, [&](long i) {
      if (!needed[k][i]) return;
      spans[k][i] = clipper::intersection(spans[k - 1][i], spans[k - 1][i + half]);
    });
  }
  tbb::parallel_for(long{0}, n, [&](long i) {
    if (!has_core(i)) {
      cores[i] = Region{};
      return;
    }
    const std::vector<clipper::Paths>& span = spans[level_of(i)];
    const long second = second_of(i);
    cores[i] = from_clipper(second == first[i] ? span[first[i]]
                                               : clipper::intersection(span[first[i]], span[second]));
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
