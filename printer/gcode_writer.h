// The G-code writer: layers of toolpaths to a Marlin-flavour program (DESIGN.md §1).
//
// Input: every layer's toolpaths in the part's frame (part centred on the origin, mm), the
// printer and material profiles. Output, streamed: a header comment (print-time estimate from
// the motion model run over the whole program, filament length and weight, layer count), the
// heating (M140/M104, then M190/M109 at the first-layer temperatures; M116 instead where the
// profile's firmware waits so), the profile's start G-code with its placeholders expanded,
// G90 and M82 or M83, then per layer:
//   ;LAYER:<n>  ;Z:<z>  ;HEIGHT:<t>  M73 P<percent> R<minutes left>  G92 E0   (the host keys
//   on ;LAYER:; t is the layer's own thickness, z_hi - z_lo: layers may differ; M73 only for
//   a firmware that has it)
//   the regular temperatures after the first layer, the fan (M106/M107) per the material,
//   ;TYPE:<role> before each change of feature, travels (G0) with retraction and z-hop before
//   paths marked retract_before, extrusions (G1 ... E) from the bead model at that layer's
//   own thickness and the path's width, the feature's speed (first-layer speed on layer 0);
//   bridges with the material's bridge flow and, around them, its bridge fan (M106/M107);
// then M107 and the end G-code. Toolpaths move to the bed centre. X, Y, Z are written to
// 0.001 mm, E to 0.00001 mm, F to 1 mm/min; the estimate runs over these written values, so
// re-reading the program gives the same time.
// Throws ConfigError if the toolpaths do not fit the build volume (with both sizes).
#pragma once

#include <cstddef>
#include <functional>
#include <ostream>
#include <string>
#include <vector>

#include "geometry/toolpaths/toolpaths.h"
#include "printer/profile.h"

namespace printer {

struct GcodeOptions {
  double layer_height = 0.2;         // the {layer_height} placeholder and the header, mm
  std::vector<std::string> notes;    // extra header lines ("model: bunny.stl", "contour: ma")
  std::string input_filename_base;   // the model's name without extension (PrusaSlicer's placeholder)
};

struct GcodeSummary {
  std::size_t layers = 0;
  double print_seconds = 0;   // motion and dwell time, as PrintClock reads the program
  double filament_mm = 0;     // filament laid in beads (retractions excluded)
  double support_filament_mm = 0;  // of it, support, support interface and raft
  double filament_grams = 0;
  std::size_t bytes = 0;      // size of the program written
  std::size_t lines = 0;
  // When each layer starts (its ;LAYER: line), s from the program's start, as the M73 lines
  // count it: layer k prints from layer_starts[k] to layer_starts[k + 1] (the last to
  // print_seconds, with the end G-code).
  std::vector<double> layer_starts;
  // Layer k's print time from layer_starts, s.
  double layer_seconds(std::size_t k) const {
    return (k + 1 < layer_starts.size() ? layer_starts[k + 1] : print_seconds) - layer_starts[k];
  }
};

// Called after each layer is written with the count written so far.
using LayersWritten = std::function<void(std::size_t done)>;

// `timed`: time_gcode's summary of these layers, profiles and options, where the program was
// timed already (the clock does not run again; the text is the same).
GcodeSummary write_gcode(std::ostream& out, const std::vector<geometry::LayerToolpaths>& layers,
                         const Profiles& profiles, const GcodeOptions& options = {},
                         const LayersWritten& on_layer = {}, const GcodeSummary* timed = nullptr);

// The same summary without the text (bytes and lines 0): the program run through the clock
// alone, for estimates of layer stacks that are not written.
GcodeSummary time_gcode(const std::vector<geometry::LayerToolpaths>& layers,
                        const Profiles& profiles, const GcodeOptions& options = {});

// The same into a file; a file that cannot be written throws ConfigError naming it.
GcodeSummary write_gcode_file(const std::string& path,
                              const std::vector<geometry::LayerToolpaths>& layers,
                              const Profiles& profiles, const GcodeOptions& options = {},
                              const LayersWritten& on_layer = {}, const GcodeSummary* timed = nullptr);

// "1 h 23 min 45 s", "12 min 5 s", "40 s".
std::string format_duration(double seconds);

}  // namespace printer
