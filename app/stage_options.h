// The profiles' settings as the stages take them: the toolpaths', the supports' (boxes in the
// part's frame: the part is centred on the bed), the raft's, what --orient auto weighs, and
// the unsupported-extrusion check's.
#pragma once

#include "geometry/mesh/orientation.h"
#include "geometry/support/support_plan.h"
#include "geometry/toolpaths/toolpath_plan.h"
#include "printer/profile.h"
#include "sim/unsupported_extrusion.h"

namespace app {

geometry::ToolpathOptions toolpath_options(const printer::PrinterProfile& machine);
geometry::SupportOptions support_options(const printer::Profiles& profiles);
geometry::RaftOptions raft_options(const printer::PrinterProfile& machine);

// How far a raft lifts the part: its layers and the air gap, mm (0 without a raft).
double raft_height(const printer::RaftSettings& raft);

// What a column of support costs on this printer, as --orient auto weighs the resting faces
// (geometry/mesh/orientation.h): its body's lines (bead width over the spacing, twice that
// for a grid), its interface (thickness and density) and its contact gaps.
geometry::SupportCost support_cost(const printer::PrinterProfile& machine);

// The unsupported-extrusion check's parameters for a print with these profiles: the
// filament, the material's bridge length, and as the air a bead may sag across the larger of
// the support's top and bottom contact distances (sim/unsupported_extrusion.h).
sim::SupportCheckOptions support_check_options(const printer::Profiles& profiles);

}  // namespace app
