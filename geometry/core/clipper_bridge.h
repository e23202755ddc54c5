// Conversion between our millimetre Regions and Clipper 1's integer paths.
//
// Clipper works on 64-bit integers; we use 1 unit = 1 nm (kClipperScale units per mm), which
// keeps any bed-sized part inside Clipper's fast low range (|coordinate| < 2^30 units, 1073 mm).
#pragma once

#include <polyclipping/clipper.hpp>

#include "geometry/core/polygon.h"

namespace geometry {

inline constexpr double kClipperScale = 1e6;

// A length or coordinate already in units, rounded to the nearest unit, halves away from
// zero (std::llround's result) without the library call: v minus its truncation is exact
// for |v| < 2^53, so the comparisons with 0.5 decide as llround does. Inline: the offsets
// round every point they make.
inline ClipperLib::cInt rounded_units(double v) {
  const auto whole = static_cast<ClipperLib::cInt>(v);
  const double rest = v - static_cast<double>(whole);
  return rest >= 0.5 ? whole + 1 : (rest <= -0.5 ? whole - 1 : whole);
}

ClipperLib::IntPoint to_clipper(Vec2 p);
Vec2 from_clipper(const ClipperLib::IntPoint& p);

ClipperLib::Path to_clipper(const Loop& loop);
ClipperLib::Paths to_clipper(const Region& region);
Loop from_clipper(const ClipperLib::Path& path);
Region from_clipper(const ClipperLib::Paths& paths);

// Outer loops CCW and holes CW, from any PolyTree Clipper produced.
Region from_clipper(const ClipperLib::PolyTree& tree);

}  // namespace geometry
