// Benchmark: `mahost slice` of the bunny (50 mm, --up y --units m) stage by stage, in process:
// read + repair + place, contours (ma by default), toolpaths, G-code writing (both runs of the
// writer: the clock and the text), with wall time, CPU time and peak RSS after each stage.
// Then the whole command as a user runs it, under /usr/bin/time, for its wall time and peak
// memory. Prints its figures; never run by ctest.
//
// Usage: bench_slice_gcode [LAYER=0.15] [CONTOUR=ma|mid|lower]
// For the side-by-side with CuraEngine and PrusaSlicer see tests/bench/compare_slicers.sh.
#include <sys/resource.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/core.h>
#include <tbb/parallel_for.h>

#include "geometry/slicing/layer_stack.h"
#include "geometry/contour/ma_contour.h"
#include "geometry/mesh/placement.h"
#include "geometry/mesh/repair.h"
#include "geometry/mesh/stl_io.h"
#include "geometry/toolpaths/toolpath_plan.h"
#include "printer/gcode_writer.h"
#include "printer/profile.h"
#include "bench/bench_main.h"
#include "bench/bench_model.h"

namespace {

using Clock = std::chrono::steady_clock;

double cpu_seconds() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_utime.tv_sec + usage.ru_utime.tv_usec * 1e-6 + usage.ru_stime.tv_sec +
         usage.ru_stime.tv_usec * 1e-6;
}

double peak_mib() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_maxrss / 1024.0;
}

struct Stage {
  Clock::time_point wall = Clock::now();
  double cpu = cpu_seconds();
  void report(const char* name) {
    const double wall_s = std::chrono::duration<double>(Clock::now() - wall).count();
    fmt::print("  {:<22} {:7.3f} s wall {:7.3f} s cpu   peak RSS so far {:6.1f} MiB\n", name,
               wall_s, cpu_seconds() - cpu, peak_mib());
    wall = Clock::now();
    cpu = cpu_seconds();
  }
};

}  // namespace

static int run_bench(int argc, char** argv) {
  const double thickness = argc > 1 ? std::atof(argv[1]) : 0.15;
  const std::string contour = argc > 2 ? argv[2] : "ma";
  const std::string bunny = MAHOST_DATA_DIR "/bunny.stl";
  fmt::print("bunny 50 mm, layer {} mm, contour {}, UP Plus 2 profile\n", thickness, contour);

  printer::ProfileRequest request;
  request.config_dir = MAHOST_DATA_DIR "/../configs";
  const printer::Profiles profiles = printer::load_profiles(request);

  Stage stage;
  geometry::RepairReport report;
  const geometry::Mesh mesh = bench::load_model(bunny, &report);
  stage.report("read, repair, place");

  const auto layers = geometry::uniform_layers(50, thickness, profiles.printer.first_layer_height);
  const geometry::LayerStack stack(mesh, layers);
  std::vector<geometry::Region> regions(layers.size());
  tbb::parallel_for(std::size_t{0}, layers.size(), [&](std::size_t i) {
    regions[i] = contour == "lower" ? stack.lower(i)
                 : contour == "mid" ? stack.mid(i)
                                    : geometry::ma_contour(stack, i);
  });
  stage.report("contours");

  geometry::ToolpathOptions options;
  options.extrusion_width = profiles.printer.extrusion_width;
  options.first_layer_width = profiles.printer.first_layer_width;
  const auto toolpaths = geometry::plan_toolpaths(regions, layers, options);
  std::size_t points = 0;
  for (const auto& layer : toolpaths) {
    for (const auto& path : layer.paths) points += path.points.size();
  }
  stage.report("toolpaths");

  std::ostringstream out;
  printer::GcodeOptions gcode_options;
  gcode_options.layer_height = thickness;
  const printer::GcodeSummary summary = printer::write_gcode(out, toolpaths, profiles, gcode_options);
  const double write_wall = std::chrono::duration<double>(Clock::now() - stage.wall).count();
  stage.report("G-code (clock + text)");
  fmt::print("  {} layers, {} toolpath points -> {} lines, {:.1f} MiB, {:.0f} lines/s written\n",
             summary.layers, points, summary.lines, summary.bytes / 1048576.0,
             summary.lines / write_wall);
  fmt::print("  estimate {} ({:.1f} s), filament {:.1f} mm, {:.2f} g\n",
             printer::format_duration(summary.print_seconds), summary.print_seconds,
             summary.filament_mm, summary.filament_grams);

  // The whole command, as a user runs it.
  const std::string output = "/tmp/bench_slice_gcode.gcode";
  const std::string command = fmt::format(
      "/usr/bin/time -f '  mahost slice (whole command): %e s wall, %U s user, peak RSS %M KiB' "
      "{} slice {} --up y --units m --height 50 --layer {} --contour {} -o {} >/dev/null",
      MAHOST_BINARY, bunny, thickness, contour, output);
  std::fflush(stdout);
  const int status = std::system(command.c_str());
  std::remove(output.c_str());
  return status == 0 ? 0 : 1;
}

int main(int argc, char** argv) { return bench::main(argc, argv, run_bench); }
