// `mahost slice MODEL.stl [placement] -o OUT.gcode [--printer up-plus-2] [--material abs]
//  [--layer 0.2 | --boundaries FILE|z1,z2,...] [--contour ma] [--perimeters 2] [--infill 20] [--set key=value ...]`
//
// The slice pipeline (app/slice.h) into a file: a progress bar per stage on a terminal; one
// final line: layers, print-time estimate, filament, output size.
#include <memory>
#include <string>

#include <CLI/CLI.hpp>
#include <fmt/core.h>

#include "app/slice.h"
#include "host/commands.h"
#include "host/slice_flags.h"

namespace host {
namespace {

struct SliceCommandOptions {
  app::SliceOptions slice;
  std::string output;
};

void run_slice(const SliceCommandOptions& options) {
  const app::SliceResult result =
      app::slice(options.slice, options.output, terminal_slice_events(options.slice.contour));
  fmt::print("{}: {}\n", options.output, app::slice_summary_text(result));
  if (const std::string plan = app::slice_plan_text(result); !plan.empty()) fmt::print("{}\n", plan);
}

}  // namespace

void add_slice_command(CLI::App& app) {
  auto options = std::make_shared<SliceCommandOptions>();
  CLI::App* slice = app.add_subcommand("slice", "Slice a model (STL, 3MF, OBJ) into G-code");
  slice->footer(
      "Each layer extrudes the region its contour strategy picks (--contour); walls, skins, "
      "infill and a skirt follow the printer profile, and the G-code header carries the "
      "print-time estimate of the printer's motion model. Overhangs steeper than the "
      "material allows get support (--support), spans held at both ends within its bridge "
      "length are bridged, and the part may stand on a raft (--raft) or a brim (--brim); "
      "supports, bridges, brim and raft are marked ;TYPE:SUPPORT, SUPPORT-INTERFACE, BRIDGE, "
      "BRIM and RAFT. Layers are numbered from 0 in the file's ;LAYER:n comments, a raft's "
      "first.");
  slice->add_option("MODEL", options->slice.model.path, "the STL file (ASCII or binary)")
      ->required();
  slice->add_option("-o,--output", options->output, "the G-code file to write (required)")
      ->required();
  add_slice_options(*slice, options->slice);
  slice->callback([options] { run_slice(*options); });
}

}  // namespace host
