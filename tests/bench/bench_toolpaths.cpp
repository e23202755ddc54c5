// Benchmark: plan_toolpaths over every layer of the 50 mm Stanford bunny.
//
//   build*/tests/bench/bench_toolpaths [MODEL.stl] [layer mm[,mm...]] [lower|mid|optimal-height|ma]
//                                      [repeat] [runs] [bunny|mm]
//
// Reads and repairs the model, places it (bunny, the default: Y up, metres, scaled to 50 mm
// tall; mm: as the file is, Z up), cuts its layers at each thickness given (default 0.2,0.15:
// 250 and 334 layers of the bunny), takes each layer's region from the contour strategy (mid
// by default), then times plan_toolpaths alone with the default options (0.45 mm beads, 2
// walls, 20% grid, 3 top and 3 bottom layers, one skirt loop). Prints, per thickness, the
// median and the least wall and CPU time of `runs` timings (default 5), the paths and
// extrusion length produced, and the process's peak resident memory. The machine is shared:
// CPU time is the steadier figure; wall time shows the threads at work; compare builds by
// running them alternately.
// With `repeat` > 1 each timing makes the plan that many times (figures per plan): under a
// profiler the planner then outweighs the contour stage it starts from. Under
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
#include <sstream>
#include <vector>
#include <string>

#include "geometry/contour/contour_strategy.h"
#include "geometry/slicing/layer_stack.h"
#include "geometry/mesh/placement.h"
#include "geometry/mesh/repair.h"
#include "geometry/mesh/stl_io.h"
#include "geometry/toolpaths/toolpath_plan.h"
#include "bench/bench_main.h"
#include "bench/bench_model.h"

namespace {

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
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

// The median of the values (the upper one of an even count's middle two).
double median(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  return values.empty() ? 0 : values[values.size() / 2];
}

std::vector<double> thicknesses(const std::string& list) {
  std::vector<double> result;
  std::stringstream in(list);
  for (std::string item; std::getline(in, item, ',');) result.push_back(std::stod(item));
  return result;
}

struct Timings {
  std::vector<double> wall, cpu;  // s per plan, one per run
};

// The plan made `runs` times `repeat` times over; the last plan is kept in `plan`.
Timings time_plans(const std::vector<geometry::Region>& regions,
                   const std::vector<geometry::Layer>& layers, int repeat, int runs,
                   std::vector<geometry::LayerToolpaths>& plan) {
  Timings t;
  for (int run = 0; run < runs; ++run) {
    const auto start = std::chrono::steady_clock::now();
    const double cpu_start = cpu_seconds();
    CALLGRIND_START_INSTRUMENTATION;
    for (int k = 0; k < repeat; ++k) {
      plan = geometry::plan_toolpaths(regions, layers, geometry::ToolpathOptions{});
    }
    CALLGRIND_STOP_INSTRUMENTATION;
    t.wall.push_back(seconds_since(start) / repeat);
    t.cpu.push_back((cpu_seconds() - cpu_start) / repeat);
  }
  return t;
}

void report(const std::vector<geometry::LayerToolpaths>& plan, const Timings& t) {
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
  const double cpu = median(t.cpu);
  std::printf("plan_toolpaths    %.3f s wall, %.3f s CPU median of %zu (least %.3f, %.3f); "
              "%.2f ms CPU/layer\n",
              median(t.wall), cpu, t.cpu.size(), *std::min_element(t.wall.begin(), t.wall.end()),
              *std::min_element(t.cpu.begin(), t.cpu.end()),
              1000 * cpu / static_cast<double>(std::max<std::size_t>(plan.size(), 1)));
  std::printf("paths %zu, points %zu, retractions %zu, extruded path length %.1f m\n", paths,
              points, retractions, extruded / 1000);
}

}  // namespace

static int run_bench(int argc, char** argv) {
  using namespace geometry;
  const std::string model = argc > 1 ? argv[1] : MAHOST_DATA_DIR "/bunny.stl";
  const std::vector<double> layer_list = thicknesses(argc > 2 ? argv[2] : "0.2,0.15");
  const std::string contour = argc > 3 ? argv[3] : "mid";
  const int repeat = argc > 4 ? std::max(std::stoi(argv[4]), 1) : 1;
  const int runs = argc > 5 ? std::max(std::stoi(argv[5]), 1) : 5;
  const std::string placing = argc > 6 ? argv[6] : "bunny";
  const ContourStrategy* kind = find_contour_strategy(contour);
  if (!kind) {
    std::fprintf(stderr, "bench_toolpaths: contour must be one of %s, not '%s'\n",
                 contour_names().c_str(), contour.c_str());
    return 2;
  }
  if (placing != "bunny" && placing != "mm") {
    std::fprintf(stderr, "bench_toolpaths: placement must be bunny or mm, not '%s'\n",
                 placing.c_str());
    return 2;
  }

  auto start = std::chrono::steady_clock::now();
  const Mesh mesh = place(repair(read_stl(model)), placing == "bunny" ? bench::bunny_placement() : Placement{});
  const double height = bounding_box(mesh).max.z - bounding_box(mesh).min.z;
  std::printf("model %s: load+repair+place %.3f s\n", model.c_str(), seconds_since(start));

  for (const double layer : layer_list) {
    start = std::chrono::steady_clock::now();
    const LayerStack stack(mesh, uniform_layers(height, layer));
    std::vector<Region> regions(stack.size());
    tbb::parallel_for(std::size_t{0}, stack.size(),
                      [&](std::size_t i) { regions[i] = layer_contour(stack, i, *kind); });
    std::size_t region_points = 0;
    for (const Region& r : regions)
      for (const Loop& loop : r.loops) region_points += loop.size();
    std::printf("\n%zu layers of %.2f mm, %s contours: regions %.3f s (%zu points)\n",
                stack.size(), layer, contour.c_str(), seconds_since(start), region_points);
    std::vector<LayerToolpaths> plan;
    const Timings t = time_plans(regions, stack.layers(), repeat, runs, plan);
    report(plan, t);
  }
  std::printf("peak resident %.1f MiB\n", peak_mib());
  return 0;
}

int main(int argc, char** argv) { return bench::main(argc, argv, run_bench); }
