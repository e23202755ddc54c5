// The printed part: what the simulated printer built, as a mesh a user can open next to the
// model (`mahost sim --printed-stl part.stl`).
//
// Input: a deposition record and the filament diameter (mm).
// Output: each layer's printed region (the union of its beads, sim/deposition.h) extruded
// from z - height to z: a closed, outward-oriented shell per layer (walls and both caps,
// holes included). Layers touch but are not merged, so the mesh is a stack of closed shells;
// its volume is the sum of the layers' area x height. An empty record gives an empty mesh.
#pragma once

#include "geometry/mesh/mesh.h"
#include "sim/deposition.h"

namespace sim {

geometry::Mesh printed_part(const DepositionRecord& record, double filament_diameter);

// One layer's region extruded between two heights (the caps triangulated), appended to mesh.
void append_prism(const geometry::Region& region, double z_bottom, double z_top,
                  geometry::Mesh& mesh);

}  // namespace sim
