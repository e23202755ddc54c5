// Benchmark: the adaptive layer plan (geometry/plan/layer_plan.h) of a model at several
// tolerances: layers, how many candidate slabs were measured of how many, the rounds of the
// lazy search, wall and CPU time, the plan's D (mean, max, by-height 95th percentile) and its
// total swept volume (swept_volume.h). With --exhaustive, also the plan found by measuring
// every candidate first, to see that the lazy search loses nothing.
//
// Usage: bench_plan [STL] [--tolerances 0.1,0.2,0.3] [--contours mid|ma|mid,ma,...]
//                   [--max-layers N] [--exhaustive] [--layers] [--range MIN,MAX,STEP,FIRST]
// Default: data/bunny.stl placed as in the paper (Y up, metres, 50 mm tall), the UP Plus 2's
// thicknesses (0.15-0.4 mm in 0.05 steps, first layer 0.3 mm), contours mid. --range gives
// another printer's (generic-marlin: 0.05,0.3,0.01,0.2).
#include <sys/resource.h>
#include <time.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <string>
#include <vector>

#include "geometry/mesh/placement.h"
#include "geometry/mesh/repair.h"
#include "geometry/mesh/stl_io.h"
#include "geometry/plan/layer_plan.h"
#include "bench/bench_main.h"

using namespace geometry;
using Clock = std::chrono::steady_clock;

namespace {

double cpu_seconds() {
  timespec now{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &now);
  return static_cast<double>(now.tv_sec) + 1e-9 * static_cast<double>(now.tv_nsec);
}

std::vector<std::string> split(const std::string& text) {
  std::vector<std::string> parts;
  std::stringstream list(text);
  for (std::string part; std::getline(list, part, ',');) parts.push_back(part);
  return parts;
}

// The D within which layers covering `share` of the judged height stay (layers weighted by
// thickness), leaving out layers below z_from.
double by_height_percentile(const AdaptivePlan& plan, double share, double z_from) {
  std::vector<std::pair<double, double>> d;  // (D, thickness)
  double total = 0;
  for (std::size_t i = 0; i < plan.layers.size(); ++i) {
    if (plan.layers[i].z_lo < z_from) continue;
    d.push_back({plan.distance[i], plan.layers[i].thickness()});
    total += plan.layers[i].thickness();
  }
  std::sort(d.begin(), d.end());
  double covered = 0;
  for (const auto& [distance, t] : d) {
    covered += t;
    if (covered >= share * total - 1e-12) return distance;
  }
  return d.empty() ? 0 : d.back().first;
}

void report(const char* label, const AdaptivePlan& plan, double wall, double cpu, double z_from,
            bool layers) {
  double sum = 0, worst = 0, thinnest = 1e9, thickest = 0, swept = 0;
  for (std::size_t i = 0; i < plan.layers.size(); ++i) {
    sum += plan.distance[i];
    swept += plan.swept[i];
    worst = std::max(worst, plan.distance[i]);
    thinnest = std::min(thinnest, plan.layers[i].thickness());
    thickest = std::max(thickest, plan.layers[i].thickness());
  }
  const double n = static_cast<double>(std::max<std::size_t>(plan.layers.size(), 1));
  std::printf("%-12s tol %6.3f  layers %4zu (%.2f-%.2f mm)  unmet %3zu  mean D %.4f  max D %.4f  "
              "p95h D %.4f  swept %.2f mm3  measured %5zu of %5zu in %3zu rounds  %.2f s wall "
              "%.2f s cpu\n",
              label, plan.tolerance, plan.layers.size(), thinnest, thickest, plan.unmet, sum / n,
              worst, by_height_percentile(plan, 0.95, z_from), swept, plan.measured,
              plan.candidates, plan.rounds, wall, cpu);
  if (layers) {
    for (std::size_t i = 0; i < plan.layers.size(); ++i) {
      std::printf("  %4zu %8.3f %6.3f D %.4f%s\n", i, plan.layers[i].z_lo,
                  plan.layers[i].thickness(), plan.distance[i], plan.met[i] ? "" : " unmet");
    }
  }
}

}  // namespace

static int run_bench(int argc, char** argv) {
  std::string path = std::string(MAHOST_DATA_DIR) + "/bunny.stl";
  std::vector<std::string> tolerances{"0.1", "0.2", "0.3", "0.5"};
  std::vector<std::string> contours{"mid"};
  std::size_t max_layers = 0;
  bool exhaustive = false, layers = false;
  AllowedThicknesses allowed{.listed = {}, .min = 0.15, .max = 0.4, .step = 0.05, .first = 0.3};
  double z_from = -1;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--tolerances" && i + 1 < argc) tolerances = split(argv[++i]);
    else if (arg == "--contours" && i + 1 < argc) contours = split(argv[++i]);
    else if (arg == "--max-layers" && i + 1 < argc) max_layers = std::strtoul(argv[++i], nullptr, 10);
    else if (arg == "--exhaustive") exhaustive = true;
    else if (arg == "--layers") layers = true;
    else if (arg == "--from" && i + 1 < argc) z_from = std::atof(argv[++i]);
    else if (arg == "--range" && i + 1 < argc) {
      const std::vector<std::string> range = split(argv[++i]);
      if (range.size() != 4) {
        std::fprintf(stderr, "bench_plan: --range takes MIN,MAX,STEP,FIRST in mm\n");
        return 2;
      }
      allowed = {.listed = {}, .min = std::atof(range[0].c_str()), .max = std::atof(range[1].c_str()),
                 .step = std::atof(range[2].c_str()), .first = std::atof(range[3].c_str())};
    }
    else path = arg;
  }
  AdaptiveOptions options;
  options.contours.clear();
  for (const std::string& name : contours) {
    const ContourStrategy* strategy = find_contour_strategy(name);
    if (!strategy) {
      std::fprintf(stderr, "bench_plan: unknown contour '%s'\n", name.c_str());
      return 2;
    }
    options.contours.push_back(strategy);
  }
  Placement placement;
  if (path.find("bunny") != std::string::npos) {
    placement.units_to_mm = 1000;
    placement.up = Axis::y;
    placement.height = 50;
    if (z_from < 0) z_from = 2.25;  // the hole-filled base
  }
  const Mesh mesh = place(repair(read_stl(path)), placement);
  const double top = bounding_box(mesh).max.z;
  const LayerStack stack(mesh, {});
  const std::vector<FlatLevel> flats = flat_levels(mesh);
  std::printf("model %s: %zu faces, %.2f mm tall, %zu flat levels; contours %s\n", path.c_str(),
              mesh.faces.size(), top, flats.size(), contours.size() == 1 ? contours[0].c_str() : "several");
  for (const std::string& text : max_layers > 0 ? std::vector<std::string>{"0"} : tolerances) {
    options.tolerance = std::atof(text.c_str());
    options.max_layers = max_layers;
    for (int pass = 0; pass < (exhaustive ? 2 : 1); ++pass) {
      options.measure_all = pass == 1;
      const auto start = Clock::now();
      const double cpu = cpu_seconds();
      const AdaptivePlan plan = adaptive_plan(stack, top, allowed, flats, options);
      report(pass == 0 ? "lazy" : "exhaustive", plan,
             std::chrono::duration<double>(Clock::now() - start).count(), cpu_seconds() - cpu,
             std::max(z_from, 0.0), layers);
    }
  }
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  std::printf("peak resident memory: %.1f MB\n", static_cast<double>(usage.ru_maxrss) / 1024.0);
  return 0;
}

int main(int argc, char** argv) { return bench::main(argc, argv, run_bench); }
