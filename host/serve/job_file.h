// A G-code file as `mahost serve` prints and draws it: the commands the job streams
// (printer::GcodeFile, read from disk a block at a time), the printer state at each layer
// start, and each layer's paths for the page's drawing.
//
// Input: the file, checked once when a job starts. Output: immutable after load, so the
// printing thread and the HTTP threads share it without locks; the drawing of a layer is
// made on request, from the layer's commands alone (read from the file). Units: mm, bytes.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "printer/gcode_file.h"
#include "printer/print_state.h"

namespace host::serve {

struct JobFile {
  printer::GcodeFile gcode;
  std::uint64_t bytes = 0;
  // The state before each layer's first command (index as gcode.layers).
  std::vector<printer::PrintState> layer_start;
  // Where the file extrudes inside its layers (a prime line before the first layer mark is
  // left out): {min x, min y, max x, max y}; all 0 for a file that extrudes nothing there.
  double min_x = 0, min_y = 0, max_x = 0, max_y = 0;
};

// How serve reads the G-code it is given (uploads, and the files it prints): a refused line is
// to be fixed and the file uploaded again, as there is no --force to give from a browser.
inline constexpr printer::GcodeReading kUploadedGcode{.otherwise = "then upload the file again"};

// Parses `bytes` as printer::parse_gcode does (same commands, same errors, named `name`) and
// fills the rest. Throws printer::ConfigError for text that is not G-code or has no command.
JobFile load_job_file(std::string_view bytes, const std::string& name);
// The same checked from a file a piece at a time, kept as printer::read_gcode_file keeps it (an
// index of blocks: a file of 100 MiB holds neither its text nor its commands); ConfigError
// naming it when it cannot be read.
JobFile read_job_file(const std::string& path);

// One straight move of a layer: extruding (E grows while X or Y moves) or travel.
struct LayerMove {
  float x0, y0, x1, y1;
  bool extrudes;
  std::uint32_t command;  // index of the command that makes it, in the file
};

// The moves of layer `index` (0-based, as gcode.layers) from its start state; empty for an
// index outside the file's layers. Throws printer::GcodeFileChanged for a file changed on disk.
std::vector<LayerMove> layer_moves(const JobFile& file, int index);

// An SVG path ("M1.00 2.00L3.00 4.00...") of the moves that extrude (or, `extrudes` false,
// travel) and come from commands in [from_command, to_command); consecutive moves are
// joined. Coordinates to 0.01 mm, Y as in the file (the page flips it).
std::string svg_path(const std::vector<LayerMove>& moves, bool extrudes, std::size_t from_command,
                     std::size_t to_command);

}  // namespace host::serve
