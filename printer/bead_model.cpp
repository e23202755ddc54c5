#include "printer/bead_model.h"

#include <cmath>
#include <numbers>

namespace printer {

double bead_area(double width, double height) {
  if (!(width > 0) || !(height > 0)) return 0;
  if (width <= height) return std::numbers::pi * width * width / 4;
  return (width - height) * height + std::numbers::pi * height * height / 4;
}

double filament_area(double filament_diameter) {
  if (!(filament_diameter > 0)) return 0;
  return std::numbers::pi * filament_diameter * filament_diameter / 4;
}

double filament_for_bead(double width, double height, double length, double filament_diameter,
                         double flow) {
  const double filament = filament_area(filament_diameter);
  if (!(filament > 0) || !(length > 0) || !(flow > 0)) return 0;
  return bead_area(width, height) * length / filament * flow;
}

double bead_width(double filament, double length, double height, double filament_diameter,
                  double flow) {
  if (!(filament > 0) || !(length > 0) || !(height > 0) || !(flow > 0)) return 0;
  const double area = filament * filament_area(filament_diameter) / (length * flow);
  const double round_strand = std::numbers::pi * height * height / 4;
  if (area <= round_strand) return std::sqrt(4 * area / std::numbers::pi);  // w <= h
  return (area - round_strand) / height + height;
}

double filament_weight(double filament, double filament_diameter, double density) {
  if (!(filament > 0) || !(density > 0)) return 0;
  return filament * filament_area(filament_diameter) * density / 1000.0;  // mm^3 -> cm^3
}

}  // namespace printer
