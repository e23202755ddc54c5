// Estimates of layer stacks from a sample of their layers; see uniform_estimate.h.
#include "app/uniform_estimate.h"

#include <algorithm>
#include <cmath>

#include <tbb/parallel_for.h>

#include "geometry/core/clipper.h"
#include "geometry/support/support_plan.h"
#include "geometry/toolpaths/toolpath_plan.h"
#include "app/stage_options.h"

namespace app {
namespace {

// The sample's one pair in so many: estimated_seconds's, uniform_seconds's.
constexpr std::size_t kEstimatePairs = 3;
constexpr std::size_t kScaledPairs = 12;
// A sampled layer is compared with the last sampled one of its parity below it: a layer
// whose part's or support's area differs from it by more than this share is sampled too.
constexpr double kEstimateChange = 0.10;
// The sample's sections are straightened within this first (mm), as sparse infill's area is
// (infill.cpp): a fine mesh's section has several times the vertices a print time needs, and
// every offset and boolean of the toolpaths pays for them. tests/bench/estimate_accuracy.sh,
// 22 rows (the bunny, a sphere, a T, a frustum, steps, a dome, a vase): with the sections
// straightened the largest error is 1.7% and the mean 0.56%, against 1.7% and 0.53% without
// (the bunny's own, without supports, -0.7% against +0.1%: the straightened beads run with
// fewer slow-downs), and the bunny's adaptive slice takes 5% less time.
constexpr double kSampleTolerance = 0.025;

// How a layer came into the sample (ToolpathOptions::planned takes any non-zero as planned).
constexpr char kRegular = 1;  // one pair in so many, alike the sampled layer below
constexpr char kChanged = 2;  // unlike the sampled layer of its parity below it (supports,
                              // skins near a change of area, the bed, the top)
constexpr char kGrown = 3;    // only its part's area unlike that layer's

// Which layer's paths each layer prints in estimated_seconds (itself where it is sampled),
// and in `options.planned` the layers to plan: one pair in `pairs` and the unlike ones; each
// layer's area (its part's and its support's, mm^2) into `areas`.
std::vector<std::size_t> estimate_sources(const std::vector<geometry::Region>& regions,
                                          const std::vector<geometry::Layer>& layers,
                                          const geometry::SupportPlan& supports,
                                          geometry::ToolpathOptions& options, std::size_t pairs,
                                          std::vector<double>& areas) {
  const std::size_t n = regions.size();
  std::vector<double> part(n), support(n, 0);
  std::vector<char> special(n, 0);
  for (std::size_t i = 0; i < n; ++i) {
    part[i] = geometry::area(regions[i]);
    if (i < supports.layers.size()) {
      const geometry::LayerSupport& held = supports.layers[i];
      support[i] = geometry::area(held.body);
      special[i] = !held.interface.loops.empty() || !held.bridges.empty();
    }
  }
  const auto unlike = [](double a, double b) {
    return std::abs(a - b) > kEstimateChange * std::max(a, b);
  };
  // Skins: a layer within the skins' reach of a change of area is planned, and so of the bed
  // and of the stack's top. The reach in layers: at least so many, and so many mm of the
  // thinnest layer after the first.
  double thinnest = INFINITY;
  for (std::size_t i = 1; i < layers.size(); ++i) thinnest = std::min(thinnest, layers[i].thickness());
  int skin = std::max({options.top_layers, options.bottom_layers, 0});
  if (std::isfinite(thinnest) && thinnest > 0) {
    for (const double mm : {options.top_thickness, options.bottom_thickness}) {
      if (mm > 0) skin = std::max(skin, static_cast<int>(std::ceil(mm / thinnest - 1e-6)));
    }
  }
  const std::size_t reach = static_cast<std::size_t>(skin) + 1;
  for (std::size_t i = 0; i < n; ++i) {
    if (i < reach || i + reach >= n) special[i] = 1;
    if (i == 0 || !unlike(part[i], part[i - 1])) continue;
    for (std::size_t k = i > reach ? i - reach : 0; k < std::min(n, i + reach); ++k) special[k] = 1;
  }
  options.planned.assign(n, 0);
  std::vector<std::size_t> source(n);
  std::size_t last[2] = {0, 0};  // the last layer planned of each parity
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t from = last[i % 2];
    const bool changed = special[i] || special[from] || unlike(support[i], support[from]);
    const bool grown = unlike(part[i], part[from]);
    if (i < 2 || (i / 2) % pairs == 0 || changed || grown) {
      options.planned[i] = changed ? kChanged : grown ? kGrown : kRegular;
      last[i % 2] = i;
    }
    source[i] = last[i % 2];
  }
  areas.resize(n);
  for (std::size_t i = 0; i < n; ++i) areas[i] = part[i] + support[i];
  return source;
}

// The sample's toolpaths, raft layers first, and which layer's paths each part layer prints
// in estimated_seconds (itself where it is sampled).
struct SampledPaths {
  std::vector<geometry::LayerToolpaths> toolpaths;
  std::vector<std::size_t> source;
  std::vector<char> planned;  // per part layer: 0, kRegular, kChanged or kGrown
  std::vector<double> areas;  // per part layer: its part's and its support's area, mm^2
  std::size_t raft = 0;
};
SampledPaths sampled_paths(const geometry::LayerStack& index, const std::vector<geometry::Layer>& layers,
                           const printer::Profiles& profiles, std::size_t pairs) {
  const geometry::LayerStack stack(index, layers);
  const std::size_t n = layers.size();
  std::vector<geometry::Region> regions(n);
  tbb::parallel_for(std::size_t{0}, n, [&](std::size_t i) {
    regions[i] = geometry::from_clipper(
        geometry::clipper::simplified(geometry::to_clipper(stack.mid(i)), kSampleTolerance));
  });
  const geometry::SupportPlan supports = geometry::plan_supports(
      regions, layers, support_options(profiles), raft_options(profiles.printer));
  geometry::ToolpathOptions options = toolpath_options(profiles.printer);
  SampledPaths sample;
  sample.source = estimate_sources(regions, layers, supports, options, pairs, sample.areas);
  sample.planned = options.planned;
  sample.toolpaths = geometry::plan_toolpaths(regions, layers, options, supports);
  sample.raft = sample.toolpaths.size() - n;  // the part's layers follow the raft's
  return sample;
}

}  // namespace

double estimated_seconds(const geometry::LayerStack& index, const std::vector<geometry::Layer>& layers,
                         const printer::Profiles& profiles) {
  SampledPaths sample = sampled_paths(index, layers, profiles, kEstimatePairs);
  const std::size_t n = layers.size();
  for (std::size_t i = 0; i < n; ++i) {
    if (sample.source[i] != i) {
      sample.toolpaths[sample.raft + i].paths = sample.toolpaths[sample.raft + sample.source[i]].paths;
    }
  }
  const printer::GcodeSummary summary = printer::time_gcode(sample.toolpaths, profiles);
  if (summary.layer_starts.size() != sample.toolpaths.size()) return summary.print_seconds;
  const std::vector<double>& area = sample.areas;
  const auto layer_time = [&](std::size_t i) { return summary.layer_seconds(sample.raft + i); };
  // The next sampled layer of each layer's parity above it, unless sampled for a change of
  // what it prints other than its part's area (n: none).
  std::vector<std::size_t> above(n, n);
  std::size_t next[2] = {n, n};
  for (std::size_t i = n; i-- > 0;) {
    above[i] = next[i % 2];
    if (sample.source[i] == i) next[i % 2] = sample.planned[i] == kChanged ? n : i;
  }
  double seconds = summary.print_seconds;
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t lo = sample.source[i], hi = above[i];
    if (lo == i || !(area[lo] > 0) || !(area[i] > 0)) continue;
    // Its time per mm^2 (of its part and support) as the sampled layers' of its parity on
    // either side, interpolated by height in layers: the copied paths' time, scaled.
    double scale = area[i] / area[lo];
    if (hi != n && area[hi] > 0 && layer_time(lo) > 0) {
      const double w = static_cast<double>(i - lo) / static_cast<double>(hi - lo);
      scale *= (1 - w) + w * (layer_time(hi) / area[hi]) / (layer_time(lo) / area[lo]);
    }
    seconds += (scale - 1) * layer_time(i);
  }
  return seconds;
}

LayerSample sample_layers(const geometry::LayerStack& index, const std::vector<geometry::Layer>& layers,
                          const printer::Profiles& profiles) {
  const SampledPaths sample = sampled_paths(index, layers, profiles, kScaledPairs);
  const printer::GcodeSummary summary = printer::time_gcode(sample.toolpaths, profiles);
  LayerSample timed_layers;
  timed_layers.layers = layers;
  timed_layers.seconds.assign(layers.size(), -1);
  timed_layers.changed.assign(layers.size(), 0);
  for (std::size_t i = 0; i < layers.size() && i < sample.planned.size(); ++i) {
    timed_layers.changed[i] = sample.planned[i] == kChanged || sample.planned[i] == kGrown;
  }
  const std::vector<double>& starts = summary.layer_starts;
  if (starts.size() != sample.toolpaths.size()) return timed_layers;
  timed_layers.before = starts[sample.raft];
  for (std::size_t i = 0; i < layers.size(); ++i) {
    if (sample.source[i] != i) continue;
    timed_layers.seconds[i] = summary.layer_seconds(sample.raft + i);
  }
  return timed_layers;
}

double uniform_seconds(const LayerSample& sample, const std::vector<geometry::Layer>& printed,
                       const printer::GcodeSummary& summary) {
  const std::size_t n = sample.layers.size();
  const std::vector<double>& starts = summary.layer_starts;
  // The printed layer holding each sample layer's middle, and its time (none: 0, and the
  // sample's layers stand for those not sampled as they are).
  std::vector<double> printed_seconds(n, 0);
  const bool timed = !printed.empty() && starts.size() >= printed.size();
  const std::size_t raft = timed ? starts.size() - printed.size() : 0;
  for (std::size_t j = 0, i = 0; timed && j < n; ++j) {
    const double middle = 0.5 * (sample.layers[j].z_lo + sample.layers[j].z_hi);
    while (i + 1 < printed.size() && printed[i].z_hi <= middle) ++i;
    printed_seconds[j] = summary.layer_seconds(raft + i);
  }
  const auto sampled = [&](std::size_t j) { return sample.seconds[j] >= 0; };
  // A sampled layer's time against its printed layer's; where that one takes no time, its
  // own time stands for its neighbours as it is.
  const auto ratio = [&](std::size_t s) {
    return printed_seconds[s] > 0 ? sample.seconds[s] / printed_seconds[s] : -1.0;
  };
  // The sampled layers of each parity at or above each layer (n: none).
  std::vector<std::size_t> above(n, n);
  std::size_t next[2] = {n, n};
  for (std::size_t j = n; j-- > 0;) {
    if (sampled(j)) next[j % 2] = j;
    above[j] = next[j % 2];
  }
  double seconds = sample.before;
  // Printed layers alike (their times within kEstimateChange of each other): the ratio of
  // a sampled layer carries over from one to the other.
  const auto alike = [&](std::size_t a, std::size_t b) {
    return std::abs(printed_seconds[a] - printed_seconds[b]) <=
           kEstimateChange * std::max(printed_seconds[a], printed_seconds[b]);
  };
  std::size_t below[2] = {n, n};  // the last sampled layer of each parity so far
  for (std::size_t j = 0; j < n; ++j) {
    double t = 0;
    if (sampled(j)) {
      t = sample.seconds[j];
      below[j % 2] = j;
    } else {
      // Sampled layers of its parity below it (alike it: else this one would be sampled
      // too) and above it (alike unless sampled for a change).
      const std::size_t lo = below[j % 2], hi = above[j];
      const bool use_lo = lo != n && ratio(lo) >= 0 && alike(lo, j);
      const bool use_hi = hi != n && !sample.changed[hi] && ratio(hi) >= 0 && alike(hi, j);
      if (use_lo && use_hi) {
        const double w = static_cast<double>(j - lo) / static_cast<double>(hi - lo);
        t = ((1 - w) * ratio(lo) + w * ratio(hi)) * printed_seconds[j];
      } else if (use_lo || use_hi) {
        t = ratio(use_lo ? lo : hi) * printed_seconds[j];
      } else if (lo != n || hi != n) {
        // The printed program changes here where the sample does not: as the sample below.
        t = sample.seconds[lo != n ? lo : hi];
      }
    }
    seconds += t;
  }
  return seconds;
}

}  // namespace app
