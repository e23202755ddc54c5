// libFuzzer entry for the STL reader (geometry/mesh/stl_io.cpp): any bytes must give facets with
// finite corners or one geometry::InputError with a one-line message naming the file. Any
// other exception, a crash, a sanitizer report or a hang is a bug.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string_view>
#include <vector>

#include "geometry/mesh/stl_io.h"

namespace {

void check(std::string_view bytes, bool keep_normals) {
  try {
    std::vector<geometry::Vec3> normals;
    geometry::StlReadOptions options;
    if (keep_normals) options.stored_normals = &normals;
    const auto facets = geometry::read_stl_bytes(bytes, "fuzz.stl", options);
    if (keep_normals && normals.size() != facets.size()) std::abort();
    if (facets.empty()) std::abort();  // no facets must be refused, not returned
    for (const geometry::Triangle& t : facets) {
      for (const geometry::Vec3& p : t.v) {
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) std::abort();
      }
    }
  } catch (const geometry::InputError& e) {
    const std::string_view message = e.what();
    if (message.rfind("fuzz.stl: ", 0) != 0) std::abort();
    if (message.find('\n') != std::string_view::npos) std::abort();
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  check(bytes, true);
  check(bytes, false);
  return 0;
}
