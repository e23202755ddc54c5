// Reading a model as 3MF against the same model as binary STL (geometry::read_model, the file
// read and parsed to triangles; no repair). The 3MF is the one PrusaSlicer writes for the STL
// (`prusa-slicer --export-3mf`), so it is a real producer's file: zip-compressed XML, shared
// vertices. Models: the bunny (data/bunny.stl) and a UV sphere of about N triangles made here.
// Runs alternate STL and 3MF; the medians are printed with their ratio.
//
// Usage: build/tests/bench/bench_model_load [--triangles N] [--runs R]
//        (default N = 1000000, R = 7; needs prusa-slicer, which scripts/setup installs)
#include <algorithm>
#include <chrono>
#include <ctime>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include <fmt/core.h>

#include "bench_main.h"
#include "geometry/mesh/model_io.h"
#include "geometry/mesh/stl_io.h"

namespace {

using Clock = std::chrono::steady_clock;

// A UV sphere of radius 40 mm with `rings` x 2*`rings` quads, each two triangles.
std::vector<geometry::Triangle> sphere(int rings) {
  const int segments = 2 * rings;
  auto at = [&](int i, int j) {
    const double theta = M_PI * i / rings, phi = 2 * M_PI * j / segments;
    return geometry::Vec3{40 * std::sin(theta) * std::cos(phi), 40 * std::sin(theta) * std::sin(phi),
                          40 * std::cos(theta)};
  };
  std::vector<geometry::Triangle> out;
  for (int i = 0; i < rings; ++i) {
    for (int j = 0; j < segments; ++j) {
      const auto a = at(i, j), b = at(i + 1, j), c = at(i + 1, j + 1), d = at(i, j + 1);
      if (i > 0) out.push_back({{a, b, d}});
      if (i + 1 < rings) out.push_back({{b, c, d}});
    }
  }
  return out;
}

// The CPU seconds of this process (the readers run on one thread): on a shared machine the
// wall clock also counts the others' work.
double cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return t.tv_sec + t.tv_nsec * 1e-9;
}

struct Timing {
  double wall = 0, cpu = 0;
};

Timing time_of(const std::string& path, std::size_t& triangles) {
  const auto start = Clock::now();
  const double cpu = cpu_seconds();
  const geometry::ModelFile file = geometry::read_model(path);
  triangles = file.triangles.size();
  return {std::chrono::duration<double>(Clock::now() - start).count(), cpu_seconds() - cpu};
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

void compare(const std::string& name, const std::string& stl, const std::string& dir, int runs) {
  const std::string threemf = dir + "/" + name + ".3mf";
  const std::string command = fmt::format("prusa-slicer --export-3mf -o '{}' '{}' >/dev/null 2>&1", threemf, stl);
  if (std::system(command.c_str()) != 0 || !std::filesystem::exists(threemf)) {
    throw std::runtime_error("prusa-slicer --export-3mf failed (is prusa-slicer installed?)");
  }
  std::vector<double> stl_wall, stl_cpu, threemf_wall, threemf_cpu;
  std::size_t stl_triangles = 0, threemf_triangles = 0;
  for (int r = 0; r < runs; ++r) {
    const Timing a = time_of(stl, stl_triangles);
    const Timing b = time_of(threemf, threemf_triangles);
    stl_wall.push_back(a.wall);
    stl_cpu.push_back(a.cpu);
    threemf_wall.push_back(b.wall);
    threemf_cpu.push_back(b.cpu);
  }
  const double a = median(stl_cpu), b = median(threemf_cpu);
  fmt::print("{:<7} STL {:>7} triangles {:5.1f} MB: cpu {:6.3f} s (wall {:6.3f}) | 3MF {:>7} triangles {:5.1f} MB: "
             "cpu {:6.3f} s (wall {:6.3f}) | 3MF/STL cpu {:.2f}\n",
             name, stl_triangles, std::filesystem::file_size(stl) / 1e6, a, median(stl_wall), threemf_triangles,
             std::filesystem::file_size(threemf) / 1e6, b, median(threemf_wall), b / a);
}

int run_bench(int argc, char** argv) {
  long triangles = 1000000;
  int runs = 7;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string flag = argv[i];
    if (flag == "--triangles") triangles = std::stol(argv[i + 1]);
    else if (flag == "--runs") runs = std::stoi(argv[i + 1]);
    else throw std::runtime_error("unknown option " + flag);
  }
  const std::string dir = (std::filesystem::temp_directory_path() / "bench_model_load").string();
  std::filesystem::create_directories(dir);
  compare("bunny", MAHOST_DATA_DIR "/bunny.stl", dir, runs);
  const int rings = std::max(3, static_cast<int>(std::sqrt(triangles / 4.0)));
  geometry::write_stl_binary(dir + "/sphere.stl", sphere(rings));
  compare("sphere", dir + "/sphere.stl", dir, runs);
  std::filesystem::remove_all(dir);
  return 0;
}

}  // namespace

int main(int argc, char** argv) { return bench::main(argc, argv, run_bench); }
