// The slice pipeline called in-process (app/slice.h), as the command line and the web host
// call it: the result carries what a user should hear of, progress and cancellation go
// through SliceEvents, and nothing is printed.
#include <atomic>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <doctest/doctest.h>
#include <fmt/core.h>

#include "app/slice.h"
#include "app/uniform_estimate.h"
#include "geometry/slicing/layer_stack.h"
#include "geometry/core/error.h"
#include "geometry/mesh/stl_io.h"
#include "printer/error.h"
#include "support/run_command.h"
#include "support/solids.h"

namespace slice_test {

namespace fs = std::filesystem;

std::string read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// A 20 x 20 x 10 mm box as an STL in `dir`; with `open`, one of its facets left out (a hole
// the repair fills).
std::string box_stl(const std::string& dir, bool open = false) {
  const geometry::Mesh mesh = solids::box({0, 0, 0}, {20, 20, 10}).mesh;
  std::vector<geometry::Triangle> facets;
  for (const auto& face : mesh.faces) {
    facets.push_back({{mesh.vertices[face[0]], mesh.vertices[face[1]], mesh.vertices[face[2]]}});
  }
  if (open) facets.pop_back();
  const std::string path = dir + (open ? "/open_box.stl" : "/box.stl");
  geometry::write_stl_binary(path, facets);
  return path;
}

TEST_CASE("slice_in_process_writes_the_gcode_the_options_ask_for") {
  const std::string dir = test_support::scratch_dir("app_slice_options");
  app::SliceOptions options;
  options.model.path = box_stl(dir);
  options.layer = 0.2;
  options.support.raft = false;
  options.support.brim = 4;
  options.perimeters = 3;
  const std::string gcode = dir + "/box.gcode";
  std::vector<app::SliceStage> started;
  app::SliceEvents events;
  events.progress = [&](app::SliceStage stage, std::size_t done, std::size_t) {
    if (done == 0) started.push_back(stage);  // from the calling thread
  };
  const app::SliceResult result = app::slice(options, gcode, events);

  // The up-plus-2's first layer, then 0.2 mm layers to the box's top at 10 mm.
  const double first = result.profiles.printer.first_layer_height;
  REQUIRE(result.layers.size() == static_cast<std::size_t>(std::ceil((10 - first) / 0.2 - 1e-9)) + 1);
  CHECK(result.layers.front().z_hi == doctest::Approx(first));
  CHECK(result.layers.back().z_hi == doctest::Approx(10).epsilon(0.2 / 10));
  CHECK(result.layer_thickness == 0.2);
  CHECK(result.part_size.x == doctest::Approx(20));
  CHECK(result.part_size.z == doctest::Approx(10));
  CHECK(result.summary.layers == result.layers.size());  // no raft
  CHECK(result.profiles.printer.print.perimeters == 3);
  CHECK(result.profiles.printer.brim_width == 4);
  CHECK_FALSE(result.repair.anything_repaired());
  CHECK(result.warnings.empty());
  CHECK(started == std::vector<app::SliceStage>{app::SliceStage::planning, app::SliceStage::contours,
                                                 app::SliceStage::supports, app::SliceStage::toolpaths,
                                                 app::SliceStage::writing});
  const std::string text = read_file(gcode);
  CHECK(text.size() == result.summary.bytes);
  CHECK(text.find("\n; brim: 4 mm\n") != std::string::npos);
  CHECK(text.find("perimeters: 3,") != std::string::npos);
  CHECK(app::slice_summary_text(result).starts_with(fmt::format("{} layers, estimated print time", result.layers.size())));
}

TEST_CASE("the_repair_report_comes_back_in_the_result_and_as_it_happens") {
  const std::string dir = test_support::scratch_dir("app_slice_repair");
  app::SliceOptions options;
  options.model.path = box_stl(dir, true);
  std::vector<std::string> heard;
  app::SliceEvents events;
  events.warning = [&](const std::string& line) { heard.push_back(line); };
  const app::SliceResult result = app::slice(options, dir + "/open_box.gcode", events);
  CHECK(result.repair.anything_repaired());
  CHECK(result.repair.open_edges_before == 3);
  CHECK(result.repair.open_edges_after == 0);
  REQUIRE(result.warnings.size() == 1);
  CHECK(result.warnings == heard);
  CHECK(result.warnings[0] == options.model.path + ": repaired: " + result.repair.summary());
  CHECK(result.part_size.z == doctest::Approx(10));
}

TEST_CASE("layer_tops_left_out_are_said_in_the_result") {
  const std::string dir = test_support::scratch_dir("app_slice_boundaries");
  app::SliceOptions options;
  options.model.path = box_stl(dir);
  options.support.raft = false;
  // The up-plus-2's first layer (0.3 mm), then 0.3 mm layers to 10.8 mm: 10.2 mm covers the
  // box's top, the two above it are left out.
  std::string tops;
  for (int k = 1; k <= 36; ++k) tops += fmt::format("{}{:.1f}", k == 1 ? "" : ",", 0.3 * k);
  options.boundaries = tops;
  const app::SliceResult result = app::slice(options, dir + "/box.gcode");
  REQUIRE(result.warnings.size() == 1);
  CHECK(result.warnings[0].find("2 layer tops above the part's top") != std::string::npos);
  CHECK(result.layers.back().z_hi == doctest::Approx(10.2));
}

// The G-code's own estimate in its header (";PRINT_TIME_S:5035.140"), s; -1 if none.
double header_seconds(const std::string& gcode) {
  const std::string text = read_file(gcode);
  const std::size_t at = text.find(";PRINT_TIME_S:");
  return at == std::string::npos ? -1 : std::stod(text.substr(at + 14));
}

// Slicing `stl` as a print-time budget's estimate times it: mid's sections, no support, no
// raft, uniform 0.25 mm layers.
app::SliceOptions printed_as_estimated(const std::string& stl) {
  app::SliceOptions options;
  options.model.path = stl;
  options.contour = "mid";
  options.support.placement = "none";
  options.support.raft = false;
  options.layer = 0.25;
  return options;
}

TEST_CASE("a_print_time_budget_holds_for_the_gcodes_own_estimate") {
  // A 96-gon frustum widening upward from radius 4 to 16 over 30 mm (its wall 22 degrees from
  // vertical: no support), printed by mid's sections as the plan is estimated. Its D depends
  // only on a layer's thickness, so a plan is about uniform at the thickest layer within the
  // tolerance. The plan estimates each candidate from a sample of its layers, those between
  // printing the paths of the sampled one below, narrower than their own (their time scaled
  // to their area: else about 2% short of their program for uniform 0.25 mm layers). A budget
  // 1% under that program is kept by the file's own estimate (its header's, what `print
  // --dry-run` says; the plan line says that one too), by thicker layers, not by a plan whose
  // sample fits and whose program does not.
  const std::string dir = test_support::scratch_dir("app_slice_time_budget");
  const std::string stl = dir + "/frustum.stl", gcode = dir + "/frustum.gcode";
  geometry::write_stl_binary(stl, solids::frustum(4, 16, 30, 96).mesh);
  app::SliceOptions options = printed_as_estimated(stl);
  const double uniform = app::slice(options, gcode).summary.print_seconds;
  options.layer = 0.4;
  const double thickest = app::slice(options, gcode).summary.print_seconds;
  options.layer.reset();
  const double budget = std::round(0.99 * uniform);
  REQUIRE(thickest < budget);
  options.adaptive.max_seconds = budget;
  const app::SliceResult result = app::slice(options, gcode);
  const std::string said = result.warnings.empty() ? "" : result.warnings.front();
  CAPTURE(uniform);
  CAPTURE(budget);
  CAPTURE(said);
  CHECK(result.summary.print_seconds <= budget);
  CHECK(header_seconds(gcode) <= budget);
  CHECK(header_seconds(gcode) == doctest::Approx(result.summary.print_seconds).epsilon(1e-6));
  CHECK(result.choice.estimated_seconds == result.summary.print_seconds);
  CHECK(result.summary.print_seconds >= thickest);
  // The plan's estimate follows the part's widening (and leaves a little headroom): its first
  // plan's program fits, and the plan is not made again.
  CHECK(said.find("planned again") == std::string::npos);
}

TEST_CASE("a_plans_print_time_estimate_follows_a_part_that_widens_or_narrows") {
  // The estimate a print-time budget plans by (uniform_estimate.h) times one pair of layers in
  // three; the layers between print the paths of the sampled one of their parity below, and
  // take its time per mm^2 of section, interpolated up to the next sampled one, times their
  // own area. Frustums widening from radius 4 to 16 and narrowing from 16 to 4 over 30 mm,
  // uniform 0.25 mm layers printed by mid's sections as the estimate takes them: the estimate
  // is within 0.5% of the program's own (-0.01% and -0.08%; the copied paths alone say -1.9%
  // and +1.7%).
  const std::string dir = test_support::scratch_dir("app_slice_estimate_shape");
  for (const auto& [bottom, top] : {std::pair{4.0, 16.0}, std::pair{16.0, 4.0}}) {
    CAPTURE(bottom);
    const std::string stl = dir + "/frustum.stl";
    const solids::Solid frustum = solids::frustum(bottom, top, 30, 96);
    geometry::write_stl_binary(stl, frustum.mesh);
    const app::SliceResult result = app::slice(printed_as_estimated(stl), dir + "/frustum.gcode");
    const geometry::LayerStack index(frustum.mesh, {});
    const double estimate = app::estimated_seconds(index, result.layers, result.profiles);
    CAPTURE(estimate);
    CHECK(estimate == doctest::Approx(result.summary.print_seconds).epsilon(0.005));
  }
}

TEST_CASE("a_cancelled_slice_stops_and_leaves_no_file") {
  const std::string dir = test_support::scratch_dir("app_slice_cancel");
  app::SliceOptions options;
  options.model.path = box_stl(dir);
  const std::string gcode = dir + "/box.gcode";
  for (const app::SliceStage stop_at : {app::SliceStage::planning, app::SliceStage::contours,
                                        app::SliceStage::toolpaths, app::SliceStage::writing}) {
    CAPTURE(app::stage_name(stop_at));
    std::atomic<bool> stop{false};
    std::atomic<bool> reached{false};
    app::SliceEvents events;
    events.progress = [&](app::SliceStage stage, std::size_t, std::size_t) {
      if (stage == stop_at) reached = stop = true;
    };
    events.cancelled = [&] { return stop.load(); };
    CHECK_THROWS_AS(app::slice(options, gcode, events), app::SliceCancelled);
    CHECK(reached);
    CHECK_FALSE(fs::exists(gcode));
  }
}

TEST_CASE("bad_requests_throw_the_errors_host_turns_into_one_line") {
  const std::string dir = test_support::scratch_dir("app_slice_errors");
  app::SliceOptions options;
  options.model.path = dir + "/missing.stl";
  CHECK_THROWS_AS(app::slice(options, dir + "/x.gcode"), geometry::InputError);
  options.model.path = box_stl(dir);
  options.layer = 0.17;  // not one of the up-plus-2's thicknesses
  CHECK_THROWS_AS(app::slice(options, dir + "/x.gcode"), printer::ConfigError);
  options.layer.reset();
  options.printer = "no-such-printer";
  CHECK_THROWS_AS(app::slice(options, dir + "/x.gcode"), printer::ConfigError);
  CHECK_FALSE(fs::exists(dir + "/x.gcode"));
}

}  // namespace slice_test
