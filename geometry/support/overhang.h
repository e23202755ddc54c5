// Overhangs: the part of a layer's region that the layer below does not carry.
//
// A bead rests on the one below if at least half its width does, and a layer t thick whose
// wall leans at the overhang angle a from vertical reaches t tan(a) past the layer below; so
// a layer's reach is r = min(t tan(a), w/2), w the bead width (beyond w/2 the outer wall's
// centre line would be over air whatever the angle says).
//
// overhang(region, below, reach, min_area):
//   the pieces of `region` farther than `reach` from `below` (the steep part), slivers
//   narrower than 20 um (offset rounding, edges a few microns apart) and pieces of less than
//   `min_area` mm^2 dropped; each piece is then grown back to the whole of the region beyond
//   `below` within `reach` of it, so that what is supported or bridged is the full overhang,
//   from the edge of the layer below out (PrusaSlicer's contact areas do the same). An empty
//   `below` makes all of `region` overhang (a piece that starts in the air).
// Regions in mm (outer loops CCW, holes CW); the Clipper overload takes and gives
// geometry::clipper's paths. Empty region: empty result; reach <= 0: every part of region
// not over below.
#pragma once

#include <polyclipping/clipper.hpp>

#include "geometry/core/polygon.h"

namespace geometry {

double overhang_reach(double thickness, double angle_degrees, double bead_width);

Region overhang(const Region& region, const Region& below, double reach, double min_area);
ClipperLib::Paths overhang(const ClipperLib::Paths& region, const ClipperLib::Paths& below,
                           double reach, double min_area);

// The islands of `region` of at least `min_area` mm^2 (net of their holes).
ClipperLib::Paths without_specks(const ClipperLib::Paths& region, double min_area);

}  // namespace geometry
