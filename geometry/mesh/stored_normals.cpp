// Stored normals against the repaired part; see stored_normals.h.
#include "geometry/mesh/stored_normals.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <unordered_map>

namespace geometry {
namespace {

// A stored normal whose cosine with the repaired face's normal is below this points into the
// part. Exporters round normals to a few digits, so only a clear disagreement counts; a flipped
// normal has a cosine near -1.
constexpr double kAgreement = -1e-3;
// Needles and caps: twice the area below this share of the longest edge squared.
constexpr double kDegenerateRatio = 1e-5;

// A facet's three corners in a fixed order, whichever corner its vertex order starts at and
// whichever way it turns: the key the file's facet and the repaired face share.
using CornerKey = std::array<double, 9>;

CornerKey corner_key(Vec3 a, Vec3 b, Vec3 c) {
  std::array<Vec3, 3> corners{a, b, c};
  std::sort(corners.begin(), corners.end(), [](const Vec3& p, const Vec3& q) {
    if (p.x != q.x) return p.x < q.x;
    if (p.y != q.y) return p.y < q.y;
    return p.z < q.z;
  });
  return {corners[0].x, corners[0].y, corners[0].z, corners[1].x, corners[1].y,
          corners[1].z, corners[2].x, corners[2].y, corners[2].z};
}

struct CornerKeyHash {
  std::size_t operator()(const CornerKey& key) const {
    std::uint64_t h = 1469598103934665603ull;
    for (const double v : key) {
      h ^= std::bit_cast<std::uint64_t>(v == 0 ? 0.0 : v);  // -0 and +0 alike
      h *= 1099511628211ull;
    }
    return static_cast<std::size_t>(h ^ (h >> 29));
  }
};

bool has_direction(const Vec3& n) {
  return std::isfinite(n.x) && std::isfinite(n.y) && std::isfinite(n.z) &&
         (n.x != 0 || n.y != 0 || n.z != 0);
}

}  // namespace

StoredNormals compare_stored_normals(const std::vector<Triangle>& facets,
                                     const std::vector<Vec3>& normals, const Mesh& repaired) {
  StoredNormals result;
  const std::size_t count = std::min(facets.size(), normals.size());
  result.facets = count;
  std::unordered_map<CornerKey, Vec3, CornerKeyHash> outward;
  outward.reserve(repaired.faces.size());
  for (const auto& f : repaired.faces) {
    const Vec3 a = repaired.vertices[f[0]], b = repaired.vertices[f[1]], c = repaired.vertices[f[2]];
    outward.emplace(corner_key(a, b, c), cross(b - a, c - a));
  }
  for (std::size_t i = 0; i < count; ++i) {
    const Vec3& stored = normals[i];
    if (!has_direction(stored)) {
      ++result.no_direction;
      continue;
    }
    const Triangle& t = facets[i];
    const Vec3 ab = t.v[1] - t.v[0], ac = t.v[2] - t.v[0], bc = t.v[2] - t.v[1];
    const double longest = std::max({dot(ab, ab), dot(ac, ac), dot(bc, bc)});
    const Vec3 winding = cross(ab, ac);
    if (!(std::sqrt(dot(winding, winding)) > kDegenerateRatio * longest)) continue;
    const auto found = outward.find(corner_key(t.v[0], t.v[1], t.v[2]));
    if (found == outward.end()) continue;
    const Vec3& n = found->second;
    ++result.compared;
    const double cosine = dot(stored, n) / (std::sqrt(dot(stored, stored)) * std::sqrt(dot(n, n)));
    if (cosine < kAgreement) ++result.disagreeing;
  }
  return result;
}

}  // namespace geometry
