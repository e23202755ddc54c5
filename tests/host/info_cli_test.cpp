// `mahost info` as a user runs it: the figures of a model, --export, and every file or flag
// that cannot be used refused with exactly one line on stderr and exit code 2.
#include <doctest/doctest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>

#include "geometry/mesh/mesh.h"
#include "geometry/mesh/stl_io.h"
#include "support/run_command.h"

namespace info_cli_test {

using test_support::run_mahost;

namespace {

const std::string kData = MAHOST_DATA_DIR;
const std::string kBroken = kData + "/stl-models/broken/";

std::size_t lines(const std::string& text) {
  return static_cast<std::size_t>(std::count(text.begin(), text.end(), '\n'));
}

// The value after a label in info's output ("volume        25569.661 mm^3" -> "25569.661 ...").
std::string field(const std::string& out, const std::string& label) {
  std::size_t start = 0;
  while (start < out.size()) {
    const std::size_t end = std::min(out.find('\n', start), out.size());
    const std::string line = out.substr(start, end - start);
    if (line.rfind(label + " ", 0) == 0) {
      return line.substr(line.find_first_not_of(' ', label.size()));
    }
    start = end + 1;
  }
  return "";
}

// Exit code 2 and one line on stderr that starts "mahost: " and contains `expected`.
void check_refused(const std::vector<std::string>& args, const std::string& expected) {
  CAPTURE(args);
  const auto result = run_mahost(args);
  CAPTURE(result.err);
  CHECK(result.exit_code == 2);
  CHECK(lines(result.err) == 1);
  CHECK(result.err.rfind("mahost: ", 0) == 0);
  CHECK(result.err.find(expected) != std::string::npos);
}

}  // namespace

TEST_CASE("info_refuses_every_broken_file_in_one_line") {
  int refused = 0;
  for (const auto& entry : std::filesystem::directory_iterator(kBroken)) {
    const std::string path = entry.path().string();
    const std::string name = entry.path().filename().string();
    if (name == "wrongHeader.bin.stl") continue;  // a valid binary cube
    // Wrong stored normals are read (info_counts_stored_normals_against_the_repaired_part_...).
    if (name == "wrongNormal.ascii.stl" || name == "wrongNormals.ascii.stl" || name == "notANumberNormal.ascii.stl") continue;
    check_refused({"info", path}, path + ": ");
    ++refused;
  }
  CHECK(refused == 10);
}

TEST_CASE("info_counts_stored_normals_against_the_repaired_part_and_refuses_none") {
  // wrongNormal: one of four normals points against its facet; notANumberNormal: one is NaN.
  auto result = run_mahost({"info", kBroken + "wrongNormal.ascii.stl"});
  CHECK(result.exit_code == 0);
  CHECK(result.err.empty());
  CHECK(field(result.out, "watertight") == "yes");
  CHECK(field(result.out, "volume") == "0.167 mm^3");  // the unit corner tetrahedron
  CHECK(field(result.out, "normals") == "1 of 4 stored normals point into the repaired part");
  result = run_mahost({"info", kBroken + "notANumberNormal.ascii.stl"});
  CHECK(field(result.out, "normals") == "0 of 3 stored normals point into the repaired part (1 more is zero or not a number)");
  result = run_mahost({"info", kBroken + "wrongNormals.ascii.stl"});  // every normal zero
  CHECK(field(result.out, "normals") == "0 of 0 stored normals point into the repaired part (4 more are zero or not numbers)");
  // --ignore-normals is taken for earlier versions' scripts, and changes nothing.
  CHECK(run_mahost({"info", kBroken + "wrongNormal.ascii.stl", "--ignore-normals"}).out ==
        run_mahost({"info", kBroken + "wrongNormal.ascii.stl"}).out);
}

TEST_CASE("info_reads_solid_header_binary_cube") {
  const auto result = run_mahost({"info", kBroken + "wrongHeader.bin.stl"});
  CHECK(result.exit_code == 0);
  CHECK(result.err.empty());
  CHECK(field(result.out, "triangles") == "12 in the file, 12 after repair");
  CHECK(field(result.out, "vertices") == "8");
  CHECK(field(result.out, "size") == "100.000 x 100.000 x 100.000 mm");
  CHECK(field(result.out, "min") == "-50.000 -50.000 0.000 mm");
  CHECK(field(result.out, "max") == "50.000 50.000 100.000 mm");
  CHECK(field(result.out, "volume") == "1000000.000 mm^3");
  CHECK(field(result.out, "surface area") == "60000.000 mm^2");
  CHECK(field(result.out, "open edges") == "0 before repair, 0 after");
  CHECK(field(result.out, "repairs") == "none");
  CHECK(field(result.out, "watertight") == "yes");
}

TEST_CASE("info_bunny_placed_as_in_the_paper") {
  const auto result =
      run_mahost({"info", kData + "/bunny.stl", "--up", "y", "--units", "m", "--height", "50"});
  CHECK(result.exit_code == 0);
  CHECK(field(result.out, "triangles").rfind("69451 in the file", 0) == 0);
  const std::string size = field(result.out, "size");
  CHECK(size.substr(size.size() - 9) == "50.000 mm");
  CHECK(field(result.out, "min").substr(field(result.out, "min").size() - 8) == "0.000 mm");
  CHECK(field(result.out, "repairs").rfind("5 holes filled (+", 0) == 0);
  CHECK(field(result.out, "watertight") == "yes");
  CHECK(field(result.out, "open edges").find(", 0 after") != std::string::npos);
  const double volume = std::stod(field(result.out, "volume"));
  CHECK(volume > 24000);
  CHECK(volume < 27000);
  // The repairs were announced in the output, not as a warning.
  CHECK(result.err.empty());
}

TEST_CASE("info_export_writes_the_placed_repaired_mesh") {
  const std::string dir = test_support::scratch_dir("info_export");
  const std::string out = dir + "/bunny-placed.stl";
  const auto first = run_mahost({"info", kData + "/bunny.stl", "--up", "y", "--units", "m",
                                 "--height", "50", "--export", out});
  REQUIRE(first.exit_code == 0);
  const auto facets = geometry::read_stl(out);
  const std::string triangles = field(first.out, "triangles");
  const std::size_t repaired = std::stoul(triangles.substr(triangles.find(", ") + 2));
  CHECK(facets.size() == repaired);
  CHECK(std::filesystem::file_size(out) == 84 + 50 * repaired);
  // What was exported needs no repair and no placement any more.
  const auto second = run_mahost({"info", out});
  CHECK(second.exit_code == 0);
  CHECK(field(second.out, "open edges") == "0 before repair, 0 after");
  CHECK(field(second.out, "repairs") == "none");
  CHECK(field(second.out, "watertight") == "yes");
  CHECK(field(second.out, "size") == field(first.out, "size"));
  CHECK(field(second.out, "volume") == field(first.out, "volume"));
}

TEST_CASE("info_refuses_files_that_are_not_models") {
  const std::string dir = test_support::scratch_dir("info_bad_files");
  check_refused({"info", dir + "/missing.stl"}, dir + "/missing.stl: no such file");
  check_refused({"info", dir}, dir + ": is a directory");
  std::ofstream(dir + "/empty.stl").flush();
  check_refused({"info", dir + "/empty.stl"}, "empty file");
  {
    std::mt19937 random(7);
    std::string noise(10000, '\0');
    for (char& c : noise) c = static_cast<char>(random());
    std::ofstream(dir + "/noise.stl", std::ios::binary) << noise;
  }
  check_refused({"info", dir + "/noise.stl"}, dir + "/noise.stl: ");
  {
    // A truncated binary: the bunny cut in the middle of a facet.
    std::ifstream in(kData + "/bunny.stl", std::ios::binary);
    std::string head(84 + 50 * 500 + 21, '\0');
    in.read(head.data(), static_cast<std::streamsize>(head.size()));
    std::ofstream(dir + "/cut.stl", std::ios::binary) << head;
  }
  check_refused({"info", dir + "/cut.stl"}, "truncated");
  check_refused({"info", kBroken + "singleFace.ascii.stl"}, "zero volume");
}

TEST_CASE("info_refuses_bad_flags_in_one_line") {
  const std::string cube = kBroken + "wrongHeader.bin.stl";
  check_refused({"info"}, "MODEL is required");
  check_refused({"info", cube, "--units", "cm"}, "--units: 'cm' is not a unit");
  check_refused({"info", cube, "--scale", "0"}, "--scale: needs a number greater than 0");
  check_refused({"info", cube, "--scale", "nan"}, "--scale: needs a number greater than 0");
  check_refused({"info", cube, "--height", "-3"}, "--height: needs a number greater than 0");
  check_refused({"info", cube, "--height", "50", "--scale", "2"}, "excludes");
  check_refused({"info", cube, "--up", "w"}, "--up: 'w' is not an axis");
  check_refused({"info", cube, "--bogus"}, "--bogus");
  check_refused({"--bogus"}, "unknown option '--bogus'");
  check_refused({"bogus"}, "unknown command 'bogus'");
  check_refused({"info", cube, "--export", "/nonexistent-dir/out.stl"},
                "/nonexistent-dir/out.stl: cannot write");
}

TEST_CASE("info_help_lists_its_options") {
  const auto result = run_mahost({"info", "--help"});
  CHECK(result.exit_code == 0);
  for (const char* option : {"MODEL", "--units", "--scale", "--height", "--up", "--export"}) {
    CHECK(result.out.find(option) != std::string::npos);
  }
  // Taken for earlier versions' scripts, not offered: stored normals never decide.
  CHECK(result.out.find("--ignore-normals") == std::string::npos);
}

}  // namespace info_cli_test
