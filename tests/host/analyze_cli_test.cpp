// `mahost analyze` and `mahost advise` as a user runs them, on an n-gon cone whose errors are
// known in closed form (tests/geometry/metrics/distance_error_test.cpp): radius r = 10, height h = 15,
// n = 64. Over a layer of thickness t below the apex,
//   lower: D = t r cos(pi/n) / h,   mid: D = t r / (2h).
#include <doctest/doctest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "geometry/mesh/stl_io.h"
#include "support/run_command.h"
#include "support/solids.h"

namespace analyze_cli_test {

using test_support::run_mahost;

namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kR = 10, kH = 15;
constexpr int kN = 64;

std::string cone_stl(const std::string& dir) {
  const std::string path = dir + "/cone.stl";
  geometry::write_stl_binary(path, solids::cone(kR, kH, kN).mesh);
  return path;
}

std::string read_file(const std::string& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// CSV rows as maps from column name to text.
std::vector<std::map<std::string, std::string>> read_csv(const std::string& path) {
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);
  std::vector<std::string> names;
  for (std::stringstream header(line); std::getline(header, line, ',');) names.push_back(line);
  std::vector<std::map<std::string, std::string>> rows;
  while (std::getline(in, line)) {
    std::map<std::string, std::string> row;
    std::stringstream fields(line);
    for (const std::string& name : names) std::getline(fields, row[name], ',');
    rows.push_back(row);
  }
  return rows;
}

int count_lines(const std::string& text) {
  int lines = 0;
  for (char c : text) lines += c == '\n';
  return lines;
}

}  // namespace

TEST_CASE("analyze_cone_reports_closed_form_distances") {
  const std::string dir = test_support::scratch_dir("analyze_cone");
  const std::string stl = cone_stl(dir);
  const auto result = run_mahost({"analyze", stl, "--layer", "0.25", "--from-zero", "--contours",
                                  "lower,mid,ma", "--csv", dir + "/layers.csv", "--json",
                                  dir + "/summary.json"});
  CAPTURE(result.err);
  REQUIRE(result.exit_code == 0);
  for (const char* row : {"\nlower ", "\nmid ", "\nma ", "ma vs lower:", "ma vs mid:"})
    CHECK(result.out.find(row) != std::string::npos);

  const auto rows = read_csv(dir + "/layers.csv");
  REQUIRE(rows.size() == 60 * 3);  // 15 mm / 0.25 mm layers, three strategies
  const double t = 0.25;
  for (const auto& row : rows) {
    const int layer = std::stoi(row.at("layer"));
    if (layer >= 59) continue;  // the apex layer has its own figures
    const double d = std::stod(row.at("distance"));
    CAPTURE(layer);
    if (row.at("strategy") == "lower") CHECK(std::abs(d - t * kR * std::cos(kPi / kN) / kH) <= 2e-3);
    if (row.at("strategy") == "mid") CHECK(std::abs(d - t * kR / (2 * kH)) <= 2e-3);
    if (row.at("strategy") == "ma") CHECK(std::abs(d - t * kR / (2 * kH)) <= 4e-3);
    // Both exact up to Clipper's 1 pm grid: 1e-9 mm x perimeter (63 mm) x t.
    CHECK(std::stod(row.at("volume_limit")) <= std::stod(row.at("volume_deviation")) + 1e-7);
  }

  const auto summary = nlohmann::json::parse(read_file(dir + "/summary.json"));
  CHECK(summary["layers"] == 60);
  REQUIRE(summary["strategies"].size() == 3);
  for (const auto& s : summary["strategies"])
    CHECK(s["total_volume_deviation"].get<double>() >= summary["volume_limit"].get<double>() - 1e-9);
  // lower's D is twice mid's: ma, equal to mid, halves lower's mean D.
  bool found = false;
  for (const auto& c : summary["comparisons"]) {
    if (c["strategy"] == "ma" && c["baseline"] == "lower") {
      found = true;
      CHECK(c["mean_distance_change_percent"].get<double>() == doctest::Approx(-50).epsilon(0.03));
    }
  }
  CHECK(found);
}

TEST_CASE("analyze_draws_charts_and_a_layer") {
  const std::string dir = test_support::scratch_dir("analyze_plots");
  const std::string stl = cone_stl(dir);
  const auto result = run_mahost({"analyze", stl, "--layer", "0.5", "--contours", "lower,mid,ma",
                                  "--plots", dir + "/plots", "--thick", "1.0", "--layer-index", "7"});
  CAPTURE(result.err);
  REQUIRE(result.exit_code == 0);
  for (const char* name : {"distance.svg", "volume.svg", "distance-lower-vs-ma.svg",
                           "distance-mid-vs-ma.svg", "distance-lower-0.5-vs-ma-1.svg", "layer-7.svg"}) {
    CAPTURE(name);
    const std::string svg = read_file(dir + "/plots/" + name);
    CHECK(svg.find("<svg") != std::string::npos);
    CHECK(svg.find("<path") != std::string::npos);
  }
  // The layer drawing names every strategy in its legend.
  const std::string layer = read_file(dir + "/plots/layer-7.svg");
  for (const char* title : {"boundary pair", "lower", "mid", "ma"}) CHECK(layer.find(title) != std::string::npos);
  CHECK(result.out.find("ma at 1 mm: 15 layers") != std::string::npos);
}

TEST_CASE("analyze_exports_the_layered_part") {
  const std::string dir = test_support::scratch_dir("analyze_export");
  const std::string stl = cone_stl(dir);
  const auto result = run_mahost({"analyze", stl, "--layer", "0.5", "--contours", "mid",
                                  "--csv", dir + "/layers.csv", "--export-layers",
                                  dir + "/layers.stl", "--contour", "mid"});
  CAPTURE(result.err);
  REQUIRE(result.exit_code == 0);
  double expected = 0;
  for (const auto& row : read_csv(dir + "/layers.csv"))
    expected += std::stod(row.at("area")) * std::stod(row.at("thickness"));
  const auto triangles = geometry::read_stl(dir + "/layers.stl");
  double volume = 0;
  for (const auto& tri : triangles)
    volume += geometry::dot(tri.v[0], geometry::cross(tri.v[1], tri.v[2])) / 6;
  // float32 coordinates in the file: 1e-6 relative.
  CHECK(volume == doctest::Approx(expected).epsilon(1e-5));
  CHECK(triangles.size() > 30u * 64u);
}

TEST_CASE("analyze_refuses_bad_input_with_one_line") {
  const std::string dir = test_support::scratch_dir("analyze_bad");
  const std::string stl = cone_stl(dir);
  struct Case {
    std::vector<std::string> args;
    std::string names;
  };
  const std::vector<Case> cases{
      {{"analyze", stl, "--contours", "lower,median"}, "--contours"},
      {{"analyze", dir + "/missing.stl"}, "missing.stl"},
      {{"analyze", stl, "--layer", "0.5", "--from-zero", "--layer-index", "30"}, "--layer-index"},
      {{"analyze", stl, "--from-zero", "--boundaries", "1,2"}, "--from-zero"},
      {{"analyze", stl, "--csv", dir + "/no/such/dir/x.csv"}, "x.csv"},
      {{"analyze", stl, "--layer", "-1"}, "--layer"},
      {{"analyze", stl, "--export-layers", dir + "/x.stl", "--contour", "median"}, "--contour"},
      {{"advise", stl, "--printer", "no-such-printer"}, "no-such-printer"},
      {{"advise", stl, "--thicknesses", "0.2,abc"}, "--thicknesses"},
  };
  for (const Case& c : cases) {
    CAPTURE(c.args.back());
    const auto result = run_mahost(c.args);
    CHECK(result.exit_code == 2);
    CHECK(count_lines(result.err) == 1);
    CHECK(result.err.find(c.names) != std::string::npos);
    CHECK(result.err.find("internal") == std::string::npos);
  }
}

TEST_CASE("advise_picks_the_thickest_layer_within_the_benchmark") {
  // mid at t has D = t r / (2h); lower at 0.15 has 0.15 r cos(pi/n) / h: within up to
  // t = 0.3 cos(pi/64) = 0.2996 (plus the 1 um distance tolerance), so 0.3 passes, 0.35 fails.
  const std::string dir = test_support::scratch_dir("advise_cone");
  const std::string stl = cone_stl(dir);
  const auto result = run_mahost({"advise", stl, "--contour", "mid", "--thicknesses",
                                  "0.15,0.2,0.25,0.3,0.35", "--json", dir + "/advice.json"});
  CAPTURE(result.err);
  REQUIRE(result.exit_code == 0);
  const auto advice = nlohmann::json::parse(read_file(dir + "/advice.json"));
  CHECK(advice["advised_thickness"].get<double>() == doctest::Approx(0.3));
  REQUIRE(advice["thicknesses"].size() == 5);
  for (const auto& row : advice["thicknesses"]) {
    const double t = row["thickness"].get<double>();
    CAPTURE(t);
    CHECK(row["layers"].get<int>() == static_cast<int>(std::ceil(15 / t - 1e-9)));
    if (t <= 0.3) CHECK(row["within_benchmark_percent"].get<double>() >= 95);
    else CHECK(row["within_benchmark_percent"].get<double>() < 50);
  }
  CHECK(result.out.find("advice: mid at 0.3 mm") != std::string::npos);
}

TEST_CASE("advise_reads_the_printers_thicknesses") {
  const std::string dir = test_support::scratch_dir("advise_printer");
  const std::string stl = cone_stl(dir);
  const auto result = run_mahost({"advise", stl, "--printer", "up-plus-2", "--contour", "ma"});
  CAPTURE(result.err);
  REQUIRE(result.exit_code == 0);
  // The UP Plus 2: 0.15 to 0.4 mm in 0.05 mm steps.
  for (const char* row : {"0.15mm", "0.2mm", "0.25mm", "0.3mm", "0.35mm", "0.4mm"})
    CHECK(result.out.find(row) != std::string::npos);
  CHECK(result.out.find("advice: ma at") != std::string::npos);
}

TEST_CASE("analyze_compares_with_a_zero_baseline_by_absolute_difference") {
  // A cube: every strategy is the section exactly, every D is zero but for rounding (1e-16 mm),
  // and a percentage of that is noise ("-100.0%", "+5691854825303922.0%"): the comparisons give
  // the absolute difference, and no change prints as -0.0.
  const std::string dir = test_support::scratch_dir("analyze_zero_baseline");
  const std::string stl = dir + "/cube.stl";
  geometry::write_stl_binary(stl, solids::cube(10).mesh);
  const auto result = run_mahost({"analyze", stl, "--layer", "0.5", "--from-zero", "--contours",
                                  "lower,mid,ma", "--json", dir + "/summary.json"});
  CAPTURE(result.out);
  REQUIRE(result.exit_code == 0);
  for (const char* line : {"ma vs lower: mean D 0.0000 mm, max D 0.0000 mm, total ΔV 0.000 mm³",
                           "ma vs mid: mean D 0.0000 mm, max D 0.0000 mm, total ΔV 0.000 mm³"}) {
    CHECK(result.out.find(line) != std::string::npos);
  }
  CHECK(result.out.find("-0.0") == std::string::npos);
  CHECK(result.out.find("100.0%") == std::string::npos);
  const auto summary = nlohmann::json::parse(read_file(dir + "/summary.json"));
  for (const auto& c : summary["comparisons"]) {
    CHECK(c["mean_distance_change_percent"].is_null());
    CHECK(std::abs(c["mean_distance_change"].get<double>()) <= 1e-9);
  }
}

TEST_CASE("analyze_judges_the_layers_slice_prints_unless_from_zero") {
  // A 7.9 mm box on the UP Plus 2 at 0.2 mm: slice prints a 0.3 mm first layer and lands the
  // top at 7.9 (0.3 + 38 x 0.2); from zero, 40 layers of 0.2 end at 8.0, past the top.
  const std::string dir = test_support::scratch_dir("analyze_slice_layers");
  const std::string stl = dir + "/box.stl", gcode = dir + "/box.gcode";
  geometry::write_stl_binary(stl, solids::box({0, 0, 0}, {20, 20, 7.9}).mesh);
  const auto sliced = run_mahost({"slice", stl, "--layer", "0.2", "--no-raft", "--support", "none", "-o", gcode});
  REQUIRE(sliced.exit_code == 0);
  const auto same = run_mahost({"analyze", stl, "--layer", "0.2", "--contours", "mid", "--csv", dir + "/slice.csv"});
  REQUIRE(same.exit_code == 0);
  const auto rows = read_csv(dir + "/slice.csv");
  REQUIRE(rows.size() == 39);
  CHECK(std::stod(rows.front().at("thickness")) == doctest::Approx(0.3));
  CHECK(std::stod(rows.back().at("z_lo")) + std::stod(rows.back().at("thickness")) == doctest::Approx(7.9));
  for (const auto& row : rows) CHECK(std::stod(row.at("distance")) <= 1e-6);  // the top on a boundary
  const auto grid = run_mahost({"analyze", stl, "--layer", "0.2", "--from-zero", "--contours", "mid",
                                "--csv", dir + "/zero.csv"});
  REQUIRE(grid.exit_code == 0);
  const auto zero = read_csv(dir + "/zero.csv");
  REQUIRE(zero.size() == 40);
  CHECK(std::stod(zero.front().at("thickness")) == doctest::Approx(0.2));
}

}  // namespace analyze_cli_test
