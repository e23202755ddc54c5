// `mahost info MODEL [placement] [--export OUT.stl]`: what the model is after reading,
// repair and placement, the numbers a user checks before slicing (size, volume, watertight),
// and optionally the placed, repaired mesh as binary STL, which is what every later stage
// slices.
#include <memory>
#include <string>

#include <CLI/CLI.hpp>
#include <fmt/core.h>

#include "app/model.h"
#include "geometry/mesh/mesh.h"
#include "geometry/mesh/stl_io.h"
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
  const geometry::Mesh& mesh = model.mesh;
  const geometry::RepairReport& repair = model.repair;
  const geometry::Box3 box = geometry::bounding_box(mesh);
  const geometry::Vec3 size = box.max - box.min;
  const std::string repairs = repair.summary();

  fmt::print("model         {}\n", options.model.path);
  fmt::print("format        {}{}\n", geometry::format_name(model.format),
             model.format == geometry::ModelFormat::threemf
                 ? (model.objects == 1 ? std::string(", 1 object")
                                       : fmt::format(", {} objects placed together", model.objects))
                 : "");
  fmt::print("triangles     {} in the file, {} after repair\n", repair.facets_read,
             mesh.faces.size());
  fmt::print("vertices      {}\n", mesh.vertices.size());
  fmt::print("size          {:.3f} x {:.3f} x {:.3f} mm\n", size.x, size.y, size.z);
  fmt::print("min           {:.3f} {:.3f} {:.3f} mm\n", box.min.x, box.min.y, box.min.z);
  fmt::print("max           {:.3f} {:.3f} {:.3f} mm\n", box.max.x, box.max.y, box.max.z);
  fmt::print("volume        {:.3f} mm^3\n", geometry::signed_volume(mesh));
  fmt::print("surface area  {:.3f} mm^2\n", geometry::surface_area(mesh));
  fmt::print("open edges    {} before repair, {} after\n", repair.open_edges_before,
             repair.open_edges_after);
  fmt::print("repairs       {}\n", repairs.empty() ? "none" : repairs);
  fmt::print("watertight    {}\n", repair.closed ? "yes" : "no");
  // Stored normals decide nothing (the vertex order and the repair do); those that point into
  // the repaired part are counted, as a sign of an exporter's disagreement.
  if (model.normals) {
    const geometry::StoredNormals& n = *model.normals;
    fmt::print("normals       {} of {} stored normals point into the repaired part{}\n",
               n.disagreeing, n.compared,
               n.no_direction == 0   ? std::string()
               : n.no_direction == 1 ? std::string(" (1 more is zero or not a number)")
                                     : fmt::format(" ({} more are zero or not numbers)", n.no_direction));
  }
  // Support under overhangs past 50 degrees from vertical, columns to the bed or the part
  // below (an estimate; orientation.h), and what --orient auto made of it.
  fmt::print("overhangs     ~{:.0f} mm^3 of support under walls leaning past {:g} deg from vertical\n",
             geometry::support_volume_estimate(mesh, options.model.overhang_angle),
             options.model.overhang_angle);
  if (model.orientation) fmt::print("orientation   {}\n", app::orientation_text(model));
  if (!options.export_path.empty()) {
    geometry::write_stl_binary(options.export_path, mesh);
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
