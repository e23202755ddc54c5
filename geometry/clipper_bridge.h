// Conversion between our millimetre Regions and Clipper 1's integer paths.
//
// Clipper works on 64-bit integers; we use 1 unit = 1 nm (kClipperScale units per mm), which
// keeps any bed-sized part inside Clipper's fast low range (|coordinate| < 2^30 units, 1073 mm).
#pragma once

#include <polyclipping/clipper.hpp>

#include "geometry/polygon.h"

namespace geometry {

inline constexpr double kClipperScale = 1e6;

ClipperLib::IntPoint to_clipper(Vec2 p);
Vec2 from_clipper(const ClipperLib::IntPoint& p);

ClipperLib::Path to_clipper(const Loop& loop);
ClipperLib::Paths to_clipper(const Region& region);
Loop from_clipper(const ClipperLib::Path& path);
Region from_clipper(const ClipperLib::Paths& paths);

// Outer loops CCW and holes CW, from any PolyTree Clipper produced.
Region from_clipper(const ClipperLib::PolyTree& tree);

}  // namespace geometry
