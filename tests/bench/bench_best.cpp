// Benchmark: the best contour (best_contour.h) over every layer of the Stanford bunny.
//
// Usage: bench_best [STL] [--layer T] [--first F] [--quick] [--layers] [--dump FILE]
// Default: data/bunny.stl placed as in the paper (Y up, metres, 50 mm tall), 0.15 mm layers
// over a 0.3 mm first layer, as `mahost slice --layer 0.15` lays them.
// Prints the CPU time of best's contours, one thread, and of ma's alone for comparison, how
// often each candidate was chosen, and (unless --quick) the TBB-parallel wall time.
// --layers: one line per layer (chosen candidate, its D, the candidates' D), the D's to 17
// digits; a candidate refuted early (more than a tie above the least D) shows ">=" a lower
// bound of its D, which depends on the order best measures in. A change meant to leave best's
// choice alone leaves every line's chosen candidate and its D byte for byte.
// --dump: every layer's chosen region to FILE (text, full precision), to compare two builds
// with cmp: a change meant to leave best's choice alone leaves the file byte for byte.
#include <tbb/parallel_for.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <fstream>
#include <map>
#include <string>
#include <vector>

#include "geometry/contour/best_contour.h"
#include "geometry/contour/contour_strategy.h"
#include "geometry/contour/ma_contour.h"
#include "geometry/slicing/layer_stack.h"
#include "bench/bench_main.h"
#include "bench/bench_model.h"

using namespace geometry;

static double cpu_seconds() {
  timespec t;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return t.tv_sec + 1e-9 * t.tv_nsec;
}

static int run_bench(int argc, char** argv) {
  std::string path = std::string(MAHOST_DATA_DIR) + "/bunny.stl";
  double thickness = 0.15, first = 0.3;
  bool quick = false, layers = false;
  std::string dump;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--layer" && i + 1 < argc) {
      thickness = std::atof(argv[++i]);
    } else if (arg == "--first" && i + 1 < argc) {
      first = std::atof(argv[++i]);
    } else if (arg == "--quick") {
      quick = true;
    } else if (arg == "--layers") {
      layers = true;
    } else if (arg == "--dump" && i + 1 < argc) {
      dump = argv[++i];
    } else {
      path = arg;
    }
  }
  const Mesh mesh = bench::load_model(path);
  const Box3 box = bounding_box(mesh);
  const LayerStack stack(mesh, uniform_layers(box.max.z - box.min.z, thickness, first));
  std::printf("model %s: %zu faces, %.2f mm tall, %zu layers of %.3f mm\n", path.c_str(),
              mesh.faces.size(), box.max.z - box.min.z, stack.size(), thickness);

  const ContourOptions options;
  std::vector<BestChoice> choices(stack.size());
  double start = cpu_seconds();
  for (std::size_t i = 0; i < stack.size(); ++i) choices[i] = best_choice({stack, i, options});
  const double best_cpu = cpu_seconds() - start;
  start = cpu_seconds();
  for (std::size_t i = 0; i < stack.size(); ++i) ma_strategy({stack, i, options});
  const double ma_cpu = cpu_seconds() - start;
  std::printf("one thread, CPU: best %.3f s (%.2f ms a layer), ma alone %.3f s: best / ma %.2f\n",
              best_cpu, 1e3 * best_cpu / stack.size(), ma_cpu, best_cpu / ma_cpu);

  std::map<std::string, int> chosen;
  for (const BestChoice& c : choices) ++chosen[std::string(c.chosen)];
  std::printf("chosen:");
  for (const auto& [name, count] : chosen) std::printf(" %s %d", name.c_str(), count);
  std::printf("\n");
  if (layers) {
    for (std::size_t i = 0; i < stack.size(); ++i) {
      const BestChoice& c = choices[i];
      // A candidate refuted early: ">=" its lower bound.
      std::string figure[3];
      for (int k = 0; k < 3; ++k) {
        char text[40];
        std::snprintf(text, sizeof text, "%s%.17g", c.refuted[k] ? ">=" : "", c.candidate_distance[k]);
        figure[k] = text;
      }
      std::printf("%zu %.3f %s D %.17g missed %zu  mid %s opt %s ma %s\n", i,
                  stack.layers()[i].z_lo, std::string(c.chosen).c_str(), c.distance,
                  c.missed_features, figure[0].c_str(), figure[1].c_str(), figure[2].c_str());
    }
  }
  if (!dump.empty()) {
    std::ofstream out(dump);
    out.precision(17);
    for (std::size_t i = 0; i < stack.size(); ++i) {
      out << i << ' ' << choices[i].chosen << '\n';
      for (const Loop& loop : choices[i].result.region.loops) {
        for (Vec2 p : loop) out << ' ' << p.x << ' ' << p.y;
        out << '\n';
      }
    }
  }
  if (!quick) {
    const auto wall_start = std::chrono::steady_clock::now();
    tbb::parallel_for(std::size_t{0}, stack.size(),
                      [&](std::size_t i) { best_strategy({stack, i, options}); });
    std::printf("parallel (TBB): best %.3f s wall\n",
                std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count());
  }
  return 0;
}

int main(int argc, char** argv) { return bench::main(argc, argv, run_bench); }
