// `mahost info MODEL [placement] [--export OUT.stl]`: what the model is after reading,
// repair and placement, the numbers a user checks before slicing (size, volume, watertight),
// and optionally the placed, repaired mesh as binary STL, which is what every later stage
// slices.
#include <memory>
#include <string>

#include <CLI/CLI.hpp>
#include <fmt/core.h>

#include "app/model.h"
#include "host/commands.h"
#include "host/slice_flags.h"

namespace host {
namespace {

struct InfoOptions {
  app::ModelOptions model;
  std::string export_path;
};

void run_info(const InfoOptions& options) {
  const app::LoadedModel model = app::load_model(options.model);
  const app::ModelFigures figures = app::model_figures(model, options.model.overhang_angle);
  const auto& repair = model.repair;
  const auto& box = figures.box;
  const auto size = box.max - box.min;
  const std::string repairs = repair.summary();

  fmt::print("model         {}\n", options.model.path);
  fmt::print("format        {}\n", figures.format);
  fmt::print("triangles     {} in the file, {} after repair\n", repair.facets_read, figures.triangles);
  fmt::print("vertices      {}\n", figures.vertices);
  fmt::print("size          {:.3f} x {:.3f} x {:.3f} mm\n", size.x, size.y, size.z);
  fmt::print("min           {:.3f} {:.3f} {:.3f} mm\n", box.min.x, box.min.y, box.min.z);
  fmt::print("max           {:.3f} {:.3f} {:.3f} mm\n", box.max.x, box.max.y, box.max.z);
  fmt::print("volume        {:.3f} mm^3\n", figures.volume);
  fmt::print("surface area  {:.3f} mm^2\n", figures.surface_area);
  fmt::print("open edges    {} before repair, {} after\n", repair.open_edges_before,
             repair.open_edges_after);
  fmt::print("repairs       {}\n", repairs.empty() ? "none" : repairs);
  fmt::print("watertight    {}\n", repair.closed ? "yes" : "no");
  // Stored normals decide nothing (the vertex order and the repair do); those that point into
  // the repaired part are counted, as a sign of an exporter's disagreement.
  if (model.normals) {
    const auto& n = *model.normals;
    fmt::print("normals       {} of {} stored normals point into the repaired part{}\n",
               n.disagreeing, n.compared,
               n.no_direction == 0   ? std::string()
               : n.no_direction == 1 ? std::string(" (1 more is zero or not a number)")
                                     : fmt::format(" ({} more are zero or not numbers)", n.no_direction));
  }
  // Support under overhangs, columns to the bed or the part below (an estimate), and what
  // --orient auto made of it.
  fmt::print("overhangs     ~{:.0f} mm^3 of support under walls leaning past {:g} deg from vertical\n",
             figures.support_volume, options.model.overhang_angle);
  if (model.orientation) fmt::print("orientation   {}\n", app::orientation_text(model));
  if (!options.export_path.empty()) {
    app::export_stl(model, options.export_path);
    fmt::print("exported      {} (binary STL, mm)\n", options.export_path);
  }
}

}  // namespace

void add_info_command(CLI::App& app) {
  auto options = std::make_shared<InfoOptions>();
  CLI::App* info = app.add_subcommand("info", "Show a model's size, volume and repairs");
  info->footer(
      "Reads, repairs and places the model as slice and print do, then prints its triangles, "
      "vertices, bounding box, volume, surface area, open edges before and after repair, the "
      "repairs done and whether it is watertight. Exit code 2 for a file that cannot be "
      "printed.");
  add_model_options(*info, options->model);
  info->add_option("--export", options->export_path,
                   "write the placed, repaired mesh to this file as binary STL, mm (default: "
                   "none)");
  info->callback([options] { run_info(*options); });
}

}  // namespace host
