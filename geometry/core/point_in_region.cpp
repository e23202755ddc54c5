#include "geometry/core/point_in_region.h"

#include <algorithm>

namespace geometry {

int winding_number(const Loop& loop, Vec2 p) {
  int w = 0;
  for (std::size_t i = 0, n = loop.size(); i < n; ++i) {
    const Vec2 a = loop[i], b = loop[i + 1 == n ? 0 : i + 1];
    // Wholly above or below p: the edge neither crosses p's ray nor holds p.
    if ((a.y < p.y && b.y < p.y) || (a.y > p.y && b.y > p.y)) continue;
    const double side = cross(b - a, p - a);
    if (side == 0 && distance_to_segment(p, a, b) == 0) {
      return signed_area(loop) >= 0 ? 1 : -1;
    }
    if (a.y <= p.y) {
      if (b.y > p.y && side > 0) ++w;
    } else if (b.y <= p.y && side < 0) {
      --w;
    }
  }
  return w;
}

bool point_in_region(const Region& region, Vec2 p) {
  int w = 0;
  for (const Loop& loop : region.loops) w += winding_number(loop, p);
  return w != 0;
}

namespace clipper {

bool point_in_region(const Paths& region, const IntPoint& p) {
  int winding = 0;
  for (const Path& loop : region) {
    const int at = ClipperLib::PointInPolygon(p, loop);
    if (at == -1) return true;
    if (at == 1) winding += ClipperLib::Orientation(loop) ? 1 : -1;
  }
  return winding != 0;
}

namespace {

// What the edge from `ip` to `next` does in ClipperLib::PointInPolygon's walk round its loop
// (Clipper 6.4.2, clipper.cpp; Hormann and Agathos): -1 when pt is on it, 1 when it toggles
// whether pt is inside, else 0. The same arithmetic, to the rounding of its doubles.
int edge_at(const IntPoint& ip, const IntPoint& next, const IntPoint& pt) {
  if (next.Y == pt.Y && (next.X == pt.X || (ip.Y == pt.Y && ((next.X > pt.X) == (ip.X < pt.X))))) {
    return -1;
  }
  if ((ip.Y < pt.Y) == (next.Y < pt.Y)) return 0;
  if (ip.X >= pt.X && next.X > pt.X) return 1;
  if (ip.X < pt.X && !(next.X > pt.X)) return 0;
  const double d = static_cast<double>(ip.X - pt.X) * static_cast<double>(next.Y - pt.Y) -
                   static_cast<double>(next.X - pt.X) * static_cast<double>(ip.Y - pt.Y);
  if (!d) return -1;
  return (d > 0) == (next.Y > ip.Y) ? 1 : 0;
}

}  // namespace

PointsInRegion::PointsInRegion(const Paths& region) {
  ClipperLib::cInt low = 0, high = -1;
  std::size_t count = 0;
  for (const Path& loop : region) {
    if (loop.size() < 3) continue;  // PointInPolygon's: no inside, no edge to be on
    for (const IntPoint& q : loop) {
      if (high < low) low = high = q.Y;
      low = std::min(low, q.Y);
      high = std::max(high, q.Y);
    }
    count += loop.size();
  }
  if (count == 0) return;
  y_low_ = low;
  y_span_ = high - low + 1;
  // About four edges a band; an edge goes into every band its heights reach.
  band_start_.assign(std::max<std::size_t>(count / 4, 1) + 1, 0);
  const auto each_edge = [&](auto&& f) {
    std::uint32_t number = 0;
    for (const Path& loop : region) {
      if (loop.size() < 3) continue;
      for (std::size_t i = 0; i < loop.size(); ++i) {
        f(loop[i], loop[i + 1 < loop.size() ? i + 1 : 0], number);
      }
      ++number;
    }
  };
  each_edge([&](const IntPoint& a, const IntPoint& b, std::uint32_t) {
    for (std::size_t k = band(std::min(a.Y, b.Y)), last = band(std::max(a.Y, b.Y)); k <= last; ++k) {
      ++band_start_[k + 1];
    }
  });
  for (std::size_t k = 1; k < band_start_.size(); ++k) band_start_[k] += band_start_[k - 1];
  edges_.resize(band_start_.back());
  std::vector<std::uint32_t> filled(band_start_.begin(), band_start_.end() - 1);
  each_edge([&](const IntPoint& a, const IntPoint& b, std::uint32_t loop) {
    for (std::size_t k = band(std::min(a.Y, b.Y)), last = band(std::max(a.Y, b.Y)); k <= last; ++k) {
      edges_[filled[k]++] = {a, b, loop};
    }
  });
  for (const Path& loop : region) {
    if (loop.size() >= 3) winding_.push_back(ClipperLib::Orientation(loop) ? 1 : -1);
  }
}

std::size_t PointsInRegion::band(ClipperLib::cInt y) const {
  const std::size_t bands = band_start_.size() - 1;
  return static_cast<std::size_t>(static_cast<__int128>(y - y_low_) * static_cast<__int128>(bands) / y_span_);
}

bool PointsInRegion::contains(const IntPoint& p) const {
  if (edges_.empty() || p.Y < y_low_ || p.Y - y_low_ >= y_span_) return false;
  const std::size_t k = band(p.Y);
  int winding = 0;
  bool inside = false;  // of the loop whose edges these are
  for (std::uint32_t i = band_start_[k], end = band_start_[k + 1]; i < end; ++i) {
    const Edge& e = edges_[i];
    const int at = edge_at(e.from, e.to, p);
    if (at == -1) return true;
    if (at == 1) inside = !inside;
    if (i + 1 == end || edges_[i + 1].loop != e.loop) {
      if (inside) winding += winding_[e.loop];
      inside = false;
    }
  }
  return winding != 0;
}

}  // namespace clipper

}  // namespace geometry
