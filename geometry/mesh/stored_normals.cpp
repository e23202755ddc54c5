// Stored normals against the repaired part; see stored_normals.h.
#include "geometry/mesh/stored_normals.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>

#include "geometry/core/number_table.h"
#include "geometry/mesh/corner_key.h"

namespace geometry {
namespace {

// A stored normal whose cosine with the repaired face's normal is below this points into the
// part. Exporters round normals to a few digits, so only a clear disagreement counts; a flipped
// normal has a cosine near -1.
constexpr double kAgreement = -1e-3;
// Needles and caps: twice the area below this share of the longest edge squared.
constexpr double kDegenerateRatio = 1e-5;

// A facet by the places of its corners (numbers of places, below), in increasing order:
// whichever corner its vertex order starts at and whichever way it turns, the key the file's
// facet and the repaired face share.
using PlaceKey = std::array<std::uint32_t, 3>;

PlaceKey place_key(std::uint32_t a, std::uint32_t b, std::uint32_t c) {
  if (a > b) std::swap(a, b);
  if (b > c) std::swap(b, c);
  if (a > b) std::swap(a, b);
  return {a, b, c};
}

struct PlaceKeyHash {
  std::size_t operator()(const PlaceKey& k) const {
    return CornerHash{}(CornerKey{k[0], k[1], k[2]});
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
  // The places the repaired mesh's corners lie at, each numbered by its first vertex there
  // (a vertex split apart by the repair lies where its other copy does).
  const std::vector<Vec3>& vertices = repaired.vertices;
  const auto key_of_vertex = [&](std::uint32_t v) { return corner_key(vertices[v]); };
  NumberTable<CornerKey, CornerHash> places(vertices.size());
  std::vector<std::uint32_t> place(vertices.size());
  for (std::uint32_t v = 0; v < vertices.size(); ++v) {
    place[v] = places.find_or_insert(corner_key(vertices[v]), v, key_of_vertex);
  }
  // The repaired faces by their corners' places, the first face of each.
  const auto key_of_face = [&](std::uint32_t f) {
    const auto& face = repaired.faces[f];
    return place_key(place[face[0]], place[face[1]], place[face[2]]);
  };
  NumberTable<PlaceKey, PlaceKeyHash> faces(repaired.faces.size());
  for (std::uint32_t f = 0; f < repaired.faces.size(); ++f) faces.find_or_insert(key_of_face(f), f, key_of_face);

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
    std::array<std::uint32_t, 3> at{};
    bool placed = true;
    for (int k = 0; k < 3 && placed; ++k) {
      at[k] = places.find(corner_key(t.v[k]), key_of_vertex);
      placed = at[k] != decltype(places)::kNone;
    }
    if (!placed) continue;
    const std::uint32_t found = faces.find(place_key(at[0], at[1], at[2]), key_of_face);
    if (found == decltype(faces)::kNone) continue;
    const auto& face = repaired.faces[found];
    const Vec3 a = vertices[face[0]], b = vertices[face[1]], c = vertices[face[2]];
    const Vec3 n = cross(b - a, c - a);
    ++result.compared;
    const double cosine = dot(stored, n) / (std::sqrt(dot(stored, stored)) * std::sqrt(dot(n, n)));
    if (cosine < kAgreement) ++result.disagreeing;
  }
  return result;
}

}  // namespace geometry
