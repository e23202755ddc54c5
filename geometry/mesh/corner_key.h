// A mesh corner's exact coordinates as a hash key, for merging and matching corners that lie
// at the same place (repair.h, stored_normals.h): the bits of x, y and z, with -0.0 and 0.0
// the same corner. The hash spreads a key over the low bits, as NumberTable needs.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>

#include "geometry/mesh/mesh.h"

namespace geometry {

struct CornerKey {
  std::uint64_t x, y, z;
  bool operator==(const CornerKey&) const = default;
};

struct CornerHash {
  std::size_t operator()(const CornerKey& k) const {
    std::uint64_t h = k.x * 0x9E3779B97F4A7C15ull;
    h ^= (k.y + 0x632BE59BD9B4E019ull + (h << 6) + (h >> 2));
    h ^= (k.z + 0x85157AF5ull + (h << 6) + (h >> 2));
    return static_cast<std::size_t>(h ^ (h >> 29));
  }
};

inline std::uint64_t coordinate_bits(double value) {
  if (value == 0) value = 0;  // folds -0.0 into +0.0
  std::uint64_t out;
  std::memcpy(&out, &value, sizeof out);
  return out;
}

inline CornerKey corner_key(const Vec3& v) {
  return {coordinate_bits(v.x), coordinate_bits(v.y), coordinate_bits(v.z)};
}

}  // namespace geometry
