// The layer plan as a user meets it: a flat top lands on a layer boundary in uniform slicing
// (an 8.00 mm part prints 8.00 mm tall), `--adaptive` plans by the exact error and says so in
// one line, every thickness in the G-code is one the printer allows, a budget is kept, and
// contradictory options are refused in one line.
#include <algorithm>
#include <cmath>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include <doctest/doctest.h>

#include "geometry/mesh/stl_io.h"
#include "printer/layer_tops.h"
#include "support/run_command.h"
#include "support/solids.h"

namespace adaptive_cli_test {

using test_support::run_mahost;

namespace {

std::string read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

std::vector<double> tops_of(const std::string& gcode) {
  return printer::layer_tops_from_gcode(read_file(gcode), gcode);
}

bool up_plus_2_allows(double t) {
  const double steps = (t - 0.15) / 0.05;
  return t >= 0.15 - 1e-6 && t <= 0.4 + 1e-6 && std::abs(steps - std::round(steps)) < 1e-4;
}

}  // namespace

TEST_CASE("uniform_slicing_prints_an_8_mm_part_8_mm_tall") {
  const std::string dir = test_support::scratch_dir("plan_flat_top");
  const std::string stl = dir + "/box8.stl", gcode = dir + "/box8.gcode";
  geometry::write_stl_binary(stl, solids::box({0, 0, 0}, {20, 20, 8}).mesh);
  const auto r = run_mahost({"slice", stl, "--no-raft", "--layer", "0.15", "--contour", "mid", "-o", gcode});
  REQUIRE(r.exit_code == 0);
  const std::vector<double> tops = tops_of(gcode);
  REQUIRE(!tops.empty());
  CHECK(tops.back() == doctest::Approx(8.0).epsilon(1e-6));  // not 7.95 (mid) or 8.10
  CHECK(tops.front() == doctest::Approx(0.3));
  for (std::size_t i = 1; i < tops.size(); ++i) CHECK(up_plus_2_allows(tops[i] - tops[i - 1]));
  CHECK(tops.size() == 52);  // 0.3 + 51 x 0.15 + one 0.2
}

TEST_CASE("slice_adaptive_plans_by_the_error_and_reports_it_in_one_line") {
  const std::string dir = test_support::scratch_dir("plan_adaptive_slice");
  const std::string stl = dir + "/cone.stl", gcode = dir + "/cone.gcode";
  // 10 mm radius, 20 mm tall: mid's D is t / 4, so a tolerance of 0.07 allows 0.25 mm layers.
  geometry::write_stl_binary(stl, solids::cone(10, 20, 64).mesh);
  const auto r = run_mahost(
      {"slice", stl, "--no-raft", "--adaptive", "--tolerance", "0.07", "--contour", "mid", "-o", gcode});
  REQUIRE(r.exit_code == 0);
  CHECK(r.out.find("adaptive: ") != std::string::npos);
  CHECK(r.out.find("for D within 0.07 mm") != std::string::npos);
  CHECK(r.out.find("at uniform 0.15 mm") != std::string::npos);
  const std::vector<double> tops = tops_of(gcode);
  REQUIRE(tops.size() > 2);
  for (std::size_t i = 1; i < tops.size(); ++i) {
    const double t = tops[i] - tops[i - 1];
    CAPTURE(tops[i]);
    CHECK(up_plus_2_allows(t));
    if (tops[i] < 19) CHECK(t <= 0.25 + 1e-6);
  }
  // About 19.7 / 0.25 layers after the first: far fewer than 0.15 mm layers (132).
  CHECK(tops.size() <= 1 + 80 + 2);
  CHECK(read_file(gcode).find("; layers: ") != std::string::npos);
}

TEST_CASE("slice_adaptive_with_supports_keeps_layers_thin_where_thick_ones_would_need_support") {
  const std::string dir = test_support::scratch_dir("plan_adaptive_overhang");
  const std::string stl = dir + "/frustum.stl";
  // Widening upwards at 40 degrees from vertical, which the material holds (50): a layer
  // t thick steps out t tan 40, past half a 0.45 mm bead above t = 0.268 mm. A tolerance of
  // 1 mm allows any thickness (mid's D is t tan 40 / 2).
  const double lean = std::tan(40 * 3.141592653589793 / 180);
  geometry::write_stl_binary(stl, solids::frustum(5, 5 + 10 * lean / std::cos(3.141592653589793 / 64), 10, 64).mesh);
  const auto thickest = [](const std::vector<double>& tops) {
    double t = 0;
    for (std::size_t i = 1; i < tops.size(); ++i) t = std::max(t, tops[i] - tops[i - 1]);
    return t;
  };
  const std::string held = dir + "/held.gcode", free = dir + "/free.gcode";
  auto r = run_mahost({"slice", stl, "--no-raft", "--support", "buildplate", "--adaptive",
                       "--tolerance", "1", "-o", held});
  REQUIRE(r.exit_code == 0);
  CHECK(r.out.find("refused as too thick for the slopes under them") != std::string::npos);
  CHECK(thickest(tops_of(held)) <= 0.25 + 1e-6);
  // So nothing needs support: every layer stands within half a bead of the one below.
  CHECK(read_file(held).find(";TYPE:SUPPORT") == std::string::npos);
  r = run_mahost({"slice", stl, "--no-raft", "--support", "none", "--adaptive", "--tolerance", "1",
                  "-o", free});
  REQUIRE(r.exit_code == 0);
  CHECK(r.out.find("refused as too thick") == std::string::npos);
  CHECK(thickest(tops_of(free)) == doctest::Approx(0.4));
}

TEST_CASE("slice_adaptive_keeps_a_layer_budget") {
  const std::string dir = test_support::scratch_dir("plan_adaptive_budget");
  const std::string stl = dir + "/cone.stl", gcode = dir + "/cone.gcode";
  geometry::write_stl_binary(stl, solids::cone(10, 20, 64).mesh);
  const auto r = run_mahost({"slice", stl, "--no-raft", "--max-layers", "60", "--contour", "mid", "-o", gcode});
  REQUIRE(r.exit_code == 0);
  CHECK(tops_of(gcode).size() <= 60);
  CHECK(r.out.find("adaptive: ") != std::string::npos);
  CHECK(r.out.find("no plan has at most") == std::string::npos);
  // Said against the cap the least error was found within, beside the least tolerance.
  CAPTURE(r.out);
  CHECK(r.out.find("for the least total error with D within ") != std::string::npos);
  CHECK(r.out.find("the least tolerance within --max-layers 60 is ") != std::string::npos);
  CHECK(r.out.find("to land") == std::string::npos);
  // A budget below the fewest layers the thicknesses allow is said, with the count printed:
  // 20 mm at most 0.4 mm a layer, over a 0.3 mm first one, is 1 + ceil(19.7 / 0.4) = 51
  // layers, the last of which starts at 19.6 mm or above, where the cone is at most 0.4 mm
  // across: its mid section, at most 0.2 mm across, fits no bead and prints nothing. Not
  // printed, that layer is not planned: 50.
  const auto tight = run_mahost(
      {"slice", stl, "--no-raft", "--max-layers", "10", "--contour", "mid", "-o", gcode});
  REQUIRE(tight.exit_code == 0);
  CAPTURE(tight.out);
  CHECK(tops_of(gcode).size() == 50);
  CHECK(tight.out.find("no plan has at most --max-layers 10: the thickest layers the printer "
                       "allows make 50") != std::string::npos);
}

TEST_CASE("adaptive_options_that_contradict_are_refused_in_one_line") {
  const std::string dir = test_support::scratch_dir("plan_adaptive_bad");
  const std::string stl = dir + "/cube.stl";
  geometry::write_stl_binary(stl, solids::cube(10).mesh);
  auto r = run_mahost({"slice", stl, "--adaptive", "--layer", "0.2", "-o", dir + "/x.gcode"});
  CHECK(r.exit_code == 2);
  CHECK(r.err.find("--layer") != std::string::npos);
  r = run_mahost({"slice", stl, "--tolerance", "0.2", "--max-layers", "10", "-o", dir + "/x.gcode"});
  CHECK(r.exit_code == 2);
  r = run_mahost({"slice", stl, "--tolerance", "-1", "-o", dir + "/x.gcode"});
  CHECK(r.exit_code == 2);
  CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
}

TEST_CASE("analyze_adaptive_judges_the_plan_and_says_how_it_was_made") {
  const std::string dir = test_support::scratch_dir("plan_adaptive_analyze");
  const std::string stl = dir + "/ball.stl";
  geometry::write_stl_binary(stl, solids::sphere(8, 48, 24, {0, 0, 8}).mesh);
  const auto r = run_mahost({"analyze", stl, "--adaptive", "--tolerance", "0.15", "--contour",
                             "best", "--contours", "mid,best"});
  REQUIRE(r.exit_code == 0);
  CHECK(r.out.find("adaptive: ") != std::string::npos);
  CHECK(r.out.find("best ") != std::string::npos);
  CHECK(r.out.find("0.15 to 0.4 mm thick") != std::string::npos);
}

namespace {

// "1 h 2 min 3 s", "33 min 53 s", "40 s" at `at` in `text`, in seconds; -1 if none.
double duration_at(const std::string& text, std::size_t at) {
  double seconds = 0;
  bool any = false;
  std::istringstream in(text.substr(at));
  double value = 0;
  std::string unit;
  while (in >> value >> unit) {
    if (unit == "h") seconds += 3600 * value;
    else if (unit == "min") seconds += 60 * value;
    else if (unit.starts_with("s")) seconds += value;
    else break;
    any = true;
    if (unit.starts_with("s")) break;
  }
  return any ? seconds : -1;
}

}  // namespace

namespace {

// The plan line of `mahost slice stl --adaptive ... extra` says two uniform estimates
// ("against 1 h 2 min at uniform 0.15 mm (333 layers) and ... at uniform 0.25 mm (200
// layers)"); each must be within 2% of slicing uniformly at that thickness with the same
// options, in as many layers.
void check_uniform_estimates(const std::string& stl, const std::string& dir,
                             const std::vector<std::string>& extra) {
  const std::string adaptive = dir + "/a.gcode", uniform = dir + "/u.gcode";
  std::vector<std::string> args{"slice", stl, "--adaptive", "--tolerance", "0.2", "-o", adaptive};
  args.insert(args.end(), extra.begin(), extra.end());
  const auto planned = run_mahost(args);
  REQUIRE(planned.exit_code == 0);
  CAPTURE(planned.out);
  // "... against 1 h 2 min 3 s at uniform 0.15 mm (333 layers) and 40 min 1 s at uniform ..."
  const std::regex estimate(R"((against|and) ((?:\d+ (?:h|min|s) ?)+)at uniform ([0-9.]+) mm \((\d+) layers\))");
  int estimates = 0;
  for (auto it = std::sregex_iterator(planned.out.begin(), planned.out.end(), estimate);
       it != std::sregex_iterator(); ++it) {
    const std::smatch& m = *it;
    const std::string said_text = m[2].str(), thickness = m[3].str(), said_layers = m[4].str();
    const double said = duration_at(said_text, 0);
    std::vector<std::string> slice{"slice", stl, "--layer", thickness, "-o", uniform};
    slice.insert(slice.end(), extra.begin(), extra.end());
    const auto sliced = run_mahost(slice);
    REQUIRE(sliced.exit_code == 0);
    CAPTURE(sliced.out);
    const std::size_t estimated = sliced.out.find("estimated print time ");
    REQUIRE(estimated != std::string::npos);
    const double full = duration_at(sliced.out, estimated + 21);
    REQUIRE(full > 0);
    CAPTURE(thickness);
    CHECK(std::abs(said - full) <= 0.02 * full);
    CHECK(sliced.out.find(": " + said_layers + " layers") != std::string::npos);
    ++estimates;
  }
  CHECK(estimates == 2);
}

}  // namespace

TEST_CASE("the_plan_lines_uniform_estimates_are_what_slicing_uniformly_estimates") {
  // The estimates time a sample of the uniform layers and fill in the rest from the plan's
  // own program. A T (its bar on supports, over a raft): supports and interfaces come and
  // go. A frustum narrowing steadily from 20 to 2 mm: copying a sampled layer's paths to the
  // layers above it (what the estimate did before) says 11% (0.15 mm) and 22% (0.4 mm) too
  // much.
  const std::string dir = test_support::scratch_dir("plan_estimate");
  const std::string tee = dir + "/tee.stl", frustum = dir + "/frustum.stl";
  geometry::write_stl_binary(
      tee, solids::lying_prism({{-5, 0}, {5, 0}, {5, 20}, {25, 20}, {25, 25}, {-25, 25}, {-25, 20}, {-5, 20}},
                               -5, 5).mesh);
  geometry::write_stl_binary(frustum, solids::frustum(20, 2, 30, 96).mesh);
  SUBCASE("a T on supports and a raft") { check_uniform_estimates(tee, dir, {"--contour", "mid"}); }
  SUBCASE("a frustum") { check_uniform_estimates(frustum, dir, {"--no-raft", "--contour", "mid"}); }
}

TEST_CASE("slice_adaptive_keeps_a_print_time_budget") {
  // A cone, between its print times at the thinnest and the thickest uniform layers: the plan
  // fits the budget (the plan's own estimate is of mid sections, as the G-code here is), and
  // a budget under the thickest layers' time gets those and says so.
  const std::string dir = test_support::scratch_dir("plan_adaptive_time");
  const std::string stl = dir + "/cone.stl", gcode = dir + "/cone.gcode";
  geometry::write_stl_binary(stl, solids::cone(10, 20, 64).mesh);
  const auto time_of = [&](const std::vector<std::string>& args) {
    const auto r = run_mahost(args);
    REQUIRE(r.exit_code == 0);
    const std::size_t at = r.out.find("estimated print time ");
    REQUIRE(at != std::string::npos);
    return std::pair{duration_at(r.out, at + 21), r.out};
  };
  const double thin = time_of({"slice", stl, "--no-raft", "--layer", "0.15", "--contour", "mid", "-o", gcode}).first;
  const double thick = time_of({"slice", stl, "--no-raft", "--layer", "0.4", "--contour", "mid", "-o", gcode}).first;
  REQUIRE(thick < thin);
  const int budget = static_cast<int>((thin + thick) / 2);
  const auto [fitted, said] = time_of({"slice", stl, "--no-raft", "--max-time", std::to_string(budget) + "s",
                                       "--contour", "mid", "-o", gcode});
  CAPTURE(said);
  CHECK(said.find("whose print fits --max-time") != std::string::npos);
  CHECK(fitted <= budget);
  CHECK(fitted >= thick);
  const auto [fastest, refused] = time_of({"slice", stl, "--no-raft", "--max-time", "1s", "--contour", "mid", "-o", gcode});
  CHECK(refused.find("no plan fits --max-time 1 s") != std::string::npos);
  CHECK(fastest <= 1.02 * thick);
}

TEST_CASE("a_print_time_budget_that_is_not_a_duration_is_refused_in_one_line") {
  const std::string dir = test_support::scratch_dir("plan_adaptive_time_bad");
  const std::string stl = dir + "/cone.stl";
  geometry::write_stl_binary(stl, solids::cone(10, 20, 16).mesh);
  for (const std::string bad : {"90", "1m30h", "abc", "-5m", "0s"}) {
    CAPTURE(bad);
    const auto r = run_mahost({"slice", stl, "--max-time", bad, "-o", dir + "/x.gcode"});
    CHECK(r.exit_code != 0);
    CHECK(r.err.find("--max-time") != std::string::npos);
    CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
  }
  const auto both = run_mahost({"slice", stl, "--max-time", "1h", "--max-layers", "50", "-o", dir + "/x.gcode"});
  CHECK(both.exit_code != 0);
  CHECK(both.err.find("excludes") != std::string::npos);
}

TEST_CASE("the_plan_line_names_each_layer_over_the_tolerance_and_why") {
  // A hemisphere of radius 10 on a 2 mm disc, printed by best: near the top even 0.15 mm
  // layers are over 0.08 mm (the surface flattens), each named by its height with the
  // shallowest slope there; the plan says it is best's D planned by mid's, and a range of one
  // thickness is said once.
  const std::string dir = test_support::scratch_dir("plan_reasons");
  const std::string dome = dir + "/dome.stl", box = dir + "/box.stl", gcode = dir + "/x.gcode";
  std::vector<geometry::Vec2> profile{{0, 0}, {10, 0}, {10, 2}};
  for (int k = 1; k < 24; ++k) {
    const double a = 3.141592653589793 / 2 * k / 24;
    profile.push_back({10 * std::cos(a), 2 + 10 * std::sin(a)});
  }
  profile.push_back({0, 12});
  geometry::write_stl_binary(dome, solids::revolve(profile, 64).mesh);
  auto r = run_mahost({"slice", dome, "--no-raft", "--support", "none", "--adaptive", "--tolerance",
                       "0.08", "-o", gcode});
  REQUIRE(r.exit_code == 0);
  CAPTURE(r.out);
  CHECK(r.out.find("best's D, planned by mid's") != std::string::npos);
  CHECK(r.out.find("over it (up to ") != std::string::npos);
  CHECK(r.out.find("the thinnest the printer has (0.15 mm)") != std::string::npos);
  CHECK(std::regex_search(r.out, std::regex(R"(z \d+\.\d\d-12\.00 \(slopes down to \d+° from horizontal)")));
  CHECK(r.out.find("nearly flat") == std::string::npos);
  // A box 7.15 mm tall of vertical walls: every layer 0.4 mm but what lands the top.
  geometry::write_stl_binary(box, solids::box({0, 0, 0}, {10, 10, 7.15}).mesh);
  r = run_mahost({"slice", box, "--no-raft", "--support", "none", "--adaptive", "--tolerance", "0.1",
                  "--contour", "mid", "-o", gcode});
  REQUIRE(r.exit_code == 0);
  CAPTURE(r.out);
  CHECK(r.out.find("over it") == std::string::npos);
  CHECK(r.out.find("first layer") == std::string::npos);
  CHECK(std::regex_search(r.out, std::regex(R"(adaptive: \d+ layers of 0\.\d+-0\.4 mm for D within 0\.1 mm \(mid's D;)")));
  // Uniform thickness after the first: one number, never "0.15-0.15".
  r = run_mahost({"slice", dome, "--no-raft", "--support", "none", "--adaptive", "--tolerance",
                  "0.001", "--contour", "mid", "-o", gcode});
  REQUIRE(r.exit_code == 0);
  CHECK(r.out.find("0.15-0.15") == std::string::npos);
}

}  // namespace adaptive_cli_test
