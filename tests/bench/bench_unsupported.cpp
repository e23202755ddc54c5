// The unsupported-extrusion check (sim/unsupported_extrusion.h) on any G-code file, mahost's
// or a peer's, with its time, and the filament per feature by the ;TYPE: comments (mahost's
// and Cura's words, PrusaSlicer's ";TYPE:Support material" and the like): to compare the
// support filament slicers spend at 0 mm unsupported (compare_supports.sh).
//
// Usage: bench_unsupported FILE.gcode... [--bridge MM] [--gap MM] [--filament MM] [--layers]
//   --bridge   longest bridge (default 10), --gap the contact gap (default 0.2),
//   --filament diameter (default 1.75), --layers: the layers with unsupported extrusion and
//   the first stretches (--stretches N of them, default 20).
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/core.h>

#include "printer/gcode_line.h"
#include "sim/gcode_deposition.h"
#include "sim/unsupported_extrusion.h"
#include "bench/bench_main.h"

namespace {

// The support class of a ;TYPE: word, across slicers.
std::string feature_class(std::string type) {
  for (char& c : type) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  if (type.find("INTERFACE") != std::string::npos) return "support interface";
  if (type.find("SUPPORT") != std::string::npos) return "support";
  if (type.find("RAFT") != std::string::npos) return "raft";
  if (type.find("SKIRT") != std::string::npos || type.find("BRIM") != std::string::npos) return "skirt/brim";
  if (type.find("BRIDGE") != std::string::npos) return "bridge";
  return "part";
}

// Filament per feature class, read with E's modes.
std::map<std::string, double> filament_by_feature(const std::string& program) {
  std::map<std::string, double> by;
  std::istringstream in(program);
  std::string line, feature = "part";
  double e = 0;
  bool relative_e = false;
  while (std::getline(in, line)) {
    const printer::GcodeCommand c = printer::parse_gcode_line(line);
    if (c.empty()) {
      if (c.comment.rfind("TYPE:", 0) == 0) feature = feature_class(c.comment.substr(5));
      continue;
    }
    if (c.letter == 'G' && (c.code == 0 || c.code == 1)) {
      if (auto v = c.get('E')) {
        const double next = relative_e ? e + *v : *v;
        if (next > e && (c.has('X') || c.has('Y'))) by[feature] += next - e;
        e = next;
      }
    } else if (c.letter == 'G' && c.code == 92) {
      if (auto v = c.get('E')) e = *v;
    } else if (c.letter == 'G' && (c.code == 90 || c.code == 91)) {
      relative_e = c.code == 91;
    } else if (c.letter == 'M' && (c.code == 82 || c.code == 83)) {
      relative_e = c.code == 83;
    }
  }
  return by;
}

}  // namespace

static int run_bench(int argc, char** argv) {
  sim::SupportCheckOptions options;
  options.bridge_length = 10;
  options.contact_gap = 0.2;
  bool per_layer = false;
  std::size_t kept = 20;
  std::vector<std::string> files;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    auto value = [&]() { return i + 1 < argc ? std::atof(argv[++i]) : 0.0; };
    if (arg == "--bridge") options.bridge_length = value();
    else if (arg == "--gap") options.contact_gap = value();
    else if (arg == "--filament") options.filament_diameter = value();
    else if (arg == "--layers") per_layer = true;
    else if (arg == "--stretches") kept = static_cast<std::size_t>(value());
    else files.push_back(arg);
  }
  options.stretches_kept = kept;
  if (files.empty()) {
    std::fprintf(stderr, "usage: bench_unsupported FILE.gcode... [--bridge MM] [--gap MM] "
                         "[--filament MM] [--layers]\n");
    return 2;
  }
  for (const std::string& file : files) {
    std::ifstream in(file, std::ios::binary);
    if (!in) {
      std::fprintf(stderr, "bench_unsupported: cannot read %s\n", file.c_str());
      return 2;
    }
    std::stringstream text;
    text << in.rdbuf();
    const std::string program = text.str();
    const auto start = std::chrono::steady_clock::now();
    const sim::DepositionRecord record = sim::deposition_from_gcode(program);
    const sim::SupportCheck check = sim::check_unsupported_extrusion(record, options);
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    fmt::print("{}: {} ({} Z levels, checked in {:.2f} s)\n", file,
               sim::unsupported_summary(check, options), record.layer_z.size(), seconds);
    const auto by = filament_by_feature(program);
    double total = 0;
    for (const auto& [feature, mm] : by) total += mm;
    std::string line = fmt::format("  filament {:.1f} mm:", total);
    for (const auto& [feature, mm] : by) line += fmt::format(" {} {:.1f}", feature, mm);
    fmt::print("{}\n", line);
    if (per_layer) {
      for (std::size_t k = 0; k < check.unsupported_per_layer.size(); ++k) {
        if (check.unsupported_per_layer[k] > 0) {
          fmt::print("  layer {:4} z {:7.3f}: {:8.2f} mm\n", k, record.layer_z[k],
                     check.unsupported_per_layer[k]);
        }
      }
      for (const sim::UnsupportedStretch& s : check.stretches) {
        fmt::print("  stretch layer {} z {:.3f} ({:.3f}, {:.3f}) -> ({:.3f}, {:.3f}) {:.3f} mm{}{}\n",
                   s.layer, s.z, s.from.x, s.from.y, s.to.x, s.to.y, s.length,
                   s.anchored ? " anchored" : "", s.between ? " between" : "");
      }
    }
  }
  return 0;
}

int main(int argc, char** argv) { return bench::main(argc, argv, run_bench); }
