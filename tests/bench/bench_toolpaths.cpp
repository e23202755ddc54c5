// Benchmark: plan_toolpaths over every layer of the 50 mm Stanford bunny (issue 4).
//
//   build*/tests/bench/bench_toolpaths [MODEL.stl] [layer mm] [lower|mid|optimal-height|ma]
//                                      [repeat]
//
// Reads and repairs the bunny (Y up, metres, scaled to 50 mm tall), cuts its layers
// (0.15 mm: 334 layers), takes each layer's region from the contour strategy (mid by
// default), then times plan_toolpaths alone with the default options (0.45 mm beads, 2 walls,
// 20% grid, 3 top and 3 bottom layers, one skirt loop). Prints the wall time of each stage, the paths
// and extrusion length produced, and the process's peak resident memory. The machine is
// shared: CPU time is the steadier figure; wall time shows the two threads at work.
// With `repeat` > 1 the plan is made that many times (figures per plan): under a profiler
// the planner then outweighs the contour stage it starts from. Under
//   valgrind --tool=callgrind --instr-atstart=no build*/tests/bench/bench_toolpaths ...
// only the plans are counted (all threads): the instruction count is the figure to compare
// on a busy machine, where even CPU time moves by 10%.
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
#include <fstream>
#include <string>

#include "geometry/contour/contour_strategy.h"
#include "geometry/slicing/layer_stack.h"
#include "geometry/mesh/placement.h"
#include "geometry/mesh/repair.h"
#include "geometry/mesh/stl_io.h"
#include "geometry/toolpaths/toolpath_plan.h"
#include "bench/bench_main.h"

namespace {

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

double resident_mib() {  // current resident set, from /proc
  std::ifstream statm("/proc/self/statm");
  long pages = 0, resident = 0;
  statm >> pages >> resident;
  return static_cast<double>(resident) * 4096 / (1024.0 * 1024.0);
}

double cpu_seconds() {  // user + system time of all threads so far
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<double>(usage.ru_utime.tv_sec + usage.ru_stime.tv_sec) +
         1e-6 * static_cast<double>(usage.ru_utime.tv_usec + usage.ru_stime.tv_usec);
}

double peak_mib() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<double>(usage.ru_maxrss) / 1024.0;
}

}  // namespace

static int run_bench(int argc, char** argv) {
  using namespace geometry;
  const std::string model = argc > 1 ? argv[1] : MAHOST_DATA_DIR "/bunny.stl";
  const double layer = argc > 2 ? std::stod(argv[2]) : 0.15;
  const std::string contour = argc > 3 ? argv[3] : "mid";
  const int repeat = argc > 4 ? std::max(std::stoi(argv[4]), 1) : 1;
  const ContourStrategy* kind = find_contour_strategy(contour);
  if (!kind) {
    std::fprintf(stderr, "bench_toolpaths: contour must be one of %s, not '%s'\n",
                 contour_names().c_str(), contour.c_str());
    return 2;
  }

  auto start = std::chrono::steady_clock::now();
  Placement placement;
  placement.units_to_mm = 1000;
  placement.up = Axis::y;
  placement.height = 50;
  const Mesh mesh = place(repair(read_stl(model)), placement);
  const double t_load = seconds_since(start);

  start = std::chrono::steady_clock::now();
  const LayerStack stack(mesh, uniform_layers(50, layer));
  std::vector<Region> regions(stack.size());
  tbb::parallel_for(std::size_t{0}, stack.size(),
                    [&](std::size_t i) { regions[i] = layer_contour(stack, i, *kind); });
  const double t_regions = seconds_since(start);
  const double rss_before = resident_mib();
  std::size_t region_points = 0;
  for (const Region& r : regions)
    for (const Loop& loop : r.loops) region_points += loop.size();

  start = std::chrono::steady_clock::now();
  const double cpu_start = cpu_seconds();
  std::vector<LayerToolpaths> plan;
  CALLGRIND_START_INSTRUMENTATION;
  for (int k = 0; k < repeat; ++k) plan = plan_toolpaths(regions, stack.layers(), ToolpathOptions{});
  CALLGRIND_STOP_INSTRUMENTATION;
  const double t_plan = seconds_since(start) / repeat;
  const double cpu_plan = (cpu_seconds() - cpu_start) / repeat;

  std::size_t paths = 0, points = 0, retractions = 0;
  double extruded = 0;
  for (const auto& l : plan) {
    for (const auto& p : l.paths) {
      ++paths;
      points += p.points.size();
      retractions += p.retract_before;
      for (std::size_t i = 0; i + 1 < p.points.size(); ++i) {
        extruded += std::hypot(p.points[i + 1].x - p.points[i].x, p.points[i + 1].y - p.points[i].y);
      }
    }
  }
  std::printf("model %s, %zu layers of %.2f mm, %s contours\n", model.c_str(), plan.size(), layer,
              contour.c_str());
  std::printf("load+repair+place %.3f s, regions %.3f s (%zu points)\n", t_load, t_regions,
              region_points);
  std::printf("plan_toolpaths    %.3f s wall, %.3f s CPU (%.2f ms CPU/layer)\n", t_plan,
              cpu_plan,
              1000 * cpu_plan / static_cast<double>(std::max<std::size_t>(plan.size(), 1)));
  std::printf("paths %zu, points %zu, retractions %zu, extruded path length %.1f m\n", paths,
              points, retractions, extruded / 1000);
  std::printf("resident before plan %.1f MiB, peak %.1f MiB\n", rss_before, peak_mib());
  return 0;
}

int main(int argc, char** argv) { return bench::main(argc, argv, run_bench); }
