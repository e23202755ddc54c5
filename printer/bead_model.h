// The bead model: how much filament a bead of a given width and height takes.
//
// A bead is a rounded rectangle in cross-section: a rectangle (w - h) x h with a half disc of
// diameter h on each side, area = (w - h) * h + pi * h^2 / 4 (Slic3r's flow model). A bead no
// wider than it is tall is a round strand of diameter w: area = pi * w^2 / 4. The filament
// length for a bead of length L is area * L / (pi * d^2 / 4) * flow.
// Units: mm, mm^2, mm^3. Total: non-positive sizes give 0.
#pragma once

namespace printer {

// Cross-section of a bead w wide and h tall, mm^2.
double bead_area(double width, double height);

// Cross-section of the filament, pi * d^2 / 4, mm^2.
double filament_area(double filament_diameter);

// Filament (mm) that lays a bead `length` mm long; `flow` is the material's multiplier.
double filament_for_bead(double width, double height, double length, double filament_diameter,
                         double flow = 1.0);

// The bead width that `filament` mm of filament gives over `length` mm at height h (the
// inverse of filament_for_bead; 0 when nothing was extruded).
double bead_width(double filament, double length, double height, double filament_diameter,
                  double flow = 1.0);

// Weight of `filament` mm of filament of diameter d and density rho (g/cm^3), grams.
double filament_weight(double filament, double filament_diameter, double density);

}  // namespace printer
