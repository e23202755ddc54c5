// A model loaded through the application layer (app/model.h) and what `mahost info` reports of
// it: the placed part's figures against a box's closed forms, and the export read back.
#include <string>

#include <doctest/doctest.h>

#include "app/model.h"
#include "geometry/mesh/stl_io.h"
#include "support/run_command.h"
#include "support/solids.h"

namespace model_test {

TEST_CASE("model_figures_of_a_box_are_its_closed_forms") {
  const std::string dir = test_support::scratch_dir("model_figures");
  app::ModelOptions options;
  options.path = dir + "/box.stl";
  geometry::write_stl_binary(options.path, solids::box({0, 0, 0}, {20, 30, 10}).mesh);
  const app::LoadedModel model = app::load_model(options, {100, 50});
  // Overhangs past 50 degrees: the box's floor rests on the bed, so none.
  const app::ModelFigures figures = app::model_figures(model, 50);
  CHECK(figures.format == "STL");
  CHECK(figures.triangles == 12);
  CHECK(figures.vertices == 8);
  CHECK(figures.box.min.x == doctest::Approx(90));
  CHECK(figures.box.max.x == doctest::Approx(110));
  CHECK(figures.box.min.y == doctest::Approx(35));
  CHECK(figures.box.max.y == doctest::Approx(65));
  CHECK(figures.box.min.z == doctest::Approx(0));
  CHECK(figures.box.max.z == doctest::Approx(10));
  CHECK(figures.volume == doctest::Approx(6000));
  CHECK(figures.surface_area == doctest::Approx(2 * (20 * 30 + 20 * 10 + 30 * 10)));
  CHECK(figures.support_volume == doctest::Approx(0));

  // The export is the placed mesh: read back, the same box where it was placed.
  app::export_stl(model, dir + "/placed.stl");
  app::ModelOptions again;
  again.path = dir + "/placed.stl";
  const app::ModelFigures placed = app::model_figures(app::load_model(again, {100, 50}), 50);
  CHECK(placed.volume == doctest::Approx(6000));
  CHECK(placed.box.min.x == doctest::Approx(90));
  CHECK(placed.box.max.y == doctest::Approx(65));
}

}  // namespace model_test
