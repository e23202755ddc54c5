#include "geometry/slab.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

#include "geometry/clipper_bridge.h"

namespace geometry {

namespace {

using ClipperLib::cInt;
using ClipperLib::IntPoint;

// Keeps the part of a convex polygon on the side where side * (z - plane) >= 0.
std::vector<Vec3> clip_half(const std::vector<Vec3>& in, double plane, double side) {
  const auto keep = [&](double z) { return side * (z - plane); };
  std::vector<Vec3> out;
  if (in.empty()) return out;
  out.reserve(in.size() + 1);
  for (std::size_t i = 0, n = in.size(); i < n; ++i) {
    const Vec3 a = in[i], b = in[(i + 1) % n];
    const double ka = keep(a.z), kb = keep(b.z);
    if (ka >= 0) out.push_back(a);
    if ((ka < 0 && kb > 0) || (ka > 0 && kb < 0)) {
      const double s = ka / (ka - kb);
      Vec3 p = a + s * (b - a);
      p.z = plane;  // exactly, so later tests against the plane are exact
      out.push_back(p);
    }
  }
  return out;
}

double cross_z(IntPoint o, IntPoint a, IntPoint b) {
  // Coordinates stay below 2^31 units (2 m), so the int64 products are exact.
  return static_cast<double>((a.X - o.X) * (b.Y - o.Y) - (a.Y - o.Y) * (b.X - o.X));
}

// Andrew's monotone chain: the convex hull, counter-clockwise, no collinear points.
ClipperLib::Path convex_hull(std::vector<IntPoint> points) {
  std::sort(points.begin(), points.end(), [](IntPoint a, IntPoint b) {
    return a.X < b.X || (a.X == b.X && a.Y < b.Y);
  });
  points.erase(std::unique(points.begin(), points.end()), points.end());
  if (points.size() < 3) return {points.begin(), points.end()};
  ClipperLib::Path hull(2 * points.size());
  std::size_t k = 0;
  for (const IntPoint& p : points) {
    while (k >= 2 && cross_z(hull[k - 2], hull[k - 1], p) <= 0) --k;
    hull[k++] = p;
  }
  for (std::size_t i = points.size() - 1, lower = k + 1; i-- > 0;) {
    while (k >= lower && cross_z(hull[k - 2], hull[k - 1], points[i]) <= 0) --k;
    hull[k++] = points[i];
  }
  hull.resize(k - 1);
  return hull;
}

}  // namespace

std::vector<Vec3> clip_to_slab(std::span<const Vec3> polygon, double z_lo, double z_hi) {
  std::vector<Vec3> piece(polygon.begin(), polygon.end());
  piece = clip_half(piece, z_lo, 1.0);
  piece = clip_half(piece, z_hi, -1.0);
  std::vector<Vec3> merged;
  merged.reserve(piece.size());
  for (const Vec3& p : piece) {
    if (merged.empty() || p.x != merged.back().x || p.y != merged.back().y ||
        p.z != merged.back().z) {
      merged.push_back(p);
    }
  }
  while (merged.size() > 1 && merged.front().x == merged.back().x &&
         merged.front().y == merged.back().y && merged.front().z == merged.back().z) {
    merged.pop_back();
  }
  if (merged.size() < 3) return {};
  const bool on_lo = std::all_of(merged.begin(), merged.end(), [&](Vec3 p) { return p.z == z_lo; });
  const bool on_hi = std::all_of(merged.begin(), merged.end(), [&](Vec3 p) { return p.z == z_hi; });
  if (on_lo || on_hi) return {};
  return merged;
}

Slab slab_of(const Mesh& mesh, std::span<const std::uint32_t> faces, double z_lo, double z_hi) {
  Slab slab{z_lo, z_hi, {}};
  if (!(z_lo < z_hi)) return slab;
  slab.facets.reserve(faces.size());
  for (std::uint32_t f : faces) {
    if (f >= mesh.faces.size()) continue;
    const auto& face = mesh.faces[f];
    if (face[0] >= mesh.vertices.size() || face[1] >= mesh.vertices.size() ||
        face[2] >= mesh.vertices.size()) {
      continue;
    }
    const std::array<Vec3, 3> corners{mesh.vertices[face[0]], mesh.vertices[face[1]],
                                      mesh.vertices[face[2]]};
    const double lo = std::min({corners[0].z, corners[1].z, corners[2].z});
    const double hi = std::max({corners[0].z, corners[1].z, corners[2].z});
    if (hi < z_lo || lo > z_hi) continue;
    std::vector<Vec3> piece = clip_to_slab(corners, z_lo, z_hi);
    if (!piece.empty()) slab.facets.push_back(std::move(piece));
  }
  return slab;
}

Slab slab_of(const LayerStack& stack, std::size_t layer) {
  if (layer >= stack.size()) return {};
  const Layer& bounds = stack.layers()[layer];
  const std::vector<std::uint32_t> faces = stack.faces_between(bounds.z_lo, bounds.z_hi);
  return slab_of(stack.mesh(), faces, bounds.z_lo, bounds.z_hi);
}

Region slab_footprint(const Slab& slab, double margin) {
  // The octagon circumscribes the disc of radius `margin`, so every grown facet contains all
  // points within `margin` of the facet's projection, and none farther than 1.09 * margin.
  const double radius = std::max(margin, 0.0) / std::cos(std::numbers::pi / 8) * kClipperScale;
  std::array<IntPoint, 8> octagon;
  for (int k = 0; k < 8; ++k) {
    const double angle = std::numbers::pi / 8 + k * std::numbers::pi / 4;
    octagon[k] = {static_cast<cInt>(std::ceil(radius * std::cos(angle) - 0.5)),
                  static_cast<cInt>(std::ceil(radius * std::sin(angle) - 0.5))};
  }
  ClipperLib::Clipper clipper;
  std::vector<IntPoint> grown;
  for (const auto& facet : slab.facets) {
    grown.clear();
    for (const Vec3& v : facet) {
      const IntPoint p = to_clipper(Vec2{v.x, v.y});
      if (radius > 0) {
        for (const IntPoint& o : octagon) grown.push_back({p.X + o.X, p.Y + o.Y});
      } else {
        grown.push_back(p);
      }
    }
    ClipperLib::Path hull = convex_hull(std::move(grown));
    grown = {};
    if (hull.size() >= 3) clipper.AddPath(hull, ClipperLib::ptSubject, true);
  }
  ClipperLib::PolyTree tree;
  clipper.Execute(ClipperLib::ctUnion, tree, ClipperLib::pftNonZero, ClipperLib::pftNonZero);
  return from_clipper(tree);
}

}  // namespace geometry
