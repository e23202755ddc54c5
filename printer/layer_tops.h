// The layer tops a G-code file prints at: another slicer's layer plan, read back so that mahost
// can judge it (`analyze --boundaries`) or print the same boundaries with its own contours.
//
// Input: G-code text as CuraEngine, PrusaSlicer, Slic3r or mahost write it. Output: the layer
// tops in mm, ascending: every height at which the file extrudes (a G0/G1 that moves X or Y
// and feeds filament forward), in the order printed. What the three peers write at a layer
// change, as run here (CuraEngine 4.13, PrusaSlicer 2.5, Slic3r 1.3):
//   CuraEngine: the Z move ("G0 F600 X.. Y.. Z0.6") at the end of the layer below, then
//               ";LAYER:n"; an empty layer keeps its ";LAYER:n" and extrudes nothing;
//   PrusaSlicer: ";LAYER_CHANGE", ";Z:0.6", ";HEIGHT:0.3", then "G1 Z.6 F..";
//   Slic3r:      only "G1 Z0.650 F7800.000" (a comment only with --gcode-comments);
//   mahost:      ";LAYER:n", ";Z:z", ";HEIGHT:t", then the Z move.
// So the comments are not what is read (they differ, Slic3r has none, an empty Cura layer has
// one); the heights that filament is laid at are, which all four share. Z-hop travels and the
// start G-code's moves lay nothing and do not count; the moves are read by
// printer/gcode_interpreter.h's rules (modes, units, G92, G28, firmware retraction).
// Heights closer than 0.5 um are one layer (they are written to 1 um). A mahost file printed
// on a raft (its header's "; raft: N layers, L mm under the part") gives the part's layers,
// as on the bed: the raft's left out, L taken off the rest.
// Throws ConfigError naming `name` when the file extrudes nothing, or goes back down to a
// height below one it printed at (several objects printed one after another, or a spiral
// vase, whose Z rises along every move: neither is a stack of layers).
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace printer {

std::vector<double> layer_tops_from_gcode(std::string_view text, const std::string& name);

// A list of layer tops, mm: one per line or separated by commas, blanks ignored, '#' starts
// a comment. Throws ConfigError naming `name` and the line of anything that is not a positive
// number, of tops that do not rise, and of an empty list.
std::vector<double> layer_tops_from_list(std::string_view text, const std::string& name);

// The --boundaries argument: a path to a file (G-code, or a list as above), else a comma list
// ("0.3,0.5,0.7"). Throws ConfigError for a file that cannot be read, or for an argument that
// is neither a file nor a list of numbers (naming it).
std::vector<double> read_layer_tops(const std::string& argument);

// True when `text` reads as G-code rather than a list of numbers: some line begins with a G
// or M command or a ';' comment.
bool looks_like_gcode(std::string_view text);

}  // namespace printer
