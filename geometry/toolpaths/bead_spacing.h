// Bead spacing: how far apart side-by-side beads lie so that they fill a layer exactly, by
// the bead model the G-code writer extrudes with (printer/bead_model.h: the extrusion amounts
// come from the bead's cross-section). Slic3r's and PrusaSlicer's Flow::spacing.
//
// A bead w wide and h tall is a rounded rectangle in cross-section, area (w - h) h + pi h^2/4
// (a round strand, pi w^2 / 4, when w <= h). Beads s apart fill the layer, volume h per unit
// of area, when s h = area:
//   s = w - h (1 - pi/4)           (w > h; 0.407 mm for w = 0.45, h = 0.2)
// Each bead fills a strip s wide, its share; its rounded sides reach (w - s) / 2 beyond it,
// into its neighbours' beads, where a gap would otherwise be left.
//
// bead_spacing:           the share s of a bead w wide and h tall (mm).
// bead_width_for_spacing: the inverse, the width whose bead fills a share s at height h.
// Total: h <= 0 (no height: a flat-sided bead) gives s = w and w = s; w <= 0 or s <= 0
// gives 0.
#pragma once

namespace geometry {

double bead_spacing(double width, double height);

double bead_width_for_spacing(double spacing, double height);

}  // namespace geometry
