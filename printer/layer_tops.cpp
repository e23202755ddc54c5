// The layer tops of a G-code file; see layer_tops.h.
#include "printer/layer_tops.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstddef>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <system_error>
#include <vector>

#include <fmt/core.h>

#include "base/text.h"
#include "printer/error.h"
#include "printer/gcode_interpreter.h"
#include "printer/gcode_line.h"

namespace printer {

namespace {

// Heights are written to 1 um (ours, PrusaSlicer's, Slic3r's; Cura's fewer digits): closer
// than half of that they are the same layer.
constexpr double kSameHeight = 0.5e-3;

// mahost's header note on a raft, "; raft: 4 layers, 1.10 mm under the part (...)": how far
// the part stands lifted, mm; 0 for any other line.
double raft_lift(std::string_view line) {
  constexpr std::string_view kNote = "; raft: ";
  constexpr std::string_view kUnder = " mm under the part";
  if (!line.starts_with(kNote)) return 0;
  const std::size_t under = line.find(kUnder);
  const std::size_t comma = line.rfind(", ", under);
  if (under == std::string_view::npos || comma == std::string_view::npos) return 0;
  double lift = 0;
  const char* first = line.data() + comma + 2;
  const auto [end, error] = std::from_chars(first, line.data() + under, lift);
  return error == std::errc{} && end == line.data() + under && lift > 0 ? lift : 0;
}

}  // namespace

bool looks_like_gcode(std::string_view text) {
  while (!text.empty()) {
    const std::size_t end = text.find('\n');
    const std::string_view line = base::trim(text.substr(0, end));
    if (!line.empty()) {
      const char c = line.front();
      if (c == ';') return true;
      if ((c == 'G' || c == 'g' || c == 'M' || c == 'm') && line.size() > 1 &&
          line[1] >= '0' && line[1] <= '9') {
        return true;
      }
    }
    if (end == std::string_view::npos) break;
    text.remove_prefix(end + 1);
  }
  return false;
}

std::vector<double> layer_tops_from_gcode(std::string_view text, const std::string& name) {
  std::vector<double> tops;
  GcodeState state;
  double lift = 0;  // a mahost raft's, mm
  std::size_t line_number = 0;
  while (!text.empty()) {
    const std::size_t end = text.find('\n');
    const std::string_view line = base::trim(text.substr(0, end));
    text.remove_prefix(end == std::string_view::npos ? text.size() : end + 1);
    ++line_number;
    // Only G and M commands matter, and mahost's note of a raft; other comments, blank lines
    // and T, S... are skipped unparsed.
    if (!line.empty() && line.front() == ';') {
      if (const double l = raft_lift(line); l > 0) lift = l;
      continue;
    }
    if (line.empty() || (line.front() != 'G' && line.front() != 'M' && line.front() != 'g' &&
                         line.front() != 'm')) {
      continue;
    }
    const GcodeStep step = interpret(state, parse_gcode_line(line));
    const auto moves = step.moves();
    const auto laying = std::find_if(moves.begin(), moves.end(), lays_filament);
    if (laying == moves.end()) continue;
    const double z = laying->to.z;
    if (!tops.empty() && std::abs(z - tops.back()) <= kSameHeight) continue;
    if (!tops.empty() && z < tops.back()) {
      throw ConfigError(fmt::format(
          "{}: line {} extrudes at Z {:g} mm, below the layer at {:g} mm printed before it; "
          "the file is not one part printed layer by layer (several objects one after "
          "another?), so it gives no layer boundaries",
          name, line_number, z, tops.back()));
    }
    if (!(z > kSameHeight)) {
      throw ConfigError(fmt::format("{}: line {} extrudes at Z {:g} mm, on or below the bed; "
                                    "give a file that prints on the bed at Z 0",
                                    name, line_number, z));
    }
    tops.push_back(z);
  }
  if (tops.empty()) {
    throw ConfigError(fmt::format("{}: the G-code extrudes nothing, so it gives no layer "
                                  "boundaries",
                                  name));
  }
  // On a raft the part's layers are those above it, their tops as the part had them on the
  // bed (the raft's layers and its air gap are no layers of the part).
  if (lift > 0) {
    std::erase_if(tops, [&](double top) { return top <= lift + kSameHeight; });
    for (double& top : tops) top -= lift;
    if (tops.empty()) {
      throw ConfigError(fmt::format("{}: the G-code extrudes nothing above its raft, so it gives "
                                    "no layer boundaries",
                                    name));
    }
  }
  // A spiral vase rises along its moves: thousands of "layers" a few um apart.
  for (std::size_t i = 1; i < tops.size(); ++i) {
    if (tops[i] - tops[i - 1] < 0.01 - kSameHeight) {
      throw ConfigError(fmt::format(
          "{}: it extrudes at Z {:g} and then {:g} mm, {:.3f} mm apart, thinner than any "
          "printer's layer (a spiral vase rises along its moves); give a file printed in layers",
          name, tops[i - 1], tops[i], tops[i] - tops[i - 1]));
    }
  }
  return tops;
}

std::vector<double> layer_tops_from_list(std::string_view text, const std::string& name) {
  std::vector<double> tops;
  std::size_t line_number = 0;
  while (!text.empty()) {
    const std::size_t end = text.find('\n');
    std::string_view line = text.substr(0, end);
    text.remove_prefix(end == std::string_view::npos ? text.size() : end + 1);
    ++line_number;
    if (const std::size_t hash = line.find('#'); hash != std::string_view::npos) {
      line = line.substr(0, hash);
    }
    while (!line.empty()) {
      const std::size_t comma = line.find(',');
      std::string_view item = line.substr(0, comma);
      line.remove_prefix(comma == std::string_view::npos ? line.size() : comma + 1);
      item = base::trim(item);
      if (item.empty()) continue;
      double value = 0;
      const auto [ptr, error] = std::from_chars(item.data(), item.data() + item.size(), value);
      const std::string where = line_number > 1 || !text.empty()
                                    ? fmt::format("{} line {}", name, line_number)
                                    : name;
      if (error != std::errc() || ptr != item.data() + item.size() || !std::isfinite(value) ||
          !(value > 0)) {
        throw ConfigError(fmt::format("{}: '{}' is not a layer top in mm (give positive "
                                      "numbers, e.g. 0.3,0.5,0.7)",
                                      where, item));
      }
      if (!tops.empty() && !(value > tops.back())) {
        throw ConfigError(fmt::format("{}: layer top {:g} mm is not above the one before it "
                                      "({:g} mm); give the tops rising",
                                      where, value, tops.back()));
      }
      tops.push_back(value);
    }
  }
  if (tops.empty()) {
    throw ConfigError(fmt::format("{}: no layer tops in it; give numbers in mm, e.g. 0.3,0.5,0.7",
                                  name));
  }
  return tops;
}

std::vector<double> read_layer_tops(const std::string& argument) {
  std::error_code error;
  if (!std::filesystem::is_regular_file(argument, error)) {
    // Not a file: a list, unless it looks like a path that is missing.
    const bool list = !argument.empty() &&
                      argument.find_first_not_of("0123456789.,+-eE \t") == std::string::npos;
    if (!list) {
      throw ConfigError(fmt::format(
          "--boundaries {}: no such file, and not a list of layer tops; give a file (G-code, "
          "or one top per line) or tops in mm, e.g. --boundaries 0.3,0.5,0.7",
          argument));
    }
    return layer_tops_from_list(argument, "--boundaries");
  }
  std::ifstream in(argument, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  if (!in) {
    throw ConfigError(fmt::format("--boundaries {}: cannot read this file", argument));
  }
  const std::string content = text.str();
  const std::string name = fmt::format("--boundaries {}", argument);
  return looks_like_gcode(content) ? layer_tops_from_gcode(content, name)
                                   : layer_tops_from_list(content, name);
}

}  // namespace printer
