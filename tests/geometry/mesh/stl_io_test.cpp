// STL reading and writing: both formats, binary detection by size, every broken file of the
// stl-models package refused with a reason, garbage and truncation refused without a crash.
#include "geometry/mesh/stl_io.h"

#include <doctest/doctest.h>
#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <string>

#include "geometry/mesh/repair.h"
#include "support/run_command.h"

namespace stl_io_test {

using namespace geometry;

namespace {

const std::string kData = MAHOST_DATA_DIR;
const std::string kBroken = kData + "/stl-models/broken/";

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

void spit(const std::string& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary) << bytes;
}

// The message of the InputError `read` throws, or "" if it throws none.
template <class F>
std::string refusal(F&& read) {
  try {
    read();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

// A 10 mm cube [0,10]^3 with outward facets, 12 triangles.
std::vector<Triangle> cube_facets(double side = 10) {
  const double s = side;
  const Vec3 p[8] = {{0, 0, 0}, {s, 0, 0}, {s, s, 0}, {0, s, 0},
                     {0, 0, s}, {s, 0, s}, {s, s, s}, {0, s, s}};
  const int quads[6][4] = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4},
                           {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}};
  std::vector<Triangle> out;
  for (const auto& q : quads) {
    out.push_back({{p[q[0]], p[q[1]], p[q[2]]}});
    out.push_back({{p[q[0]], p[q[2]], p[q[3]]}});
  }
  return out;
}

std::string binary_stl(const std::string& header, const std::vector<Triangle>& facets,
                       std::uint32_t count) {
  std::string out = header.substr(0, 80);
  out.resize(80, '\0');
  for (int i = 0; i < 4; ++i) out += static_cast<char>(count >> (8 * i));
  for (const Triangle& t : facets) {
    const float values[12] = {0, 0, 0,
                              float(t.v[0].x), float(t.v[0].y), float(t.v[0].z),
                              float(t.v[1].x), float(t.v[1].y), float(t.v[1].z),
                              float(t.v[2].x), float(t.v[2].y), float(t.v[2].z)};
    out.append(reinterpret_cast<const char*>(values), sizeof values);
    out += std::string(2, '\0');
  }
  return out;
}

bool same_facets(const std::vector<Triangle>& a, const std::vector<Triangle>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    for (int k = 0; k < 3; ++k) {
      if (a[i].v[k].x != b[i].v[k].x || a[i].v[k].y != b[i].v[k].y ||
          a[i].v[k].z != b[i].v[k].z) {
        return false;
      }
    }
  }
  return true;
}

}  // namespace

TEST_CASE("broken_files_refused_with_the_reason") {
  // Each broken file of stl-models and a word its one-line refusal must contain (its files
  // whose stored normals are wrong are read: stored_normals_never_refuse_a_file).
  const std::pair<const char*, const char*> cases[] = {
      {"empty.stl", "empty file"},
      {"fourVertices.ascii.stl", "more than 3 vertices"},
      {"quad.ascii.stl", "more than 3 vertices"},
      {"twoVertices.ascii.stl", "only 2 vertices"},
      {"incorrectFaceCounter.bin.stl", "header says 66 facets"},
      {"missingEndsolid.ascii.stl", "without 'endsolid'"},
      {"missingNormal.ascii.stl", "'facet normal' needs three numbers"},
      {"solidNameMismatch.ascii.stl", "'endsolid anything but tetrahedron' does not match"},
      {"missingFace.ascii.stl", "missing too much"},
      {"singleFace.ascii.stl", "zero volume"},
  };
  for (const auto& [file, reason] : cases) {
    CAPTURE(file);
    const std::string path = kBroken + file;
    const std::string message = refusal([&] {
      RepairReport report;
      repair(read_stl(path), &report);
      check_printable(report, path);
    });
    CHECK(message.rfind(path + ": ", 0) == 0);
    CHECK(message.find(reason) != std::string::npos);
    CHECK(message.find('\n') == std::string::npos);
  }
}

TEST_CASE("syntax_errors_name_their_line") {
  CHECK(refusal([] { read_stl(kBroken + "fourVertices.ascii.stl"); }).find("(line 7)") !=
        std::string::npos);
  CHECK(refusal([] { read_stl(kBroken + "twoVertices.ascii.stl"); }).find("(line 6)") !=
        std::string::npos);
  CHECK(refusal([] { read_stl(kBroken + "missingNormal.ascii.stl"); }).find("(line 24)") !=
        std::string::npos);
}

TEST_CASE("wrong_header_cube_read_as_binary") {
  // Its 80-byte header starts with "solid", but 84 + 50 * 12 is its size: binary.
  const auto facets = read_stl(kBroken + "wrongHeader.bin.stl");
  REQUIRE(facets.size() == 12);
  RepairReport report;
  const Mesh mesh = repair(facets, &report);
  const Box3 box = bounding_box(mesh);
  CHECK(box.min.x == -50);
  CHECK(box.max.x == 50);
  CHECK(box.min.z == -50);
  CHECK(box.max.y == 50);
  CHECK(report.closed);
  CHECK(report.volume == doctest::Approx(100.0 * 100 * 100).epsilon(1e-12));
}

TEST_CASE("binary_with_solid_header_read_as_binary") {
  const auto cube = cube_facets();
  const auto facets = read_stl_bytes(binary_stl("solid cube exported by a CAD", cube, 12), "cube.stl");
  CHECK(same_facets(facets, cube));
}

TEST_CASE("ascii_and_binary_bunny_read_to_the_same_triangles") {
  const auto binary = read_stl(kData + "/stl-models/objects/bunny.bin.stl");
  const auto ascii = read_stl(kData + "/stl-models/objects/bunny.ascii.stl");
  REQUIRE(binary.size() == 69451);
  REQUIRE(ascii.size() == binary.size());
  // The ASCII file prints the binary file's float32 values to 7 digits: as float32 they
  // are the same numbers.
  std::size_t differing = 0;
  for (std::size_t i = 0; i < ascii.size(); ++i) {
    for (int k = 0; k < 3; ++k) {
      const Vec3 a = ascii[i].v[k], b = binary[i].v[k];
      if (float(a.x) != float(b.x) || float(a.y) != float(b.y) || float(a.z) != float(b.z)) {
        ++differing;
      }
    }
  }
  CHECK(differing == 0);
}

TEST_CASE("cube_written_in_both_formats_reads_back_exactly") {
  const std::string dir = test_support::scratch_dir("stl_io_cube");
  const auto cube = cube_facets(10);
  write_stl_ascii(dir + "/cube.ascii.stl", cube, "cube");
  write_stl_binary(dir + "/cube.bin.stl", cube);
  CHECK(std::filesystem::file_size(dir + "/cube.bin.stl") == 84 + 50 * 12);
  CHECK(slurp(dir + "/cube.bin.stl").rfind("solid", 0) != 0);  // never mistaken for ASCII
  const auto ascii = read_stl(dir + "/cube.ascii.stl");
  const auto binary = read_stl(dir + "/cube.bin.stl");
  CHECK(same_facets(ascii, cube));
  CHECK(same_facets(binary, cube));
  // Written normals agree with the vertex order, so the default check accepts both files.
  RepairReport report;
  repair(binary, &report);
  CHECK(report.volume == 1000.0);
  CHECK(report.surface_area == 600.0);
}

TEST_CASE("ascii_variants_exporters_write_are_read") {
  // Upper-case keywords, CRLF, '+' signs, exponents, a nameless solid, two solids in a file.
  const std::string text =
      "SOLID\r\n"
      "FACET NORMAL 0 0 +1\r\n OUTER LOOP\r\n"
      "  VERTEX 0 0 0\r\n  VERTEX +1.0e0 0 0\r\n  VERTEX 0 1E+0 -0\r\n"
      " ENDLOOP\r\nENDFACET\r\nENDSOLID\r\n"
      "solid second part\n facet normal 0 0 1\n outer loop\n"
      "  vertex 0 0 1\n vertex 1 0 1\n vertex 0 1 1\n endloop\n endfacet\n"
      "endsolid second\n";
  const auto facets = read_stl_bytes(text, "variants.stl");
  REQUIRE(facets.size() == 2);
  CHECK(facets[0].v[1].x == 1.0);
  CHECK(facets[0].v[2].y == 1.0);
  CHECK(facets[1].v[2].z == 1.0);
}

TEST_CASE("stored_normals_never_refuse_a_file") {
  // A normal against the vertex order, several, and a NaN: read, and the repair closes them.
  for (const char* file : {"wrongNormal.ascii.stl", "wrongNormals.ascii.stl",
                           "notANumberNormal.ascii.stl"}) {
    CAPTURE(file);
    std::vector<Vec3> normals;
    const auto facets = read_stl(kBroken + file, {.stored_normals = &normals});
    REQUIRE(facets.size() == 4);
    CHECK(normals.size() == 4);
    RepairReport report;
    repair(facets, &report);
    CHECK(report.closed);
    CHECK(report.volume == doctest::Approx(1.0 / 6));  // the unit corner tetrahedron
  }
}

TEST_CASE("stored_normals_are_handed_out_in_file_order") {
  const std::string text =
      "solid t\nfacet normal 0 0 0\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\n"
      "endloop\nendfacet\nfacet normal 0 0 -1.5\nouter loop\nvertex 0 0 1\nvertex 1 0 1\n"
      "vertex 0 1 1\nendloop\nendfacet\nendsolid t\n";
  std::vector<Vec3> normals;
  const auto facets = read_stl_bytes(text, "two.stl", {.stored_normals = &normals});
  REQUIRE(normals.size() == 2);
  CHECK(normals[0].z == 0);
  CHECK(normals[1].z == -1.5);  // as stored: neither checked nor normalised
}

TEST_CASE("files_that_are_not_there_refused") {
  const std::string dir = test_support::scratch_dir("stl_io_missing");
  CHECK(refusal([&] { read_stl(dir + "/nothing.stl"); }) ==
        dir + "/nothing.stl: no such file (check the path)");
  CHECK(refusal([&] { read_stl(dir); }) == dir + ": is a directory, not a model file");
  spit(dir + "/locked.stl", slurp(kBroken + "wrongHeader.bin.stl"));
  std::filesystem::permissions(dir + "/locked.stl", std::filesystem::perms::none);
  if (access((dir + "/locked.stl").c_str(), R_OK) != 0) {  // root reads anything
    CHECK(refusal([&] { read_stl(dir + "/locked.stl"); }) ==
          dir + "/locked.stl: permission denied: cannot read the file");
  }
}

TEST_CASE("truncated_binary_refused") {
  const std::string bunny = slurp(kData + "/stl-models/objects/bunny.bin.stl");
  for (std::size_t keep : {std::size_t{83}, std::size_t{84}, std::size_t{84 + 50 * 1000 + 17},
                           bunny.size() - 1}) {
    CAPTURE(keep);
    const std::string message =
        refusal([&] { read_stl_bytes(std::string_view(bunny).substr(0, keep), "cut.stl"); });
    CHECK(message.rfind("cut.stl: ", 0) == 0);
    CHECK((message.find("truncated") != std::string::npos ||
           message.find("too short") != std::string::npos));
  }
}

TEST_CASE("zero_facets_refused") {
  CHECK(refusal([] { read_stl_bytes(binary_stl("", {}, 0), "none.stl"); }) ==
        "none.stl: binary STL with no facets: there is nothing to print");
  CHECK(refusal([] { read_stl_bytes("solid empty\nendsolid empty\n", "none.stl"); })
            .find("no facets") != std::string::npos);
}

TEST_CASE("non_finite_coordinates_refused") {
  auto cube = cube_facets();
  cube[5].v[1].y = std::numeric_limits<double>::quiet_NaN();
  CHECK(refusal([&] {
          read_stl_bytes(binary_stl("", cube, 12), "nan.stl");
        }) == "nan.stl: facet 6 has a corner that is NaN or infinite");
  const std::string text =
      "solid s\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex inf 0 0\nvertex 0 1 0\n"
      "endloop\nendfacet\nendsolid s\n";
  CHECK(refusal([&] { read_stl_bytes(text, "inf.stl"); }) ==
        "inf.stl: facet 1 has a corner that is NaN or infinite (line 2)");
  const std::string huge =
      "solid s\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1e999 0 0\n"
      "vertex 0 1 0\nendloop\nendfacet\nendsolid s\n";
  CHECK(refusal([&] { read_stl_bytes(huge, "huge.stl"); }).find("NaN or infinite") !=
        std::string::npos);
}

TEST_CASE("garbage_refused_in_one_line") {
  std::mt19937 random(42);
  for (std::size_t size : {1, 5, 83, 84, 200, 4096, 100000}) {
    for (bool text_start : {false, true}) {
      std::string bytes(size, '\0');
      for (char& c : bytes) c = static_cast<char>(random());
      if (text_start) bytes.replace(0, std::min<std::size_t>(6, size), "solid ", 0,
                                    std::min<std::size_t>(6, size));
      CAPTURE(size);
      const std::string message = refusal([&] { read_stl_bytes(bytes, "noise.stl"); });
      CHECK(message.rfind("noise.stl: ", 0) == 0);
      CHECK(message.find('\n') == std::string::npos);
    }
  }
  // Printable garbage after "solid": a syntax error quoting the token, kept short.
  const std::string message = refusal([] {
    read_stl_bytes("solid x\n" + std::string(5000, 'A') + "\n", "letters.stl");
  });
  CHECK(message.find("expected 'facet' or 'endsolid', found 'AAAA") != std::string::npos);
  CHECK(message.size() < 200);
}

}  // namespace stl_io_test
