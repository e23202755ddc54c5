// STL reading and writing; see stl_io.h. No CGAL here, so the fuzz build stays quick.
#include "geometry/mesh/stl_io.h"

#include <algorithm>
#include <bit>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <limits>
#include <memory>

#include <fmt/core.h>

#include "base/text.h"
#include "geometry/mesh/file_bytes.h"

namespace geometry {
namespace {

using base::trim;

constexpr std::size_t kHeaderBytes = 80;
constexpr std::size_t kBinaryPrefix = 84;  // header + facet count
constexpr std::size_t kFacetBytes = 50;    // normal, 3 corners (12 float32), 2 attribute bytes

[[noreturn]] void fail(std::string_view name, const std::string& problem) {
  throw InputError(fmt::format("{}: {}", name, problem));
}

// A token from the file as it may appear in a one-line message: short, printable.
std::string quoted(std::string_view token) {
  std::string out = "'";
  const std::size_t shown = std::min<std::size_t>(token.size(), 24);
  for (std::size_t i = 0; i < shown; ++i) {
    const auto c = static_cast<unsigned char>(token[i]);
    if (c >= 0x20 && c < 0x7f) {
      out += static_cast<char>(c);
    } else {
      out += fmt::format("\\x{:02x}", c);
    }
  }
  if (token.size() > shown) out += "...";
  return out + "'";
}

bool iequals(std::string_view a, std::string_view b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    char x = a[i], y = b[i];
    if (x >= 'A' && x <= 'Z') x = static_cast<char>(x - 'A' + 'a');
    if (y >= 'A' && y <= 'Z') y = static_cast<char>(y - 'A' + 'a');
    if (x != y) return false;
  }
  return true;
}

bool is_space(char c) {
  return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\f' || c == '\v';
}

// `where` is appended to the message: "" for binary files, " (line N)" for ASCII.
void require_finite(std::string_view name, const Triangle& t, std::size_t facet,
                    std::string_view where) {
  for (const Vec3& p : t.v) {
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) {
      fail(name, fmt::format("facet {} has a corner that is NaN or infinite{}", facet, where));
    }
  }
}

std::uint32_t read_u32(const char* p) {
  const auto* b = reinterpret_cast<const unsigned char*>(p);
  return static_cast<std::uint32_t>(b[0]) | static_cast<std::uint32_t>(b[1]) << 8 |
         static_cast<std::uint32_t>(b[2]) << 16 | static_cast<std::uint32_t>(b[3]) << 24;
}

double read_f32(const char* p) { return std::bit_cast<float>(read_u32(p)); }

Vec3 read_vec3(const char* p) { return {read_f32(p), read_f32(p + 4), read_f32(p + 8)}; }

std::vector<Triangle> read_binary(std::string_view bytes, std::string_view name,
                                  const StlReadOptions& options) {
  const std::size_t count = read_u32(bytes.data() + kHeaderBytes);
  if (count == 0) fail(name, "binary STL with no facets: there is nothing to print");
  std::vector<Triangle> facets(count);
  if (options.stored_normals) options.stored_normals->resize(count);
  const char* p = bytes.data() + kBinaryPrefix;
  for (std::size_t i = 0; i < count; ++i, p += kFacetBytes) {
    Triangle& t = facets[i];
    t.v = {read_vec3(p + 12), read_vec3(p + 24), read_vec3(p + 36)};
    require_finite(name, t, i + 1, "");
    if (options.stored_normals) (*options.stored_normals)[i] = read_vec3(p);
  }
  return facets;
}

// A cursor over ASCII STL text that knows its line number.
class AsciiCursor {
 public:
  AsciiCursor(std::string_view text, std::string_view name) : text_(text), name_(name) {}

  // The next whitespace-separated token; empty at the end of the text.
  std::string_view token() {
    skip_space();
    token_line_ = line_;
    const std::size_t start = pos_;
    while (pos_ < text_.size() && !is_space(text_[pos_])) ++pos_;
    return text_.substr(start, pos_ - start);
  }

  // What is left of the current line (the name after solid / endsolid), trimmed.
  std::string_view rest_of_line() {
    const std::size_t start = pos_;
    while (pos_ < text_.size() && text_[pos_] != '\n') ++pos_;
    return trim(text_.substr(start, pos_ - start));
  }

  bool at_end() {
    skip_space();
    return pos_ == text_.size();
  }

  std::size_t line() const { return token_line_; }

  [[noreturn]] void fail_here(const std::string& problem) const {
    fail(name_, fmt::format("{} (line {})", problem, token_line_));
  }

  void expect(std::string_view keyword, std::string_view context) {
    const std::string_view t = token();
    if (iequals(t, keyword)) return;
    if (t.empty()) fail_here(fmt::format("file ends inside {}: truncated", context));
    fail_here(fmt::format("expected '{}' in {}, found {}", keyword, context, quoted(t)));
  }

  double number(std::string_view what, std::string_view context) {
    std::string_view t = token();
    if (t.empty()) fail_here(fmt::format("file ends inside {}: truncated", context));
    std::string_view digits = t;
    // from_chars refuses a leading '+', which some exporters write.
    if (digits.size() > 1 && digits[0] == '+' && digits[1] != '-') digits.remove_prefix(1);
    double value = 0;
    const auto [end, error] =
        std::from_chars(digits.data(), digits.data() + digits.size(), value);
    if (error == std::errc::result_out_of_range) {
      value = std::numeric_limits<double>::infinity();
    } else if (error != std::errc() || end != digits.data() + digits.size()) {
      fail_here(fmt::format("{} needs three numbers, found {} in {}", what, quoted(t), context));
    }
    return value;
  }

 private:
  void skip_space() {
    while (pos_ < text_.size() && is_space(text_[pos_])) {
      if (text_[pos_] == '\n') ++line_;
      ++pos_;
    }
  }

  std::string_view text_;
  std::string_view name_;
  std::size_t pos_ = 0;
  std::size_t line_ = 1;
  std::size_t token_line_ = 1;
};

// "endsolid" may repeat the name of its "solid", leave it out, or shorten it to its first
// words (several exporters do); any other name means two files were spliced or one was cut.
bool names_agree(std::string_view solid_name, std::string_view end_name) {
  const auto word_prefix = [](std::string_view whole, std::string_view part) {
    return whole.substr(0, part.size()) == part &&
           (whole.size() == part.size() || is_space(whole[part.size()]));
  };
  return end_name.empty() || word_prefix(solid_name, end_name) ||
         word_prefix(end_name, solid_name);
}

// After "endsolid": its name checked against the solid's (`solid_name` of `solid_line`), then
// true at the end of the file, else the next solid's "solid" line read into solid_name and
// solid_line.
bool end_of_solid(AsciiCursor& in, std::string_view& solid_name, std::size_t& solid_line) {
  const std::string_view end_name = in.rest_of_line();
  if (!names_agree(solid_name, end_name)) {
    in.fail_here(fmt::format("'endsolid {}' does not match 'solid {}' of line {}",
                             std::string(end_name).substr(0, 60),
                             std::string(solid_name).substr(0, 60), solid_line));
  }
  if (in.at_end()) return true;
  // Some exporters write several solids into one file: read them all.
  const std::string_view next = in.token();
  if (!iequals(next, "solid")) {
    in.fail_here(fmt::format("expected end of file or 'solid' after 'endsolid', found {}",
                             quoted(next)));
  }
  solid_name = in.rest_of_line();
  solid_line = in.line();
  return false;
}

// The three "vertex" lines of facet `index` and its "endloop".
Triangle facet_corners(AsciiCursor& in, std::size_t index, const std::string& context) {
  Triangle tri;
  for (int corner = 0; corner < 3; ++corner) {
    const std::string_view v = in.token();
    if (iequals(v, "endloop")) {
      in.fail_here(fmt::format("facet {} has only {} vertices; an STL facet has 3", index,
                               corner));
    }
    if (!iequals(v, "vertex")) {
      if (v.empty()) in.fail_here(fmt::format("file ends inside {}: truncated", context));
      in.fail_here(fmt::format("expected 'vertex' in {}, found {}", context, quoted(v)));
    }
    tri.v[corner].x = in.number("'vertex'", context);
    tri.v[corner].y = in.number("'vertex'", context);
    tri.v[corner].z = in.number("'vertex'", context);
  }
  const std::string_view close = in.token();
  if (iequals(close, "vertex")) {
    in.fail_here(fmt::format("facet {} has more than 3 vertices; an STL facet is a triangle",
                             index));
  }
  if (!iequals(close, "endloop")) {
    if (close.empty()) in.fail_here(fmt::format("file ends inside {}: truncated", context));
    in.fail_here(fmt::format("expected 'endloop' in {}, found {}", context, quoted(close)));
  }
  return tri;
}

// Facet `index` after its "facet" keyword, to its "endfacet": its corners, checked finite, and
// the normal the file stores for it (`stored`).
Triangle read_facet(AsciiCursor& in, std::size_t index, std::string_view name, Vec3& stored) {
  const std::size_t facet_line = in.line();
  const std::string context = fmt::format("facet {}", index);
  in.expect("normal", context);
  stored.x = in.number("'facet normal'", context);
  stored.y = in.number("'facet normal'", context);
  stored.z = in.number("'facet normal'", context);
  in.expect("outer", context);
  in.expect("loop", context);
  const Triangle tri = facet_corners(in, index, context);
  in.expect("endfacet", context);
  require_finite(name, tri, index, fmt::format(" (line {})", facet_line));
  return tri;
}

std::vector<Triangle> read_ascii(std::string_view text, std::string_view name,
                                 const StlReadOptions& options) {
  AsciiCursor in(text, name);
  std::vector<Triangle> facets;
  // About 250 bytes per facet in typical exporters' output: one allocation for most files.
  facets.reserve(text.size() / 256 + 1);
  if (options.stored_normals) options.stored_normals->clear();

  in.expect("solid", "the first line");
  std::string_view solid_name = in.rest_of_line();
  std::size_t solid_line = in.line();
  for (;;) {
    const std::string_view t = in.token();
    if (t.empty()) {
      in.fail_here(fmt::format("file ends without 'endsolid' for the solid of line {}: "
                               "truncated",
                               solid_line));
    }
    if (iequals(t, "endsolid")) {
      if (end_of_solid(in, solid_name, solid_line)) break;
      continue;
    }
    if (!iequals(t, "facet")) {
      in.fail_here(fmt::format("expected 'facet' or 'endsolid', found {}", quoted(t)));
    }
    Vec3 stored;
    const Triangle tri = read_facet(in, facets.size() + 1, name, stored);
    if (options.stored_normals) options.stored_normals->push_back(stored);
    facets.push_back(tri);
  }
  if (facets.empty()) fail(name, "ASCII STL with no facets: there is nothing to print");
  return facets;
}

bool starts_with_solid(std::string_view bytes) {
  const std::string_view t = trim(bytes.substr(0, 512));
  return t.size() >= 5 && iequals(t.substr(0, 5), "solid") &&
         (t.size() == 5 || is_space(t[5]));
}

Vec3 unit_normal(const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 n = cross(b - a, c - a);
  const double length = std::sqrt(dot(n, n));
  if (!(length > 0) || !std::isfinite(length)) return {};
  return (1.0 / length) * n;
}

struct FileCloser {
  void operator()(std::FILE* f) const { std::fclose(f); }
};

std::unique_ptr<std::FILE, FileCloser> open_for_writing(const std::string& path) {
  std::unique_ptr<std::FILE, FileCloser> file(std::fopen(path.c_str(), "wb"));
  if (!file) fail(path, fmt::format("cannot write the file ({})", std::strerror(errno)));
  return file;
}

void finish_writing(std::unique_ptr<std::FILE, FileCloser> file, const std::string& path) {
  const bool failed = std::ferror(file.get()) != 0;
  const int closed = std::fclose(file.release());
  if (failed || closed != 0) {
    fail(path, fmt::format("writing failed ({})", std::strerror(errno)));
  }
}

}  // namespace

std::vector<Triangle> read_stl_bytes(std::string_view bytes, std::string_view name,
                                     const StlReadOptions& options) {
  if (bytes.empty()) fail(name, "empty file (0 bytes): not an STL model");
  if (bytes.size() >= kBinaryPrefix) {
    const std::uint64_t count = read_u32(bytes.data() + kHeaderBytes);
    const std::uint64_t expected = kBinaryPrefix + kFacetBytes * count;
    if (expected == bytes.size()) return read_binary(bytes, name, options);
  }
  // ASCII STL is text: a NUL byte means a binary file whose size does not fit its header.
  const bool text = std::memchr(bytes.data(), '\0', bytes.size()) == nullptr;
  if (text && starts_with_solid(bytes)) return read_ascii(bytes, name, options);
  if (bytes.size() < kBinaryPrefix) {
    fail(name, fmt::format("not an STL file: {} bytes is too short for binary STL (84 at "
                           "least) and it does not start with 'solid' as ASCII STL does",
                           bytes.size()));
  }
  const std::uint64_t count = read_u32(bytes.data() + kHeaderBytes);
  const std::uint64_t room = (bytes.size() - kBinaryPrefix) / kFacetBytes;
  if (text) {
    fail(name, fmt::format("not an STL file: it does not start with 'solid' as ASCII STL does, "
                           "and its size ({} bytes) does not match the facet count of a binary "
                           "STL header ({} facets would need {} bytes)",
                           bytes.size(), count, kBinaryPrefix + kFacetBytes * count));
  }
  fail(name, fmt::format("binary STL whose header says {} facets ({} bytes) but the file has "
                         "{} bytes (room for {} facets): truncated or a wrong facet count",
                         count, kBinaryPrefix + kFacetBytes * count, bytes.size(), room));
}

std::vector<Triangle> read_stl(const std::string& path, const StlReadOptions& options) {
  return read_stl_bytes(read_file_bytes(path), path, options);
}

void write_stl_binary(const std::string& path, const std::vector<Triangle>& triangles) {
  if (triangles.size() > std::numeric_limits<std::uint32_t>::max()) {
    fail(path, "too many facets for binary STL (more than 4294967295)");
  }
  auto file = open_for_writing(path);
  // The header must not start with "solid", or naive readers would take it for ASCII.
  char header[kBinaryPrefix] = {};
  std::snprintf(header, kHeaderBytes, "binary STL written by mahost");
  const auto count = static_cast<std::uint32_t>(triangles.size());
  for (int i = 0; i < 4; ++i) header[kHeaderBytes + i] = static_cast<char>(count >> (8 * i));
  std::fwrite(header, 1, sizeof header, file.get());

  std::vector<char> buffer;
  buffer.reserve(kFacetBytes * 4096);
  auto put = [&buffer](double value) {
    const auto bits = std::bit_cast<std::uint32_t>(static_cast<float>(value));
    for (int i = 0; i < 4; ++i) buffer.push_back(static_cast<char>(bits >> (8 * i)));
  };
  const auto stored = [](const Vec3& p) {
    return Vec3{static_cast<float>(p.x), static_cast<float>(p.y), static_cast<float>(p.z)};
  };
  for (const Triangle& t : triangles) {
    // The normal of the corners as stored (float32), so that a reader recomputing it from
    // them agrees even for a sliver whose rounding turns it over.
    const Vec3 a = stored(t.v[0]), b = stored(t.v[1]), c = stored(t.v[2]);
    const Vec3 n = unit_normal(a, b, c);
    for (const Vec3& p : {n, a, b, c}) {
      put(p.x);
      put(p.y);
      put(p.z);
    }
    buffer.push_back(0);
    buffer.push_back(0);
    if (buffer.size() >= kFacetBytes * 4096) {
      std::fwrite(buffer.data(), 1, buffer.size(), file.get());
      buffer.clear();
    }
  }
  std::fwrite(buffer.data(), 1, buffer.size(), file.get());
  finish_writing(std::move(file), path);
}

void write_stl_binary(const std::string& path, const Mesh& mesh) {
  std::vector<Triangle> triangles;
  triangles.reserve(mesh.faces.size());
  for (const auto& f : mesh.faces) {
    triangles.push_back({{mesh.vertices[f[0]], mesh.vertices[f[1]], mesh.vertices[f[2]]}});
  }
  write_stl_binary(path, triangles);
}

void write_stl_ascii(const std::string& path, const std::vector<Triangle>& triangles,
                     std::string_view solid_name) {
  auto file = open_for_writing(path);
  std::string text = fmt::format("solid {}\n", solid_name);
  for (const Triangle& t : triangles) {
    const Vec3 n = unit_normal(t.v[0], t.v[1], t.v[2]);
    text += fmt::format("  facet normal {} {} {}\n    outer loop\n", n.x, n.y, n.z);
    for (const Vec3& p : t.v) text += fmt::format("      vertex {} {} {}\n", p.x, p.y, p.z);
    text += "    endloop\n  endfacet\n";
    if (text.size() > (1u << 20)) {
      std::fwrite(text.data(), 1, text.size(), file.get());
      text.clear();
    }
  }
  text += fmt::format("endsolid {}\n", solid_name);
  std::fwrite(text.data(), 1, text.size(), file.get());
  finish_writing(std::move(file), path);
}

}  // namespace geometry
