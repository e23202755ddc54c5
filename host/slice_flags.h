// The slice options on the command line: flags made from app/slice_options.h's table (each
// checked by the table, shown in the help with its range and default), and what a slice on a
// terminal shows while it runs (a progress bar per stage, the warnings on stderr).
#pragma once

#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "app/layer_choice.h"
#include "app/model.h"
#include "app/slice.h"
#include "app/slice_options.h"

namespace host {

// Adds every slice option of the table: the model's placement (not the MODEL argument
// itself), --printer, --material, the layers, --contour, --perimeters, --infill, --set, the
// supports, brim and raft. They are listed under `group` in the command's help ("" leaves
// them among its other options).
void add_slice_options(CLI::App& command, app::SliceOptions& options, const std::string& group = {});

// Adds the positional MODEL argument (required) and the placement flags to a subcommand.
void add_model_options(CLI::App& command, app::ModelOptions& options);
// Adds only the placement flags (--units, --scale, --height, --up, --rotate, --orient), listed
// under `group` in the help: for a command whose positional argument is not always a model
// (`mahost print FILE.gcode`).
void add_placement_options(CLI::App& command, app::ModelOptions& options, const std::string& group = {});

// Adds --adaptive, --tolerance and --max-layers, and with `print_time` --max-time, listed
// under `group`; returns them, for the caller's excludes.
std::vector<CLI::Option*> add_adaptive_options(CLI::App& command, app::AdaptiveRequest& request,
                                               const std::string& group = {},
                                               bool print_time = false);

// Loads the model (app::load_model) for a command on a terminal: what the loading did that a
// user should hear of (app::model_notes) on stderr as "mahost: LINE".
geometry::Mesh load_model_noting(const app::ModelOptions& options);

// A slice on a terminal: a progress bar per stage (host/progress.h), each warning on stderr
// as "mahost: LINE".
app::SliceEvents terminal_slice_events(const std::string& contour);

}  // namespace host
