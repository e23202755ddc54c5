// Benchmark: the medial-axis contour (ma_contour) over every layer of the Stanford bunny.
//
// Usage: bench_ma [STL] [--layer T] [--spacing S] [--max-points N] [--no-fairing] [--errors]
//                 [--no-features] [--no-pockets]   (the rules of ma_contour.h, off)
//                 [--dump FILE] [--compare FILE] [--quick]
// --quick: the sequential pass only (no stage split, no parallel pass), for callgrind or perf.
// --dump writes every layer's contour to FILE (text, mm); --compare reads such a file and
// prints how far this run's contours are from it: the area of the symmetric difference per
// layer (sum, max) against the contours' area, to judge a speed change by its results.
// Default: data/bunny.stl placed as in the paper (Y up, metres, 50 mm tall), 0.15 mm layers.
// Prints per-layer time (max, mean), the sequential total, the TBB-parallel wall time,
// sample counts, islands, caps, and the contours' validity. With --errors also the paper's
// distance error D (mean, max over layers) of lower, mid and ma (distance_error.h). Peak memory: run it under
// /usr/bin/time -v.
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <fstream>
#include <string>
#include <vector>

#include "geometry/core/boundary_grid.h"
#include "geometry/core/clipper.h"
#include "geometry/metrics/distance_error.h"
#include "geometry/slicing/layer_stack.h"
#include "geometry/metrics/missed_features.h"
#include "geometry/contour/ma_contour.h"
#include "geometry/mesh/placement.h"
#include "geometry/mesh/repair.h"
#include "geometry/mesh/stl_io.h"
#include "bench/bench_main.h"
#include "bench/bench_model.h"

using namespace geometry;
using Clock = std::chrono::steady_clock;

static double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// One line per loop: "layer n x0 y0 x1 y1 ...", full double precision.
static void dump_contours(const std::string& file, const std::vector<Region>& contours) {
  std::ofstream out(file);
  out.precision(17);
  for (std::size_t i = 0; i < contours.size(); ++i) {
    for (const Loop& loop : contours[i].loops) {
      out << i << ' ' << loop.size();
      for (Vec2 p : loop) out << ' ' << p.x << ' ' << p.y;
      out << '\n';
    }
  }
}

static std::vector<Region> read_contours(const std::string& file, std::size_t layers) {
  std::vector<Region> contours(layers);
  std::ifstream in(file);
  std::size_t layer = 0, n = 0;
  while (in >> layer >> n) {
    Loop loop(n);
    for (Vec2& p : loop) in >> p.x >> p.y;
    if (layer < layers) contours[layer].loops.push_back(std::move(loop));
  }
  return contours;
}

// Symmetric difference of each layer's contours, mm^2: sum and max over layers, and the sum
// of the reference's areas.
static void compare_contours(const std::string& file, const std::vector<Region>& contours) {
  const std::vector<Region> reference = read_contours(file, contours.size());
  double xor_sum = 0, xor_max = 0, area = 0;
  std::size_t worst = 0, differing = 0;
  for (std::size_t i = 0; i < contours.size(); ++i) {
    const double x = clipper::area_mm2(
        clipper::symmetric_difference(to_clipper(contours[i]), to_clipper(reference[i])));
    area += clipper::area_mm2(to_clipper(reference[i]));
    xor_sum += x;
    if (x > 1e-6) ++differing;
    if (x > xor_max) {
      xor_max = x;
      worst = i;
    }
  }
  std::printf("against %s: symmetric difference %.6f mm^2 in all (%.2e of %.1f mm^2), "
              "max %.6f mm^2 (layer %zu), %zu layers differ by > 1e-6 mm^2\n",
              file.c_str(), xor_sum, area > 0 ? xor_sum / area : 0.0, area, xor_max, worst,
              differing);
}

static int run_bench(int argc, char** argv) {
  std::string path = std::string(MAHOST_DATA_DIR) + "/bunny.stl";
  double thickness = 0.15;
  MaOptions options;
  bool errors = false;
  std::string dump, compare;
  bool quick = false;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--layer" && i + 1 < argc) {
      thickness = std::atof(argv[++i]);
    } else if (arg == "--spacing" && i + 1 < argc) {
      options.spacing = std::atof(argv[++i]);
    } else if (arg == "--max-points" && i + 1 < argc) {
      options.max_points = static_cast<std::size_t>(std::atoll(argv[++i]));
    } else if (arg == "--dump" && i + 1 < argc) {
      dump = argv[++i];
    } else if (arg == "--compare" && i + 1 < argc) {
      compare = argv[++i];
    } else if (arg == "--quick") {
      quick = true;
    } else if (arg == "--errors") {
      errors = true;
    } else if (arg == "--no-fairing") {
      options.fairing = false;
    } else if (arg == "--no-features") {
      options.floating_features = false;
    } else if (arg == "--no-pockets") {
      options.pockets = false;
    } else {
      path = arg;
    }
  }

  auto start = Clock::now();
  const Mesh mesh = bench::load_model(path);
  const double load = seconds_since(start);
  const Box3 box = bounding_box(mesh);
  LayerStack stack(mesh, uniform_layers(box.max.z - box.min.z, thickness));
  std::printf("model %s: %zu faces, %.2f mm tall, %zu layers of %.3f mm (load+repair %.2f s)\n",
              path.c_str(), mesh.faces.size(), box.max.z - box.min.z, stack.size(), thickness,
              load);

  std::vector<double> times(stack.size());
  std::vector<MaStats> stats(stack.size());
  std::vector<Region> contours(stack.size());
  start = Clock::now();
  const std::clock_t cpu_start = std::clock();
  for (std::size_t i = 0; i < stack.size(); ++i) {
    const auto t0 = Clock::now();
    contours[i] = ma_contour(stack, i, options, stats[i]);
    times[i] = seconds_since(t0);
  }
  const double sequential = seconds_since(start);
  const double cpu = static_cast<double>(std::clock() - cpu_start) / CLOCKS_PER_SEC;

  // The same split into its stages, as `analyze` runs it (slab and footprint are shared
  // with the metrics there): CPU seconds.
  double slab_cpu = 0, footprint_cpu = 0, contour_cpu = 0;
  for (std::size_t i = 0; i < (quick ? 0 : stack.size()); ++i) {
    std::clock_t t = std::clock();
    const Slab slab = slab_of(stack, i);
    slab_cpu += static_cast<double>(std::clock() - t) / CLOCKS_PER_SEC;
    t = std::clock();
    const Region footprint = slab_footprint(slab);
    footprint_cpu += static_cast<double>(std::clock() - t) / CLOCKS_PER_SEC;
    t = std::clock();
    const Region contour = ma_contour(
        slab, footprint, [&stack](double z) { return stack.cross_section(z); }, options);
    contour_cpu += static_cast<double>(std::clock() - t) / CLOCKS_PER_SEC;
  }

  start = Clock::now();
  std::vector<Region> parallel = quick ? contours : std::vector<Region>(stack.size());
  if (!quick) {
    tbb::parallel_for(std::size_t{0}, stack.size(),
                      [&](std::size_t i) { parallel[i] = ma_contour(stack, i, options); });
  }
  const double wall = seconds_since(start);

  std::size_t samples = 0, max_samples = 0, islands = 0, caps = 0, walls = 0, loops = 0, empty = 0;
  std::size_t features = 0, pockets = 0;
  std::size_t differing = 0, slowest = 0;
  for (std::size_t i = 0; i < stack.size(); ++i) {
    samples += stats[i].samples;
    max_samples = std::max(max_samples, stats[i].samples);
    islands += stats[i].islands;
    caps += stats[i].caps;
    walls += stats[i].walls;
    features += stats[i].features;
    pockets += stats[i].pockets;
    loops += contours[i].loops.size();
    if (contours[i].loops.empty()) ++empty;
    if (times[i] > times[slowest]) slowest = i;
    bool same = parallel[i].loops.size() == contours[i].loops.size();
    for (std::size_t k = 0; same && k < parallel[i].loops.size(); ++k) {
      same = parallel[i].loops[k].size() == contours[i].loops[k].size() &&
             std::equal(parallel[i].loops[k].begin(), parallel[i].loops[k].end(),
                        contours[i].loops[k].begin());
    }
    if (!same) ++differing;
  }
  const double mean = stack.size() ? sequential / stack.size() : 0;
  std::printf("options: spacing %s, max_points %zu, fairing %s, features %s, pockets %s\n",
              options.spacing > 0 ? std::to_string(options.spacing).c_str() : "default",
              options.max_points, options.fairing ? "on" : "off",
              options.floating_features ? "on" : "off", options.pockets ? "on" : "off");
  std::printf("per layer: max %.1f ms (layer %zu, %zu samples), mean %.2f ms\n",
              times[slowest] * 1e3, slowest, stats[slowest].samples, mean * 1e3);
  std::printf("total: %.3f s sequential (%.3f s CPU), %.3f s wall with TBB (%zu layers)\n",
              sequential, cpu, wall, stack.size());
  std::printf("stages (CPU): slab %.3f s, footprint %.3f s, contour from footprint %.3f s\n",
              slab_cpu, footprint_cpu, contour_cpu);
  std::printf("samples: %zu total, %zu max per layer; islands %zu, caps %zu, walls %zu; "
              "floating features %zu, pockets given the mid section %zu\n",
              samples, max_samples, islands, caps, walls, features, pockets);
  std::printf("contours: %zu loops, %zu empty layers, %zu layers differ sequential vs parallel\n",
              loops, empty, differing);
  if (!dump.empty()) dump_contours(dump, contours);
  if (!compare.empty()) compare_contours(compare, contours);
  if (errors) {
    struct Tally {
      const char* name;
      double sum = 0, max = 0;
    };
    std::vector<Tally> tallies{{"lower"}, {"mid"}, {"ma"}};
    std::vector<std::array<double, 3>> d(stack.size());
    std::vector<std::size_t> missed_by_ma(stack.size());
    tbb::parallel_for(std::size_t{0}, stack.size(), [&](std::size_t i) {
      const Slab slab = slab_of(stack, i);
      const SlabSurface surface = slab_surface(slab);
      const std::vector<BoundaryPair> islands = boundary_pairs(slab_footprint(slab));
      const Region regions[3] = {stack.lower(i), stack.mid(i), contours[i]};
      for (int k = 0; k < 3; ++k) {
        const std::vector<BoundaryPair> missed = missed_features(islands, regions[k]);
        d[i][k] = distance_error(surface, BoundaryGrid(regions[k]), missed).forward;
        if (k == 2) missed_by_ma[i] = missed.size();
      }
    });
    std::size_t ma_worse_than_lower = 0, ma_worse_than_mid = 0, missed = 0;
    for (std::size_t i = 0; i < stack.size(); ++i) {
      missed += missed_by_ma[i];
      for (int k = 0; k < 3; ++k) {
        tallies[k].sum += d[i][k];
        tallies[k].max = std::max(tallies[k].max, d[i][k]);
      }
      if (d[i][2] > d[i][0] + 1e-3) ++ma_worse_than_lower;
      if (d[i][2] > d[i][1] + 1e-3) ++ma_worse_than_mid;
    }
    if (std::getenv("BENCH_MA_LAYERS")) {
      for (std::size_t i = 0; i < stack.size(); ++i) {
        std::printf("layer %3zu z %.3f D lower %.3f mid %.3f ma %.3f\n", i, stack.layers()[i].z_lo,
                    d[i][0], d[i][1], d[i][2]);
      }
    }
    for (const Tally& t : tallies) {
      std::printf("distance error %-5s: mean %.3f mm, max %.3f mm\n", t.name,
                  t.sum / stack.size(), t.max);
    }
    std::printf("layers where ma is worse (by > 1 um): than lower %zu, than mid %zu; "
                "footprint islands ma misses: %zu\n",
                ma_worse_than_lower, ma_worse_than_mid, missed);
  }
  return differing == 0 ? 0 : 1;
}

int main(int argc, char** argv) { return bench::main(argc, argv, run_bench); }
