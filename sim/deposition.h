// The deposition record: what the simulated printer laid down, so tests compare what was
// printed with what was planned and with the model (DESIGN.md §4).
//
// Input: every move the firmware executes that extrudes (E grows) while X or Y moves.
// Output: those moves in execution order; per-layer bead polygons; an STL of the beads.
// A layer is a Z level: moves at the same Z (to 1 µm) belong to one layer wherever they
// come in the print (a layer reprinted after a resume folds into the same layer). Layers are
// numbered from 0 in order of Z. Units: mm, mm/s.
//
// Bead width comes from the extruded volume through the bead model the G-code writer uses
// (printer/bead_model.h, inverted): a move of length L that feeds E mm of filament of
// diameter d at layer height h (this layer's Z minus the Z of the layer below, or Z itself for
// the first) lays a bead of cross-section E * pi d^2 / 4 / L, a rounded rectangle of width w.
#pragma once

#include <string>
#include <vector>

#include "geometry/core/polygon.h"

namespace sim {

struct DepositedMove {
  int layer = 0;              // index of the layer's Z among all Z levels, from 0
  double z = 0;               // mm
  geometry::Vec2 start, end;  // mm
  double e = 0;               // filament fed, mm (after the M221 flow factor)
  double feedrate = 0;        // mm/s, as commanded (after the M220 speed factor)
};

struct DepositionRecord {
  std::vector<DepositedMove> moves;  // in execution order
  std::vector<double> layer_z;       // Z of layer i, ascending

  // Adds a move and assigns its layer (renumbering later moves' layers when a new Z level
  // falls between existing ones).
  void add(double z, geometry::Vec2 start, geometry::Vec2 end, double e, double feedrate);
  double layer_height(int layer) const;
  double filament_used() const;  // mm of filament over all moves
};

// One bead: the segment widened to its bead width, a rectangle (4 corners, CCW).
struct Bead {
  geometry::Loop outline;
  double width = 0;
};

struct LayerBeads {
  double z = 0, height = 0;
  std::vector<Bead> beads;
};

// Beads per layer, in layer order. Moves of zero length or zero height give no bead.
std::vector<LayerBeads> bead_polygons(const DepositionRecord& record, double filament_diameter);

// The area one layer covers: the union of its beads (Clipper, non-zero fill).
geometry::Region printed_region(const LayerBeads& layer);

}  // namespace sim
