// Benchmark: read + repair + place + slice the Stanford bunny as the paper prints it
// (--up y --units m --height 50, 0.15 mm layers: 334 planes at the layers' mid-heights).
// Prints wall time per phase and peak memory (VmHWM). Goal: all 334 planes in
// under 0.2 s, peak under 100 MiB.
//
// Usage: bench_slice [MODEL.stl] [--layer MM]   (default: data/bunny.stl, 0.15)
#include <sys/resource.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "geometry/core/error.h"
#include "geometry/slicing/layer_stack.h"
#include "geometry/mesh/placement.h"
#include "geometry/mesh/repair.h"
#include "geometry/slicing/slicer.h"
#include "geometry/mesh/stl_io.h"
#include "bench/bench_main.h"
#include "bench/bench_model.h"

namespace {

using Clock = std::chrono::steady_clock;

// CPU time of the whole process (all threads), s: on a machine shared with other work the
// wall time of a phase can be several times its CPU time.
double cpu_seconds() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<double>(usage.ru_utime.tv_sec + usage.ru_stime.tv_sec) +
         1e-6 * static_cast<double>(usage.ru_utime.tv_usec + usage.ru_stime.tv_usec);
}

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// Peak resident set size so far, MiB, from /proc/self/status.
double peak_mib() {
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line)) {
    if (line.rfind("VmHWM:", 0) == 0) return std::strtod(line.c_str() + 6, nullptr) / 1024.0;
  }
  return 0;
}

struct Timing {
  double best_wall = 0, median_wall = 0, best_cpu = 0;
};

template <typename F>
Timing repeat(int times, F&& run) {
  std::vector<double> wall, cpu;
  for (int i = 0; i < times; ++i) {
    const auto start = Clock::now();
    const double cpu_start = cpu_seconds();
    run();
    wall.push_back(seconds_since(start));
    cpu.push_back(cpu_seconds() - cpu_start);
  }
  std::sort(wall.begin(), wall.end());
  std::sort(cpu.begin(), cpu.end());
  return {wall.front(), wall[wall.size() / 2], cpu.front()};
}

}  // namespace

static int run_bench(int argc, char** argv) {
  std::string path = MAHOST_DATA_DIR "/bunny.stl";
  double layer = 0.15;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--layer" && i + 1 < argc) {
      layer = std::strtod(argv[++i], nullptr);
    } else {
      path = arg;
    }
  }

  try {
    fmt::print("bench_slice: {} at {} mm layers\n", path, layer);
    auto start = Clock::now();
    const std::vector<geometry::Triangle> facets = geometry::read_stl(path);
    fmt::print("  read      {:8.3f} s  {} facets\n", seconds_since(start), facets.size());

    start = Clock::now();
    geometry::RepairReport report;
    geometry::Mesh mesh = geometry::repair(facets, &report);
    fmt::print("  repair    {:8.3f} s  {} faces, {} holes filled, closed: {}\n",
               seconds_since(start), mesh.faces.size(), report.holes_filled,
               report.closed ? "yes" : "no");

    start = Clock::now();
    mesh = geometry::place(std::move(mesh), bench::bunny_placement());
    const geometry::Box3 box = geometry::bounding_box(mesh);
    fmt::print("  place     {:8.3f} s  height {:.3f} mm, volume {:.1f} mm^3\n",
               seconds_since(start), box.max.z - box.min.z, geometry::signed_volume(mesh));

    const std::vector<geometry::Layer> layers =
        geometry::uniform_layers(box.max.z - box.min.z, layer);
    std::vector<double> heights;
    for (const auto& l : layers) heights.push_back(l.z_mid());

    // slice_mesh: the one-sweep slicer, all planes, on all cores and on one.
    std::vector<geometry::Region> sections;
    const auto all_cores = repeat(5, [&] { sections = geometry::slice_mesh(mesh, heights); });
    Timing one_core;
    {
      tbb::global_control single(tbb::global_control::max_allowed_parallelism, 1);
      one_core = repeat(5, [&] { sections = geometry::slice_mesh(mesh, heights); });
    }
    std::size_t loops = 0, points = 0;
    double volume = 0;
    for (std::size_t i = 0; i < sections.size(); ++i) {
      loops += sections[i].loops.size();
      for (const auto& loop : sections[i].loops) points += loop.size();
      volume += geometry::area(sections[i]) * layers[i].thickness();
    }
    fmt::print("  slice     {:8.3f} s  {} planes, best of 5 (median {:.3f} s, CPU {:.3f} s); "
               "one thread {:.3f} s (CPU {:.3f} s)\n",
               all_cores.best_wall, heights.size(), all_cores.median_wall, all_cores.best_cpu,
               one_core.best_wall, one_core.best_cpu);
    fmt::print("            {} loops, {} points, sum of area x thickness {:.1f} mm^3\n", loops,
               points, volume);

    // LayerStack: the index, then cross_section at every mid-height, as the metrics call it.
    start = Clock::now();
    const geometry::LayerStack stack(mesh, layers);
    fmt::print("  index     {:8.3f} s  LayerStack over {} layers\n", seconds_since(start),
               stack.size());
    std::vector<geometry::Region> mids(stack.size());
    const auto sequential = repeat(5, [&] {
      for (std::size_t i = 0; i < stack.size(); ++i) mids[i] = stack.mid(i);
    });
    const auto parallel = repeat(5, [&] {
      tbb::parallel_for(std::size_t{0}, stack.size(),
                        [&](std::size_t i) { mids[i] = stack.mid(i); });
    });
    const double per_call_us = 1e6 * sequential.best_wall / static_cast<double>(stack.size());
    fmt::print("  sections  {:8.3f} s  {} cross_section calls in sequence ({:.0f} us each, CPU "
               "{:.3f} s), {:.3f} s in parallel\n",
               sequential.best_wall, stack.size(), per_call_us, sequential.best_cpu,
               parallel.best_wall);
    std::size_t differ = 0;
    for (std::size_t i = 0; i < mids.size(); ++i) {
      if (mids[i].loops != sections[i].loops) ++differ;
    }
    fmt::print("            sections differing from slice_mesh: {}\n", differ);
    fmt::print("  peak      {:8.1f} MiB (VmHWM)\n", peak_mib());
    return differ == 0 ? 0 : 1;
  } catch (const geometry::InputError& e) {
    std::fprintf(stderr, "bench_slice: %s\n", e.what());
    return 2;
  }
}

int main(int argc, char** argv) { return bench::main(argc, argv, run_bench); }
