// Benchmark: the support stage on the 50 mm Stanford bunny.
//
//   build*/tests/bench/bench_supports [MODEL.stl] [layer mm] [contour] [none|buildplate|everywhere]
//                                     [repeat]
//
// Reads and repairs the bunny (Y up, metres, scaled to 50 mm tall), cuts its layers (0.2 mm
// after a 0.3 mm first layer, as on the UP Plus 2), takes each layer's region from the
// contour strategy (ma by default), then times, each `repeat` times: plan_supports
// (supports everywhere by default, the default options: 50 degrees, 0.2 mm gaps, lines 2.5
// mm apart) and plan_toolpaths with that plan and without any, and prints their wall and
// CPU times, what the plan holds (support area and volume, bridges, layers with support)
// and the toolpaths' extra length. CPU time (all threads) is the figure a shared machine
// does not inflate; under
//   valgrind --tool=callgrind --instr-atstart=no build*/tests/bench/bench_supports ...
// only plan_supports is counted.
#include <sys/resource.h>
#include <tbb/parallel_for.h>
#if __has_include(<valgrind/callgrind.h>)
#include <valgrind/callgrind.h>
#else
#define CALLGRIND_START_INSTRUMENTATION
#define CALLGRIND_STOP_INSTRUMENTATION
#endif

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>

#include "geometry/contour/contour_strategy.h"
#include "geometry/mesh/placement.h"
#include "geometry/mesh/repair.h"
#include "geometry/mesh/stl_io.h"
#include "geometry/slicing/layer_stack.h"
#include "geometry/support/support_plan.h"
#include "geometry/toolpaths/toolpath_plan.h"
#include "bench/bench_main.h"
#include "bench/bench_model.h"

namespace {

double cpu_seconds() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<double>(usage.ru_utime.tv_sec + usage.ru_stime.tv_sec) +
         1e-6 * static_cast<double>(usage.ru_utime.tv_usec + usage.ru_stime.tv_usec);
}

struct Timed {
  double wall = 0, cpu = 0;
};

template <class F>
Timed timed(int repeat, F&& f) {
  const auto start = std::chrono::steady_clock::now();
  const double cpu = cpu_seconds();
  for (int k = 0; k < repeat; ++k) f();
  return {std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() / repeat,
          (cpu_seconds() - cpu) / repeat};
}

double path_length(const std::vector<geometry::LayerToolpaths>& plan) {
  double total = 0;
  for (const auto& layer : plan) {
    for (const auto& path : layer.paths) {
      for (std::size_t i = 1; i < path.points.size(); ++i) {
        total += std::hypot(path.points[i].x - path.points[i - 1].x, path.points[i].y - path.points[i - 1].y);
      }
    }
  }
  return total;
}

}  // namespace

static int run_bench(int argc, char** argv) {
  using namespace geometry;
  const std::string model = argc > 1 ? argv[1] : MAHOST_DATA_DIR "/bunny.stl";
  const double layer = argc > 2 ? std::stod(argv[2]) : 0.2;
  const std::string contour = argc > 3 ? argv[3] : "ma";
  const std::string where = argc > 4 ? argv[4] : "everywhere";
  const int repeat = argc > 5 ? std::max(std::stoi(argv[5]), 1) : 1;
  const ContourStrategy* kind = find_contour_strategy(contour);
  const auto placement_kind = parse_support_placement(where);
  if (!kind || !placement_kind) {
    std::fprintf(stderr, "bench_supports: contour one of %s, support none|buildplate|everywhere\n",
                 contour_names().c_str());
    return 2;
  }
  const Mesh mesh = bench::load_model(model);
  const Box3 box = bounding_box(mesh);
  const LayerStack stack(mesh, uniform_layers(box.max.z - box.min.z, layer, 0.3));
  std::vector<Region> regions(stack.size());
  const Timed contours = timed(1, [&] {
    tbb::parallel_for(std::size_t{0}, stack.size(),
                      [&](std::size_t i) { regions[i] = layer_contour(stack, i, *kind); });
  });

  SupportOptions options;
  options.placement = *placement_kind;
  SupportPlan plan;
  CALLGRIND_START_INSTRUMENTATION;
  const Timed supports = timed(repeat, [&] { plan = plan_supports(regions, stack.layers(), options); });
  CALLGRIND_STOP_INSTRUMENTATION;
  std::vector<LayerToolpaths> with, without;
  const Timed paths_with = timed(repeat, [&] {
    with = plan_toolpaths(regions, stack.layers(), ToolpathOptions{}, plan);
  });
  const Timed paths_without = timed(repeat, [&] {
    without = plan_toolpaths(regions, stack.layers(), ToolpathOptions{});
  });

  std::size_t layers_with = 0, bridges = 0;
  double area_total = 0;
  for (const LayerSupport& l : plan.layers) {
    const double a = area(l.body) + area(l.interface);
    layers_with += a > 0;
    area_total += a;
    bridges += l.bridges.size();
  }
  std::printf("model %s, %zu layers of %.2f mm, %s contours (%.2f s wall, %.2f s CPU), support %s\n",
              model.c_str(), stack.size(), layer, contour.c_str(), contours.wall, contours.cpu,
              where.c_str());
  std::printf("plan_supports            %.3f s wall, %.3f s CPU\n", supports.wall, supports.cpu);
  std::printf("plan_toolpaths with it   %.3f s wall, %.3f s CPU\n", paths_with.wall, paths_with.cpu);
  std::printf("plan_toolpaths without   %.3f s wall, %.3f s CPU\n", paths_without.wall, paths_without.cpu);
  std::printf("support on %zu layers, %.0f mm^2 in all, volume %.0f mm^3, %zu bridges; paths %.1f m "
              "with, %.1f m without\n",
              layers_with, area_total, support_volume(plan, stack.layers()), bridges,
              path_length(with) / 1000, path_length(without) / 1000);
  return 0;
}

int main(int argc, char** argv) { return bench::main(argc, argv, run_bench); }
