// `--boundaries` as a user gives it: explicit layer tops (a list, a file, another slicer's
// G-code) on slice, analyze and advise; a variable stack all the way to the G-code, the
// metrics and the exported part; thicknesses the printer lacks refused in one line.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <doctest/doctest.h>
#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include "geometry/mesh/stl_io.h"
#include "support/gcode_beads.h"
#include "support/run_command.h"
#include "support/solids.h"

namespace boundaries_cli_test {

using test_support::run_mahost;

namespace {

std::string read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

int count_lines(const std::string& text) {
  int lines = 0;
  for (char c : text) lines += c == '\n';
  return lines;
}

// A cone of radius 10, 6 mm tall (its flank at 59 degrees), as an STL in `dir`.
std::string cone_stl(const std::string& dir) {
  const std::string path = dir + "/cone.stl";
  geometry::write_stl_binary(path, solids::cone(10, 6, 64).mesh);
  return path;
}

// 0.3 mm first, then 0.15, 0.4, 0.25, 0.2, 0.35 repeated, up to 6 mm: all UP Plus 2 layers.
std::vector<double> mixed_tops() {
  std::vector<double> tops{0.3};
  const double steps[] = {0.15, 0.4, 0.25, 0.2, 0.35};
  for (int k = 0; tops.back() < 6 - 1e-9; ++k) tops.push_back(std::min(6.0, tops.back() + steps[k % 5]));
  return tops;
}

std::string joined(const std::vector<double>& tops) {
  std::string text;
  for (double z : tops) {
    if (!text.empty()) text += ',';
    text += fmt::format("{:g}", std::round(z * 1e6) / 1e6);
  }
  return text;
}

}  // namespace

TEST_CASE("slice_prints_explicit_boundaries_layer_by_layer") {
  const std::string dir = test_support::scratch_dir("boundaries_slice");
  const std::string stl = cone_stl(dir);
  std::vector<double> tops = mixed_tops();
  // The last step would be 0.2 mm, ending at 6.0: the part's top.
  REQUIRE(std::abs(tops.back() - 6) < 1e-9);
  const std::string out = dir + "/cone.gcode";
  const auto r = run_mahost({"slice", stl, "--no-raft", "--boundaries", joined(tops), "-o", out});
  CAPTURE(r.err);
  REQUIRE(r.exit_code == 0);
  CHECK(r.out.starts_with(fmt::format("{}: {} layers, 0.15 to 0.4 mm thick, estimated print time ",
                                      out, tops.size())));
  const std::string text = read_file(out);
  // ;Z: and ;HEIGHT: per layer, the tops and thicknesses given.
  std::vector<double> zs, heights;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) {
    if (line.starts_with(";Z:")) zs.push_back(std::stod(line.substr(3)));
    if (line.starts_with(";HEIGHT:")) heights.push_back(std::stod(line.substr(8)));
  }
  REQUIRE(zs.size() == tops.size());
  REQUIRE(heights.size() == tops.size());
  for (std::size_t i = 0; i < tops.size(); ++i) {
    CHECK(zs[i] == doctest::Approx(tops[i]));
    CHECK(heights[i] == doctest::Approx(tops[i] - (i ? tops[i - 1] : 0)));
  }
  // Read back as the printer lays it: each layer's beads at its own height, as wide as
  // planned (0.5 mm on the first layer, 0.45 mm after; thin walls and gap fill narrower).
  const test_support::PrintedProgram program = test_support::read_printed_program(text);
  CHECK(program.problems.empty());
  REQUIRE(program.layers.size() == tops.size());
  for (std::size_t i = 0; i < tops.size(); ++i) {
    CAPTURE(i);
    CHECK(program.layers[i].height == doctest::Approx(heights[i]).epsilon(1e-3));
    std::map<long, double> length_by_width;  // 0.01 mm classes
    for (const auto& chain : program.layers[i].chains)
      for (const auto& bead : chain) length_by_width[std::lround(bead.width * 100)] += bead.length();
    // Near the apex (radius under 2 mm) thin walls and gap fill take over.
    if (length_by_width.empty() || tops[i] > 4.8) continue;
    const auto most = std::max_element(length_by_width.begin(), length_by_width.end(),
                                       [](auto& a, auto& b) { return a.second < b.second; });
    CHECK(most->first == (i == 0 ? 50 : 45));
  }
  CHECK(program.header.at("LAYER_COUNT") == std::to_string(tops.size()));

  // The same tops from a file with comments, and read back from this G-code: the same plan.
  std::ofstream(dir + "/plan.txt") << "# the plan\n" << joined(tops) << "\n";
  for (const std::string& source : {dir + "/plan.txt", out}) {
    CAPTURE(source);
    const auto again = run_mahost({"slice", stl, "--boundaries", source, "-o", dir + "/again.gcode"});
    CAPTURE(again.err);
    CHECK(again.exit_code == 0);
    CHECK(again.out.find(fmt::format(": {} layers, 0.15 to 0.4 mm thick,", tops.size())) != std::string::npos);
  }
}

TEST_CASE("slice_refuses_boundaries_the_printer_cannot_print") {
  const std::string dir = test_support::scratch_dir("boundaries_refused");
  const std::string stl = cone_stl(dir);
  struct Case {
    std::vector<std::string> args;
    std::string message;
  };
  const std::vector<Case> cases{
      // 0.1 mm is below the UP Plus 2's 0.15 mm.
      {{"--boundaries", "0.3,0.4,6"},
       "layer 2 (z 0.3 to 0.4 mm) is 0.1 mm thick, which the UP Plus 2"},
      // The first layer must be the printer's 0.3 mm.
      {{"--boundaries", "0.2,6"}, "layer 1 (z 0 to 0.2 mm) is 0.2 mm thick"},
      // Ending far below the part's top.
      {{"--boundaries", "0.3,0.5,0.7"}, "the layers end at 0.7 mm but the part is 6.000 mm tall"},
      {{"--boundaries", "0.3,0.2"}, "layer top 0.2 mm is not above the one before it"},
      {{"--boundaries", dir + "/nothing.gcode"}, "no such file"},
      {{"--boundaries", "0.3,0.5", "--layer", "0.2"}, "excludes"},
  };
  for (const Case& c : cases) {
    std::vector<std::string> args{"slice", stl, "-o", dir + "/x.gcode"};
    args.insert(args.end(), c.args.begin(), c.args.end());
    const auto r = run_mahost(args);
    CAPTURE(r.err);
    CHECK(r.exit_code == 2);
    CHECK(count_lines(r.err) == 1);
    CHECK(r.err.find(c.message) != std::string::npos);
    CHECK_FALSE(std::filesystem::exists(dir + "/x.gcode"));
  }
}

TEST_CASE("analyze_judges_any_boundaries_and_exports_a_watertight_part") {
  // Thicknesses the UP Plus 2 lacks (0.1 mm) are judged: analyze checks no printer.
  const std::string dir = test_support::scratch_dir("boundaries_analyze");
  const std::string stl = cone_stl(dir);
  std::vector<double> tops;
  for (double z = 0.1; z < 6 + 1e-9; z += z < 3 ? 0.1 : 0.4) tops.push_back(std::min(z, 6.0));
  const auto r = run_mahost({"analyze", stl, "--boundaries", joined(tops), "--contours", "mid,ma",
                             "--csv", dir + "/layers.csv", "--json", dir + "/summary.json",
                             "--exclude-z", "0:1", "--export-layers", dir + "/layers.stl",
                             "--contour", "ma"});
  CAPTURE(r.err);
  REQUIRE(r.exit_code == 0);
  CHECK(r.out.find(fmt::format("{} layers, 0.1 to 0.4 mm thick", tops.size())) != std::string::npos);
  CHECK(r.out.find("P95h D") != std::string::npos);
  // One CSV row per layer and strategy, with its own z_lo and thickness.
  std::ifstream csv(dir + "/layers.csv");
  std::string line;
  std::getline(csv, line);
  CHECK(line.starts_with("layer,strategy,z_lo,thickness,"));
  std::size_t rows = 0;
  while (std::getline(csv, line)) {
    std::stringstream fields(line);
    std::string layer, strategy, z_lo, thickness;
    std::getline(fields, layer, ',');
    std::getline(fields, strategy, ',');
    std::getline(fields, z_lo, ',');
    std::getline(fields, thickness, ',');
    const std::size_t i = std::stoul(layer);
    REQUIRE(i < tops.size());
    CHECK(std::stod(z_lo) == doctest::Approx(i ? tops[i - 1] : 0.0));
    CHECK(std::stod(thickness) == doctest::Approx(tops[i] - (i ? tops[i - 1] : 0.0)));
    ++rows;
  }
  CHECK(rows == 2 * tops.size());
  // The percentile by height: mid's D on a cone flank is t r / (2 h) = t * 10/12, so 95% of
  // the judged height (z 1 to 6: 3 mm of 0.4 mm layers of 5) stays within the 0.4 mm layers'
  // D, 0.333 mm (the apex layer aside, which is tiny).
  const auto summary = nlohmann::json::parse(read_file(dir + "/summary.json"));
  CHECK(summary["boundaries"] == joined(tops));
  CHECK(summary["layers"] == tops.size());
  CHECK(summary["layer_thickness"].is_null());
  CHECK(summary["layer_thickness_min"].get<double>() == doctest::Approx(0.1));
  CHECK(summary["layer_thickness_max"].get<double>() == doctest::Approx(0.4));
  CHECK(summary["percentile_excluded_z"] == nlohmann::json::array({0.0, 1.0}));
  const auto& mid = summary["strategies"][0];
  CHECK(mid["strategy"] == "mid");
  CHECK(mid["p95_distance_by_height"].get<double>() == doctest::Approx(0.4 * 10 / 12).epsilon(0.02));
  // The exported part: `mahost info` takes it as it is.
  const auto info = run_mahost({"info", dir + "/layers.stl"});
  CAPTURE(info.out);
  CHECK(info.exit_code == 0);
  CHECK(info.out.find("repairs       none") != std::string::npos);
  CHECK(info.out.find("watertight    yes") != std::string::npos);
  CHECK(info.out.find("open edges    0 before repair, 0 after") != std::string::npos);
}

TEST_CASE("advise_judges_a_plan_beside_the_uniform_thicknesses") {
  const std::string dir = test_support::scratch_dir("boundaries_advise");
  const std::string stl = cone_stl(dir);
  const auto r = run_mahost({"advise", stl, "--thicknesses", "0.15,0.3", "--contour", "mid",
                             "--boundaries", "0.15,0.3,0.6,0.9,1.2,1.5,1.8,2.1,2.4,2.7,3,3.3,3.6,"
                                             "3.9,4.2,4.5,4.8,5.1,5.4,5.7,6",
                             "--json", dir + "/advise.json"});
  CAPTURE(r.err);
  REQUIRE(r.exit_code == 0);
  // The plan is uniform 0.3 mm after a 0.15 mm first layer: nearly the 0.3 mm row.
  CHECK(r.out.find("     plan      21 ") != std::string::npos);
  const auto j = nlohmann::json::parse(read_file(dir + "/advise.json"));
  CHECK(j["plan"]["layers"] == 21);
  CHECK(j["plan"]["mean_distance"].get<double>() ==
        doctest::Approx(j["thicknesses"][1]["mean_distance"].get<double>()).epsilon(0.1));
}

}  // namespace boundaries_cli_test
