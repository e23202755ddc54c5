#include "geometry/toolpaths/skins.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "geometry/core/clipper.h"

namespace geometry {

namespace {

constexpr double kTolerance = 1e-6;  // mm: sums of layer thicknesses are not exact

// The depths with a negative count or thickness, or an infinite thickness, taken as none.
SkinDepth clamped(const SkinDepth& depth) {
  const auto thickness = [](double t) { return std::isfinite(t) ? std::max(t, 0.0) : 0; };
  return {std::max(depth.top_layers, 0), std::max(depth.bottom_layers, 0),
          thickness(depth.top_thickness), thickness(depth.bottom_thickness)};
}

// How many layers over layer i the top skin reaches by thickness: the layers above reaching
// less than `thickness` over the layer's top; beyond the stack's top is a layer that covers
// nothing. `reach` only moves up as i does: the first layer starting at or past the limit
// (n: beyond the stack).
long layers_above(const std::vector<Layer>& layers, long n, long i, double thickness,
                  long& reach) {
  reach = std::max(reach, i + 1);
  const double limit = layers[i].z_hi + thickness - kTolerance;
  while (reach < n && layers[reach].z_lo < limit) ++reach;
  // Beyond the stack counts when the stack's top is below the limit.
  long last = reach - 1;
  if (reach == n && layers[n - 1].z_hi < limit) last = n;
  return last - i;
}

// How many layers under layer i the bottom skin reaches by thickness: the layers below
// reaching less than `thickness` under its bottom; the bed (layer -1) counts when the layer
// starts less than `thickness` over the stack's bottom. `reach` only moves up as i does: the
// lowest layer ending above the limit.
long layers_below(const std::vector<Layer>& layers, long i, double thickness, long& reach) {
  const double limit = layers[i].z_lo - thickness + kTolerance;
  while (reach < i && !(layers[reach].z_hi > limit)) ++reach;
  long lowest = std::min(reach, i);
  if (lowest == 0 && layers[0].z_lo > limit) lowest = -1;
  return i - lowest;
}

// Each layer's window: the layers [first, last] whose regions must all cover a point for it
// to be sparse; whether the layer gets a core of its own (wanted, and its window inside the
// stack: a window reaching past either end covers nothing); and the window's two spans in
// the sparse table (see sparse_cores), at its level, from first and from second.
struct Windows {
  std::vector<long> first, last, second;
  std::vector<std::size_t> level;
  std::vector<char> core;
};

Windows windows_of(const std::vector<Layer>& layers, long n, const SkinDepth& depth,
                   const std::vector<char>& wanted) {
  Windows w{std::vector<long>(n), std::vector<long>(n), std::vector<long>(n),
            std::vector<std::size_t>(n), std::vector<char>(n)};
  long top_reach = 0, bottom_reach = 0;
  for (long i = 0; i < n; ++i) {
    long above = depth.top_layers;
    if (depth.top_thickness > 0) {
      above = std::max(above, layers_above(layers, n, i, depth.top_thickness, top_reach));
    }
    long below = depth.bottom_layers;
    if (depth.bottom_thickness > 0) {
      below = std::max(below, layers_below(layers, i, depth.bottom_thickness, bottom_reach));
    }
    w.first[i] = i - below;
    w.last[i] = i + above;
    while ((2L << w.level[i]) <= w.last[i] - w.first[i] + 1) ++w.level[i];
    w.second[i] = w.last[i] - (1L << w.level[i]) + 1;
    const bool is_wanted = static_cast<std::size_t>(i) >= wanted.size() || wanted[i] != 0;
    w.core[i] = is_wanted && w.first[i] >= 0 && w.last[i] < n;
  }
  return w;
}

// needed[k][i]: whether the span of 2^k layers from layer i is needed: each core's window
// takes two spans of its level, and a span its two halves.
std::vector<std::vector<char>> needed_spans(const Windows& w, long n) {
  std::size_t levels = 1;
  for (long i = 0; i < n; ++i) {
    if (w.core[i]) levels = std::max(levels, w.level[i] + 1);
  }
  std::vector<std::vector<char>> needed(levels, std::vector<char>(n, 0));
  for (long i = 0; i < n; ++i) {
    if (!w.core[i]) continue;
    needed[w.level[i]][w.first[i]] = 1;
    needed[w.level[i]][w.second[i]] = 1;
  }
  for (std::size_t k = levels; k-- > 1;) {
    const long half = 1L << (k - 1);
    for (long i = 0; i < n; ++i) {
      if (needed[k][i]) needed[k - 1][i] = needed[k - 1][i + half] = 1;
    }
  }
  return needed;
}

// spans[k][i]: the intersection of regions[i .. i + 2^k - 1], where needed.
std::vector<std::vector<clipper::Paths>> span_intersections(
    const std::vector<Region>& regions, const std::vector<std::vector<char>>& needed, long n) {
  const std::size_t levels = needed.size();
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
  return spans;
}

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
  const SkinDepth d = clamped(depth);
  if (d.top_layers == 0 && d.bottom_layers == 0 && d.top_thickness == 0 &&
      d.bottom_thickness == 0) {
    return cores;
  }
  // core_i is the intersection of the window regions[first .. last]: layer i itself is in it
  // too, which changes nothing inside layer i. Windows of 2^k layers come from halves of
  // 2^(k-1) (a sparse table), so a window of any length L costs log2(L) + 1 intersections per
  // layer rather than L - 1. Each wanted window takes two spans of its level (they overlap:
  // together they are exact), and a span its two halves: only those are made.
  // (A window of two or more layers comes out of an intersection, which takes its inputs
  // with the non-zero rule: no cleaning needed first.)
  const Windows w = windows_of(layers, n, d, wanted);
  const std::vector<std::vector<clipper::Paths>> spans =
      span_intersections(regions, needed_spans(w, n), n);
  tbb::parallel_for(long{0}, n, [&](long i) {
    if (!w.core[i]) {
      cores[i] = Region{};
      return;
    }
    const std::vector<clipper::Paths>& span = spans[w.level[i]];
    const long first = w.first[i], second = w.second[i];
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
  // What lies outside a region: nothing where the area is proven inside it (the slivers of a
  // unit Clipper's difference may leave there do not survive the opening), without the sweep.
  const auto outside = [&](const clipper::Paths& paths, const Region& region) {
    const clipper::Paths region_paths = to_clipper(region);
    if (clipper::proven_inside(paths, region_paths)) return clipper::Paths{};
    return clipper::opening(clipper::difference(paths, region_paths), sliver);
  };
  clipper::Paths solid = outside(all, *core);
  skins.sparse = from_clipper(clipper::difference(all, solid));
  if (solid.empty()) return skins;
  clipper::Paths bottom, top;
  if (below) bottom = outside(solid, *below);
  if (above) top = outside(clipper::difference(solid, bottom), *above);
  skins.bottom = from_clipper(bottom);
  skins.top = from_clipper(top);
  skins.solid = from_clipper(clipper::difference(solid, clipper::union_nonzero(bottom, top)));
  return skins;
}

}  // namespace geometry
