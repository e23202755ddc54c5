// Reading Wavefront OBJ files; see obj_io.h.
#include "geometry/mesh/obj_io.h"

#include <charconv>
#include <cmath>
#include <string>

#include <fmt/core.h>

#include "geometry/core/error.h"

namespace geometry {
namespace {

bool is_blank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v'; }

// The next blank-separated word of `line`, removed from it; empty at its end.
std::string_view next_word(std::string_view& line) {
  std::size_t start = 0;
  while (start < line.size() && is_blank(line[start])) ++start;
  std::size_t stop = start;
  while (stop < line.size() && !is_blank(line[stop])) ++stop;
  const std::string_view word = line.substr(start, stop - start);
  line.remove_prefix(stop);
  return word;
}

bool parse(std::string_view word, double& value) {
  if (word.size() > 1 && word[0] == '+') word.remove_prefix(1);
  const auto [end, error] = std::from_chars(word.data(), word.data() + word.size(), value);
  return !word.empty() && error == std::errc() && end == word.data() + word.size();
}

bool parse(std::string_view word, long long& value) {
  const auto [end, error] = std::from_chars(word.data(), word.data() + word.size(), value);
  return !word.empty() && error == std::errc() && end == word.data() + word.size();
}

}  // namespace

std::vector<Triangle> read_obj_text(std::string_view text, std::string_view name) {
  std::vector<Vec3> vertices;
  std::vector<Triangle> triangles;
  std::vector<std::size_t> corners;
  std::size_t line_number = 0;
  const auto fail = [&](const std::string& problem) {
    throw InputError(fmt::format("{}: {} (line {})", name, problem, line_number));
  };
  while (!text.empty()) {
    const std::size_t newline = text.find('\n');
    std::string_view line = text.substr(0, newline);
    text.remove_prefix(newline == std::string_view::npos ? text.size() : newline + 1);
    ++line_number;
    if (const std::size_t hash = line.find('#'); hash != std::string_view::npos) line = line.substr(0, hash);
    const std::string_view keyword = next_word(line);
    if (keyword == "v") {
      Vec3 p;
      for (double* c : {&p.x, &p.y, &p.z}) {
        const std::string_view word = next_word(line);
        if (!parse(word, *c)) {
          fail(word.empty() ? "a vertex needs three numbers"
                            : fmt::format("a vertex needs three numbers, not '{}'", word.substr(0, 24)));
        }
        if (!std::isfinite(*c)) fail("a vertex coordinate is NaN or infinite");
      }
      vertices.push_back(p);
    } else if (keyword == "f") {
      corners.clear();
      for (std::string_view word = next_word(line); !word.empty(); word = next_word(line)) {
        long long index = 0;
        const std::string_view vertex = word.substr(0, word.find('/'));
        if (!parse(vertex, index) || index == 0) {
          fail(fmt::format("a face corner must start with a vertex number, not '{}'", word.substr(0, 24)));
        }
        const long long count = static_cast<long long>(vertices.size());
        const long long at = index > 0 ? index - 1 : count + index;
        if (at < 0 || at >= count) {
          fail(fmt::format("face corner {} names vertex {}, but {} vertices are read so far",
                           corners.size() + 1, index, count));
        }
        corners.push_back(static_cast<std::size_t>(at));
      }
      if (corners.size() < 3) fail(fmt::format("a face needs three corners, not {}", corners.size()));
      for (std::size_t k = 1; k + 1 < corners.size(); ++k) {
        triangles.push_back({{vertices[corners[0]], vertices[corners[k]], vertices[corners[k + 1]]}});
      }
    }
  }
  if (triangles.empty()) {
    throw InputError(fmt::format("{}: OBJ with no faces ({} vertices): there is nothing to print",
                                 name, vertices.size()));
  }
  return triangles;
}

}  // namespace geometry
