// Benchmark: the slab footprint's islands (slab.h's slab_islands, what layer_reference builds)
// over every layer of the Stanford bunny.
//
// Usage: bench_footprint [STL] [--layer T] [--first F] [--repeat N] [--dump FILE]
// Default: data/bunny.stl placed as in the paper (Y up, metres, 50 mm tall), 0.15 mm layers
// over a 0.3 mm first layer, as `mahost slice --layer 0.15` lays them.
// Prints the CPU time of the slabs and of their footprints' islands, one thread, N times over
// (default 1), and the loops' count.
// --dump: every layer's islands to FILE (text, full precision), to compare two builds with
// cmp: a change meant to leave the footprint alone leaves the file byte for byte.
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <fstream>
#include <string>
#include <vector>

#include "geometry/slab/slab.h"
#include "geometry/slicing/layer_stack.h"
#include "bench/bench_main.h"
#include "bench/bench_model.h"

using namespace geometry;

static double cpu_seconds() {
  timespec t;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return t.tv_sec + 1e-9 * t.tv_nsec;
}

static void write_loop(std::ofstream& out, const Loop& loop) {
  for (Vec2 p : loop) out << ' ' << p.x << ' ' << p.y;
  out << '\n';
}

static int run_bench(int argc, char** argv) {
  std::string path = std::string(MAHOST_DATA_DIR) + "/bunny.stl";
  double thickness = 0.15, first = 0.3;
  int repeat = 1;
  std::string dump;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--layer" && i + 1 < argc) {
      thickness = std::atof(argv[++i]);
    } else if (arg == "--first" && i + 1 < argc) {
      first = std::atof(argv[++i]);
    } else if (arg == "--repeat" && i + 1 < argc) {
      repeat = std::max(1, std::atoi(argv[++i]));
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

  double start = cpu_seconds();
  std::vector<Slab> slabs(stack.size());
  for (std::size_t i = 0; i < stack.size(); ++i) slabs[i] = slab_of(stack, i);
  const double slab_cpu = cpu_seconds() - start;
  std::vector<std::vector<BoundaryPair>> islands(stack.size());
  start = cpu_seconds();
  for (int r = 0; r < repeat; ++r) {
    for (std::size_t i = 0; i < stack.size(); ++i) islands[i] = slab_islands(slabs[i]);
  }
  const double footprint_cpu = (cpu_seconds() - start) / repeat;
  std::size_t loops = 0, count = 0;
  for (const std::vector<BoundaryPair>& layer : islands) {
    count += layer.size();
    for (const BoundaryPair& pair : layer) loops += 1 + pair.inner.size();
  }
  std::printf("one thread, CPU: slabs %.3f s, footprints' islands %.3f s (%.2f ms a layer); "
              "%zu loops, %zu islands\n",
              slab_cpu, footprint_cpu, 1e3 * footprint_cpu / stack.size(), loops, count);
  if (!dump.empty()) {
    std::ofstream out(dump);
    out.precision(17);
    for (std::size_t i = 0; i < stack.size(); ++i) {
      for (const BoundaryPair& pair : islands[i]) {
        out << i << " island\n";
        write_loop(out, pair.outer);
        for (const Loop& hole : pair.inner) write_loop(out, hole);
      }
    }
  }
  return 0;
}

int main(int argc, char** argv) { return bench::main(argc, argv, run_bench); }
