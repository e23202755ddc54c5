// analyze and advise called in-process (app/analyze.h), as the command line calls them: the
// result carries the layers, each strategy's measurements, the comparisons and what the
// charts and the export need; progress and cancellation go through AnalysisEvents. The
// figures are checked against a frustum's and a box's closed forms.
#include <cmath>
#include <string>
#include <vector>

#include <doctest/doctest.h>

#include "app/analyze.h"
#include "geometry/core/error.h"
#include "geometry/mesh/stl_io.h"
#include "support/run_command.h"
#include "support/solids.h"

namespace analyze_test {

// The solid's mesh as an STL in `dir`, named `name`.
std::string stl_of(const solids::Solid& solid, const std::string& dir, const std::string& name) {
  const geometry::Mesh& mesh = solid.mesh;
  std::vector<geometry::Triangle> facets;
  for (const auto& face : mesh.faces) {
    facets.push_back({{mesh.vertices[face[0]], mesh.vertices[face[1]], mesh.vertices[face[2]]}});
  }
  const std::string path = dir + "/" + name;
  geometry::write_stl_binary(path, facets);
  return path;
}

constexpr int kSides = 48;
constexpr double kBottom = 10, kTop = 5, kHeight = 10;  // mm: the frustum's radii and height

// The frustum's circumradius at z, mm.
double radius_at(double z) { return kBottom + (kTop - kBottom) * z / kHeight; }

app::AnalyzeRequest frustum_request(const std::string& dir) {
  app::AnalyzeRequest request;
  request.model.path = stl_of(solids::frustum(kBottom, kTop, kHeight, kSides), dir, "frustum.stl");
  request.layer = 0.5;
  request.from_zero = true;  // 20 layers of 0.5 mm from the bed
  request.strategies = app::strategy_list({"lower", "mid"}, "--contours");
  request.contour = &geometry::contour_strategy("lower");
  return request;
}

TEST_CASE("analyze_in_process_measures_lower_on_a_frustum_as_its_closed_form") {
  const std::string dir = test_support::scratch_dir("app_analyze_frustum");
  app::AnalyzeRequest request = frustum_request(dir);
  request.export_layers = true;
  std::vector<std::string> started;
  app::AnalysisEvents events;
  events.progress = [&](const std::string& label, std::size_t done, std::size_t) {
    if (done == 0) started.push_back(label);  // from the calling thread
  };
  const app::AnalyzeResult result = app::analyze(request, events);

  REQUIRE(result.layers.size() == 20);
  REQUIRE(result.analysis.size() == 20);
  REQUIRE(result.strategies.size() == 2);  // lower, mid: --contour's lower is among them
  CHECK(result.height == doctest::Approx(kHeight));
  CHECK(started == std::vector<std::string>{"analyze"});
  // Lower prints each layer's section at its bottom, the widest: its layered part is the sum
  // of those n-gon prisms, and its total ΔV what that adds to the frustum (which it holds).
  double stepped = 0;
  for (const geometry::Layer& layer : result.layers) {
    stepped += layer.thickness() * solids::regular_polygon_area(kSides, radius_at(layer.z_lo));
  }
  const double frustum = solids::frustum(kBottom, kTop, kHeight, kSides).volume;
  // The STL holds single-precision coordinates: volumes agree to about 1e-7.
  CHECK(result.model_volume == doctest::Approx(frustum).epsilon(1e-6));
  REQUIRE(result.layered_part);
  CHECK(result.layered_part_volume == doctest::Approx(stepped).epsilon(1e-6));
  const geometry::StrategySummary& lower = result.summaries[0];
  CHECK(lower.strategy->name == "lower");
  CHECK(lower.total_deviation == doctest::Approx(stepped - frustum).epsilon(1e-3));
  // Its distance error D, the largest horizontal distance from the surface in the slab to the
  // walls: at the slab's top the section is the same n-gon (R - r) / H * t smaller in
  // circumradius, so its sides stand that times cos(pi / n) inside lower's.
  const double inset = (kBottom - kTop) / kHeight * 0.5 * std::cos(M_PI / kSides);
  CHECK(lower.max_distance == doctest::Approx(inset).epsilon(0.01));
  CHECK(lower.mean_distance == doctest::Approx(inset).epsilon(0.01));
  // Mid is compared with lower, and is better on every layer: the section at the middle
  // stands half as far from the slab's top and bottom.
  REQUIRE(result.comparisons.size() == 1);
  const app::Comparison& mid_vs_lower = result.comparisons[0];
  CHECK(mid_vs_lower.strategy == 1);
  CHECK(mid_vs_lower.baseline == 0);
  CHECK(mid_vs_lower.distance_better == 20);
  CHECK(mid_vs_lower.distance_worse == 0);
  CHECK(result.summaries[1].max_distance == doctest::Approx(inset / 2).epsilon(0.01));
  CHECK(result.volume_limit > 0);
  CHECK_FALSE(result.drawing);
  CHECK(result.thicker.empty());
}

// One layer's measurements of two strategies, k = 0 and 1: D (mm) and missed features.
geometry::LayerAnalysis layer_of(double d0, std::size_t missed0, double d1, std::size_t missed1) {
  geometry::LayerAnalysis layer;
  layer.strategies.resize(2);
  layer.strategies[0].metrics.distance = d0;
  layer.strategies[0].metrics.missed_features = missed0;
  layer.strategies[1].metrics.distance = d1;
  layer.strategies[1].metrics.missed_features = missed1;
  return layer;
}

TEST_CASE("a_layer_worse_by_D_where_the_baseline_misses_a_feature_is_counted_as_such") {
  // best (1) against mid (0): better on the first layer; worse on the second, where both miss
  // nothing; worse on the third, a tip mid's empty section leaves out and best prints at a D
  // the empty section (measured to the tip's own outline) does not have; equal on the last.
  const std::vector<geometry::LayerAnalysis> layers = {
      layer_of(0.20, 0, 0.10, 0), layer_of(0.10, 0, 0.15, 0), layer_of(0.128, 1, 0.212, 0),
      layer_of(0.10, 0, 0.10, 0)};
  const app::Comparison c = app::compare(layers, 1, 0);
  CHECK(c.distance_better == 1);
  CHECK(c.distance_worse == 2);
  CHECK(c.distance_worse_keeping_features == 1);
  // Mid against best: worse on the first layer only, where best misses nothing more.
  const app::Comparison reverse = app::compare(layers, 0, 1);
  CHECK(reverse.distance_worse == 1);
  CHECK(reverse.distance_worse_keeping_features == 0);
}

TEST_CASE("analyze_in_process_gives_the_thicker_layers_and_the_drawn_layer_asked_for") {
  const std::string dir = test_support::scratch_dir("app_analyze_thicker");
  app::AnalyzeRequest request = frustum_request(dir);
  request.thicker = {0.5, 1.0, 2.5};  // 0.5 is the layer itself: left out
  request.layer_index = 3;
  const app::AnalyzeResult result = app::analyze(request);

  REQUIRE(result.thicker.size() == 2);
  CHECK(result.thicker[0].thickness == 1.0);
  CHECK(result.thicker[0].layers.size() == 10);
  CHECK(result.thicker[1].layers.size() == 4);
  // Ma at 2.5 mm strays further than lower at 0.5 mm somewhere; at 1 mm it need not.
  CHECK(result.thicker[1].within_percent < 100);
  CHECK(result.thicker[1].max_distance > result.summaries[0].max_distance);
  REQUIRE(result.drawing);
  CHECK(result.drawing->index == 3);
  CHECK(result.drawing->layer.z_lo == doctest::Approx(1.5));
  CHECK(result.drawing->islands == 1);
  REQUIRE(result.drawing->analysis.strategies.size() == 2);
  // The drawn layer keeps its regions: lower's is the section at z 1.5 mm.
  CHECK(geometry::area(result.drawing->analysis.strategies[0].region) ==
        doctest::Approx(solids::regular_polygon_area(kSides, radius_at(1.5))).epsilon(1e-6));
}

TEST_CASE("analyze_in_process_refuses_a_layer_index_past_the_top_and_stops_when_cancelled") {
  const std::string dir = test_support::scratch_dir("app_analyze_refusals");
  app::AnalyzeRequest request = frustum_request(dir);
  request.layer_index = 20;
  CHECK_THROWS_WITH_AS(app::analyze(request), doctest::Contains("--layer-index 20: the part has 20 layers"),
                       geometry::InputError);

  request.layer_index.reset();
  std::size_t calls = 0;
  app::AnalysisEvents events;
  events.cancelled = [&] { return ++calls > 3; };
  CHECK_THROWS_AS(app::analyze(request, events), app::AnalysisCancelled);
  CHECK_THROWS_WITH(app::strategy_list({"lower", "nope"}, "--contours"),
                    doctest::Contains("--contours: unknown contour strategy 'nope'"));
  CHECK_THROWS_WITH(app::strategy_list({}, "--contours"), doctest::Contains("give at least one of"));
}

TEST_CASE("analyze_in_process_says_what_boundaries_leave_out") {
  const std::string dir = test_support::scratch_dir("app_analyze_boundaries");
  app::AnalyzeRequest request = frustum_request(dir);
  request.boundaries = "2,4,6";
  std::vector<std::string> notes;
  app::AnalysisEvents events;
  events.layers_note = [&](const std::string& line) { notes.push_back(line); };
  const app::AnalyzeResult result = app::analyze(request, events);
  CHECK(result.layers.size() == 3);
  REQUIRE(notes.size() == 1);
  CHECK(notes[0].find("the layers end at 6 mm") != std::string::npos);
}

TEST_CASE("advise_in_process_keeps_a_box_within_the_benchmark_at_every_thickness") {
  const std::string dir = test_support::scratch_dir("app_advise_box");
  app::AdviseRequest request;
  request.model.path = stl_of(solids::box({0, 0, 0}, {20, 20, 10}), dir, "box.stl");
  request.contour = &geometry::contour_strategy("ma");
  request.thicknesses = std::vector<double>{0.5, 1.0, 2.0};
  request.boundaries = "1,3,10";
  const app::AdviseResult result = app::advise(request);

  CHECK(result.thicknesses_from == "--thicknesses");
  CHECK(result.benchmark_thickness == 0.5);
  CHECK(result.benchmark_layers == 20);
  // Vertical walls: every contour is the section, D is nil at every thickness.
  REQUIRE(result.rows.size() == 3);
  for (const app::AdviseRow& row : result.rows) {
    CHECK(row.within_percent == 100);
    CHECK(row.max_distance < 1e-3);
  }
  CHECK(result.rows[1].layers == 10);
  CHECK(result.rows[1].fewer_layers_percent == doctest::Approx(50));
  CHECK(result.rows[2].fewer_layers_percent == doctest::Approx(75));
  REQUIRE(result.advised);
  CHECK(*result.advised == 2.0);
  REQUIRE(result.plan);
  CHECK(result.plan->layers == 3);
  CHECK(result.plan->fewer_layers_percent == doctest::Approx(85));
  CHECK(result.plan_layers.size() == 3);
  CHECK_FALSE(result.adaptive);
}

TEST_CASE("advise_in_process_takes_the_printers_thicknesses_unless_given_and_refuses_an_empty_list") {
  const std::string dir = test_support::scratch_dir("app_advise_thicknesses");
  app::AdviseRequest request;
  request.model.path = stl_of(solids::box({0, 0, 0}, {20, 20, 4}), dir, "box.stl");
  request.contour = &geometry::contour_strategy("mid");
  const app::AdviseResult result = app::advise(request);
  CHECK(result.thicknesses_from.rfind("UP Plus 2 (", 0) == 0);  // the default printer's
  REQUIRE(result.rows.size() > 1);
  CHECK(result.rows.front().thickness == result.benchmark_thickness);

  request.thicknesses = std::vector<double>{};  // --thicknesses given, with no thickness in it
  CHECK_THROWS_WITH_AS(app::advise(request), "--thicknesses: give at least one thickness",
                       geometry::InputError);
}

}  // namespace analyze_test
