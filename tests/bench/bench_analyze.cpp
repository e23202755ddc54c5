// Benchmark: `mahost analyze` of the Stanford bunny with all four strategies, through the same
// library call the command makes (geometry::analyze_layers, layers in parallel with TBB).
//
// Usage: bench_analyze [STL] [--layer T] [--contours lower,mid,optimal-height,ma] [--worst N]
//                      [--tolerance D] [--levels K]   (distance tolerance, reverse heights)
//                      [--components]   (also: each metric timed alone, one thread, on the
//                                         first strategy's regions)
// Default: data/bunny.stl placed as in the paper (Y up, metres, 50 mm tall), 0.15 mm layers.
// Prints the wall time of the analysis, CPU time split into reference (slab, footprint,
// columns, limit), contours per strategy and metrics, the per-strategy summary, and the peak
// resident memory (getrusage; /usr/bin/time -v agrees).
#include <sys/resource.h>
#include <time.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <string>
#include <vector>

#include "geometry/analysis/layer_analysis.h"
#include "geometry/slicing/layer_stack.h"
#include "geometry/metrics/missed_features.h"
#include "geometry/slab/slab.h"
#include "geometry/metrics/volume_deviation.h"
#include "geometry/metrics/volume_limit.h"
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

static int run_bench(int argc, char** argv) {
  std::string path = std::string(MAHOST_DATA_DIR) + "/bunny.stl";
  double thickness = 0.15;
  std::string contours = contour_names(",");
  int worst = 0;
  bool components = false;
  AnalysisOptions options;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--layer" && i + 1 < argc) {
      thickness = std::atof(argv[++i]);
    } else if (arg == "--tolerance" && i + 1 < argc) {
      options.metrics.distance.tolerance = std::atof(argv[++i]);
    } else if (arg == "--levels" && i + 1 < argc) {
      options.metrics.distance.reverse_levels = std::atoi(argv[++i]);
    } else if (arg == "--components") {
      components = true;
    } else if (arg == "--worst" && i + 1 < argc) {
      worst = std::atoi(argv[++i]);
    } else if (arg == "--contours" && i + 1 < argc) {
      contours = argv[++i];
    } else {
      path = arg;
    }
  }
  std::vector<const ContourStrategy*> kinds;
  std::stringstream list(contours);
  for (std::string name; std::getline(list, name, ',');) {
    const ContourStrategy* kind = find_contour_strategy(name);
    if (!kind) {
      std::fprintf(stderr, "bench_analyze: unknown contour '%s'\n", name.c_str());
      return 2;
    }
    kinds.push_back(kind);
  }

  auto start = Clock::now();
  const Mesh mesh = bench::load_model(path);
  const Box3 box = bounding_box(mesh);
  const LayerStack stack(mesh, uniform_layers(box.max.z - box.min.z, thickness));
  const double load = seconds_since(start);

  start = Clock::now();
  const std::vector<LayerAnalysis> layers = analyze_layers(stack, kinds, options);
  const double wall = seconds_since(start);

  double reference = 0, metrics = 0;
  std::vector<double> contour(kinds.size(), 0);
  for (const LayerAnalysis& layer : layers) {
    reference += layer.reference_seconds;
    for (std::size_t k = 0; k < layer.strategies.size(); ++k) {
      contour[k] += layer.strategies[k].contour_seconds;
      metrics += layer.strategies[k].metric_seconds;
    }
  }
  std::printf("model %s: %zu faces, %zu layers of %.3f mm, load+repair+place %.2f s\n",
              path.c_str(), mesh.faces.size(), stack.size(), thickness, load);
  std::printf("analyze wall time: %.2f s (all strategies, TBB over layers)\n", wall);
  std::printf("cpu time: reference %.2f s, metrics %.2f s (%.2f ms per layer and strategy)\n",
              reference, metrics, 1e3 * metrics / (layers.size() * kinds.size()));
  for (std::size_t k = 0; k < kinds.size(); ++k) {
    std::printf("  contours %-15s %.2f s (%.2f ms per layer)\n",
                std::string(kinds[k]->name).c_str(), contour[k],
                1e3 * contour[k] / layers.size());
  }
  std::printf("%-15s %8s %8s %10s %10s %9s %7s %6s %6s\n", "strategy", "mean D", "max D",
              "total dV", "mean dV", ">limit%", "missed", ">lower", ">mid");
  for (const StrategySummary& s : summarize(layers)) {
    std::printf("%-15s %8.4f %8.4f %10.3f %10.5f %9.2f %7zu %6zu %6zu\n",
                std::string(s.strategy->name).c_str(), s.mean_distance, s.max_distance,
                s.total_deviation, s.mean_deviation, s.above_limit_percent, s.missed_features,
                s.worse_than_lower, s.worse_than_mid);
  }
  // The layers with the largest D per strategy, to see where the figures come from.
  for (std::size_t k = 0; k < kinds.size() && worst > 0; ++k) {
    std::vector<std::size_t> order(layers.size());
    for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
      return layers[a].strategies[k].metrics.distance > layers[b].strategies[k].metrics.distance;
    });
    std::printf("worst layers of %s:", std::string(kinds[k]->name).c_str());
    for (int j = 0; j < worst && j < static_cast<int>(order.size()); ++j) {
      const LayerMetrics& m = layers[order[j]].strategies[k].metrics;
      std::printf(" #%zu z=%.2f D=%.3f missed=%zu;", order[j], m.z_lo, m.distance, m.missed_features);
    }
    std::printf("\n");
  }
  if (components) {
    // One thread, every layer, the first strategy's region: what each piece of the metrics costs.
    double t_ref[6] = {0}, t_metric[5] = {0};
    // Thread CPU time, so that other work on the machine does not count.
    const auto cpu_now = [] {
      timespec now{};
      clock_gettime(CLOCK_THREAD_CPUTIME_ID, &now);
      return static_cast<double>(now.tv_sec) + 1e-9 * static_cast<double>(now.tv_nsec);
    };
    const auto tick = [&](double& at) {
      const double now = cpu_now();
      const double s = now - at;
      at = now;
      return s;
    };
    for (std::size_t i = 0; i < stack.size(); ++i) {
      double at = cpu_now();
      const Slab slab = slab_of(stack, i);
      t_ref[0] += tick(at);
      const Region footprint = slab_footprint(slab);
      t_ref[1] += tick(at);
      const auto islands = boundary_pairs(footprint);
      const Region lower = stack.lower(i);
      t_ref[2] += tick(at);
      const SlabColumns columns = slab_columns(slab, lower);
      t_ref[3] += tick(at);
      const SlabSurface surface = slab_surface(slab, options.metrics.distance);
      t_ref[4] += tick(at);
      volume_limit(columns);
      t_ref[5] += tick(at);
      const Region& region = layers[i].strategies[0].region;
      const BoundaryGrid walls(region);
      t_metric[0] += tick(at);
      volume_deviation(columns, region, walls);
      t_metric[1] += tick(at);
      const auto missed = missed_features(islands, region);
      t_metric[2] += tick(at);
      SlabSurface no_levels = surface;
      no_levels.levels.clear();
      t_metric[4] -= tick(at);
      distance_error(no_levels, walls, missed, options.metrics.distance);
      t_metric[3] += tick(at);
      distance_error(surface, walls, missed, options.metrics.distance);
      t_metric[4] += tick(at);
    }
    std::printf("cpu, reference, one thread: slab %.2f s, footprint %.2f s, islands+lower %.2f s, "
                "columns %.2f s, surface %.2f s, limit %.2f s\n",
                t_ref[0], t_ref[1], t_ref[2], t_ref[3], t_ref[4], t_ref[5]);
    std::printf("metrics of the first strategy, one thread: grid %.2f s, dV %.2f s, missed %.2f s, "
                "forward D %.2f s, forward+reverse D %.2f s\n",
                t_metric[0], t_metric[1], t_metric[2], t_metric[3], t_metric[4]);
  }
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  std::printf("peak resident memory: %.1f MB\n", usage.ru_maxrss / 1024.0);
  return 0;
}

int main(int argc, char** argv) { return bench::main(argc, argv, run_bench); }
