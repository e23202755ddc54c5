// host/serve's pure parts: cleaning file names, the files folder, the job file's byte
// positions and layer drawing, the API key's comparison.
#include <sys/stat.h>

#include <doctest/doctest.h>

#include "host/serve/api_key.h"
#include "host/serve/file_store.h"
#include "host/serve/job_file.h"
#include "printer/error.h"
#include "printer/print_eta.h"
#include "serve_fixture.h"

namespace file_store_test {

using namespace host::serve;

TEST_CASE("clean_file_name_refuses_paths_dots_and_control_characters_and_cleans_the_rest") {
  CHECK(clean_file_name("bunny.gcode").name == "bunny.gcode");
  CHECK(clean_file_name("Bunny V2 (0.2mm).GCODE").name == "Bunny_V2_(0.2mm).GCODE");
  CHECK(clean_file_name("20mm-ümläut box.gcode").name == "20mm-_ml_ut_box.gcode");
  CHECK(clean_file_name("a..b.gco").name == "a..b.gco");  // dots inside a name are no path
  CHECK(clean_file_name("cube.stl").name == "cube.stl");
  for (const char* bad : {"../x.gcode", "/etc/x.gcode", "a\\b.gcode", "..", ".", ".x.gcode", "", "tab\t.gcode"}) {
    CAPTURE(bad);
    const CleanName c = clean_file_name(bad);
    CHECK(c.status == 400);
    CHECK(c.name.empty());
  }
  CHECK(clean_file_name(std::string(201, 'a') + ".g").status == 400);
  CHECK(clean_file_name("passwd").status == 415);
  CHECK(clean_file_name("x.gcode.exe").status == 415);
  CHECK(is_clean_name("bunny.gcode"));
  CHECK_FALSE(is_clean_name("my part.gcode"));  // it would be cleaned: not a stored name
  CHECK(kind_of("A.G") == FileKind::gcode);
  CHECK(kind_of("a.STL") == FileKind::model);
  CHECK_FALSE(kind_of("a.txt"));
}

TEST_CASE("the_files_folder_lists_regular_files_only_and_uploads_land_whole_or_not_at_all") {
  const std::string dir = test_support::scratch_dir("file_store") + "/files";
  FileStore store(dir, printer::MotionLimits{}, 1.75);
  struct stat info {};
  REQUIRE(stat(dir.c_str(), &info) == 0);
  {
    FileStore::Upload upload(store);
    REQUIRE(upload.write("G28\nG1 X10 E1\n", 14));
    CHECK(store.list().empty());  // not there until committed
    REQUIRE(upload.commit("a.gcode"));
  }
  {
    FileStore::Upload abandoned(store);
    abandoned.write("G28\n", 4);
  }  // dropped: removed
  serve_test::write_text(dir + "/notes.txt", "not a print");
  serve_test::write_text(dir + "/.hidden.gcode", "G28\n");
  std::filesystem::create_symlink("/etc/hostname", dir + "/link.gcode");
  const auto files = store.list();
  REQUIRE(files.size() == 1);
  CHECK(files[0].name == "a.gcode");
  CHECK(files[0].size == 14);
  REQUIRE(files[0].analysis);
  CHECK(files[0].analysis->commands == 2);
  CHECK(files[0].analysis->filament_mm == doctest::Approx(1.0));
  CHECK(files[0].analysis->filament_cm3 == doctest::Approx(std::acos(-1.0) * 0.875 * 0.875 / 1000));
  CHECK_THROWS_AS(store.path_of("../a.gcode"), std::invalid_argument);
  CHECK_FALSE(store.remove("link.gcode"));
  CHECK(store.remove("a.gcode"));
  CHECK_FALSE(store.find("a.gcode"));
  std::size_t left = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    left += entry.path().filename().string().rfind(".upload-", 0) == 0;
  }
  CHECK(left == 0);
}

TEST_CASE("a_job_file_holds_its_commands_and_refuses_text_that_is_not_gcode") {
  const std::string text = "; header\nG28 ; home\n\n   \nG1 X1 Y2 E0.5\r\n;LAYER:0\nG1 X3\nM84";
  const JobFile file = load_job_file(text, "t.gcode");
  REQUIRE(file.gcode.size() == 4);
  CHECK(file.bytes == text.size());
  CHECK_THROWS_AS(load_job_file("; only comments\n", "c.gcode"), printer::ConfigError);
  CHECK_THROWS_AS(load_job_file(std::string("G1\0X", 4), "nul.gcode"), printer::ConfigError);
}

TEST_CASE("a_layer_is_drawn_from_its_own_start_state_split_where_the_print_is") {
  // Layer 1 starts at X10 Y0 with E 2 (absolute): its moves are known without layer 0.
  const std::string text =
      "G90\nM82\nG92 E0\nG1 X-50 Y-50 E0.5\nG92 E0\n;LAYER:0\nG1 X0 Y0\nG1 X10 Y0 E1\nG1 E2\n;LAYER:1\nG1 X10 Y10 E3\n"
      "G0 X0 Y10\nG1 X0 Y0 E4\n";
  const JobFile file = load_job_file(text, "l.gcode");
  CHECK(file.min_x == 0);  // the prime line to -50 before the first layer is not the part
  CHECK(file.min_y == 0);
  CHECK(file.max_x == 10);
  CHECK(file.max_y == 10);
  const auto moves = layer_moves(file, 1);
  REQUIRE(moves.size() == 3);
  CHECK(moves[0].x0 == 10);
  CHECK(moves[0].y0 == 0);
  CHECK(moves[0].extrudes);
  CHECK_FALSE(moves[1].extrudes);
  CHECK(moves[2].extrudes);
  CHECK(svg_path(moves, true, 0, SIZE_MAX) == "M10.00 0.00L10.00 10.00M0.00 10.00L0.00 0.00");
  CHECK(svg_path(moves, false, 0, SIZE_MAX) == "M10.00 10.00L0.00 10.00");
  // Done through layer 1's first extrusion (command 8, so 9 done): the rest still to print.
  CHECK(svg_path(moves, true, 0, 9) == "M10.00 0.00L10.00 10.00");
  CHECK(svg_path(moves, true, 9, SIZE_MAX) == "M0.00 10.00L0.00 0.00");
  CHECK(layer_moves(file, 2).empty());
  CHECK(layer_moves(file, -1).empty());
}

TEST_CASE("a_job_file_read_in_pieces_is_the_file_read_whole_and_its_analysis_the_same") {
  // Over three pieces of printer::kGcodePiece bytes (the pieces themselves: gcode_file_test):
  // each command's end in the file, the layer states and the part's extent as from the whole
  // text, and the upload's analysis, read the same way, the motion model's time of it all.
  const std::string dir = test_support::scratch_dir("job_file_pieces");
  const std::string text = "; contour: ma\n" + serve_test::ring_gcode(2400, 120) + "\n\n; the end\nM84";
  REQUIRE(text.size() > 2 * printer::kGcodePiece);
  const std::string path = dir + "/big.gcode";
  serve_test::write_text(path, text);
  const JobFile whole = load_job_file(text, path);
  const JobFile pieces = read_job_file(path);
  CHECK(pieces.gcode.size() == whole.gcode.size());
  CHECK(pieces.gcode.hash == whole.gcode.hash);
  printer::GcodeReader reader(pieces.gcode);
  bool same_ends = true;
  for (std::size_t i = 0; i < whole.gcode.size(); ++i) same_ends &= reader.command_end(i) == whole.gcode.command_end(i);
  CHECK(same_ends);
  CHECK(pieces.bytes == text.size());
  REQUIRE(pieces.layer_start.size() == whole.layer_start.size());
  bool same_states = true;
  for (std::size_t l = 0; l < whole.layer_start.size(); ++l) {
    same_states &= pieces.layer_start[l].x == whole.layer_start[l].x && pieces.layer_start[l].e == whole.layer_start[l].e;
  }
  CHECK(same_states);
  CHECK(pieces.max_x == whole.max_x);
  FileStore store(dir + "/files", printer::MotionLimits{}, 1.75);
  const GcodeAnalysis a = store.analyse(path);
  CHECK(a.error.empty());
  CHECK(a.commands == whole.gcode.size());
  CHECK(a.layers == whole.gcode.layers.size());
  CHECK(a.contour == "ma");
  printer::PrintEta eta(whole.gcode, printer::MotionLimits{});
  eta.finish(0);
  CHECK(a.estimated_seconds == doctest::Approx(*eta.total()));
}

TEST_CASE("the_key_comparison_answers_only_an_exact_match") {
  CHECK(same_key("0123456789abcdef", "0123456789abcdef"));
  CHECK_FALSE(same_key("0123456789abcdeF", "0123456789abcdef"));
  CHECK_FALSE(same_key("0123456789abcde", "0123456789abcdef"));
  CHECK_FALSE(same_key("0123456789abcdef0", "0123456789abcdef"));
  CHECK_FALSE(same_key("", "0123456789abcdef"));
  const std::string a = make_api_key(), b = make_api_key();
  CHECK(a.size() == 32);
  CHECK(a != b);
  CHECK(a.find_first_not_of("0123456789abcdef") == std::string::npos);
}

}  // namespace file_store_test
