// Layer tops read back from G-code as CuraEngine 4.13, PrusaSlicer 2.5, Slic3r 1.3 and mahost
// write it (excerpts of files they wrote here), and from lists of numbers.
#include <doctest/doctest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <unistd.h>
#include <vector>

#include "printer/error.h"
#include "printer/layer_tops.h"

namespace layer_tops_test {

using namespace printer;

namespace {

template <class F>
std::string config_error(F&& f) {
  try {
    f();
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

void check_tops(const std::vector<double>& got, const std::vector<double>& want) {
  REQUIRE(got.size() == want.size());
  for (std::size_t i = 0; i < got.size(); ++i) CHECK(got[i] == doctest::Approx(want[i]));
}

}  // namespace

TEST_CASE("cura_layers_are_the_heights_it_extrudes_at") {
  // CuraEngine moves to the next layer's Z at the end of the layer below, before ";LAYER:n";
  // its prime "G1 F1500 E0" moves nothing; an empty last layer has a mark and no extrusion.
  const std::string cura = R"(;FLAVOR:Marlin
;LAYER_COUNT:4
;LAYER:0
M107
G0 F3600 X2.822 Y-17.543 Z0.3
;TYPE:SKIRT
G1 F1500 E0
G1 F1200 X3.5 Y-17.2 E0.0284
G1 X4.1 Y-16.9 E0.0561
;TIME_ELAPSED:89.4
G0 F600 X-6.189 Y6.255 Z0.6
;LAYER:1
G1 F2700 X9.297 Y-1.229 E1.2665
G0 F600 X-6.255 Y-6.189 Z0.75
;LAYER:2
G1 F3600 X9.345 Y-0.001 E1.6566
G1 X9.277 Y1.016 E1.7188
;LAYER:3
G0 F600 X0 Y0 Z0.9
;TIME_ELAPSED:120.0
G1 F2700 E-5
M84
)";
  check_tops(layer_tops_from_gcode(cura, "cura.gcode"), {0.3, 0.6, 0.75});
}

TEST_CASE("prusaslicer_layers_are_the_heights_it_extrudes_at") {
  // PrusaSlicer: ";LAYER_CHANGE", ";Z:", ";HEIGHT:", the Z move, then extrusion; a lift for
  // a travel ("G1 Z.8 ... ; lift Z") extrudes nothing; relative E (M83).
  const std::string prusa = R"(M83 ; use relative distances for extrusion
;LAYER_CHANGE
;Z:0.3
;HEIGHT:0.3
G1 Z.3 F7800
G1 X60.142 Y67.61 F7800
G1 F1200
G1 X62.451 Y66.001 E.09317
G1 E-1 F1800
G1 Z.8 F7800 ; lift Z
G1 X70 Y70 F7800
G1 Z.3 F7800
G1 E1 F1500
G1 X71 Y70 E.04
;LAYER_CHANGE
;Z:0.45
;HEIGHT:0.15
G1 Z.45 F7800
G1 X63.132 Y66.001 E.06123
;LAYER_CHANGE
;Z:0.7
;HEIGHT:0.25
G1 Z.7 F7800
G1 X64.01 Y66.2 E.05
)";
  check_tops(layer_tops_from_gcode(prusa, "prusa.gcode"), {0.3, 0.45, 0.7});
}

TEST_CASE("slic3r_layers_are_the_heights_it_extrudes_at") {
  // Slic3r 1.3 writes no layer comments: the start G-code lifts to Z5 without extruding,
  // then one "G1 Z... F7800.000" per layer; absolute E (M82) with G92 E0 resets.
  const std::string slic3r = R"(G28 ; home all axes
G1 Z5 F5000 ; lift nozzle
M82 ; use absolute distances for extrusion
G92 E0
G1 Z0.350 F7800.000
G1 E-2.00000 F2400.00000
G92 E0
G1 X88.211 Y91.000 F7800.000
G1 E2.00000 F2400.00000
G1 X111.789 Y91.000 E3.12345 F1200.000
G1 Z0.500 F7800.000
G1 X101.337 Y100.242 F7800.000
G1 X102.000 Y100.900 E3.18000
G92 E0
G1 Z0.650 F7800.000
G1 X103.000 Y100.900 E0.05000
G1 Z0.801 F7800.000
G1 X104.000 Y100.900 E0.10000
)";
  check_tops(layer_tops_from_gcode(slic3r, "slic3r.gcode"), {0.35, 0.5, 0.65, 0.801});
}

TEST_CASE("mahost_layers_read_back_from_its_own_gcode") {
  const std::string ours = R"(G90
M82
G92 E0
;LAYER:0
;Z:0.3
;HEIGHT:0.3
M73 P0 R60
G92 E0
G1 Z0.3 F480
G0 X10 Y10 F7200
G1 X20 Y10 E0.5 F900
;LAYER:1
;Z:0.45
;HEIGHT:0.15
M73 P1 R59
G92 E0
G1 E-1 F1800
G1 Z0.45 F480
G0 X12 Y12 F7200
G1 E0 F1500
G1 X22 Y12 E0.3 F900
)";
  check_tops(layer_tops_from_gcode(ours, "ours.gcode"), {0.3, 0.45});
}

TEST_CASE("mahost_layers_on_a_raft_are_the_parts_layers_as_on_the_bed") {
  // Two raft layers (0.3, 0.5), an air gap of 0.2 mm, then the part's 0.3 and 0.15 mm
  // layers: the header says the part stands 0.7 mm up.
  const std::string ours = R"(; raft: 2 layers, 0.70 mm under the part (air gap 0.2 mm), margin 3 mm
G90
M82
;LAYER:0
;Z:0.3
G1 Z0.3 F480
;TYPE:RAFT
G1 X10 Y10 E1 F900
;LAYER:1
;Z:0.5
G1 Z0.5 F480
;TYPE:RAFT
G1 X20 Y10 E2 F900
;LAYER:2
;Z:1
G1 Z1.0 F480
G1 X20 Y20 E3 F900
;LAYER:3
;Z:1.15
G1 Z1.15 F480
G1 X10 Y20 E4 F900
)";
  check_tops(layer_tops_from_gcode(ours, "ours.gcode"), {0.3, 0.45});
}

TEST_CASE("gcode_that_is_not_one_stack_of_layers_is_refused") {
  // Two objects printed one after another: Z goes back down.
  const std::string sequential = "G1 Z0.2\nG1 X1 Y0 E1\nG1 Z0.4\nG1 X2 Y0 E2\nG1 Z0.2\nG1 X3 Y0 E3\n";
  CHECK(config_error([&] { layer_tops_from_gcode(sequential, "seq.gcode"); }) ==
        "seq.gcode: line 6 extrudes at Z 0.2 mm, below the layer at 0.4 mm printed before it; "
        "the file is not one part printed layer by layer (several objects one after another?), "
        "so it gives no layer boundaries");
  CHECK(config_error([&] { layer_tops_from_gcode("G28\nG1 Z5\nG1 X10 Y10\n", "empty.gcode"); }) ==
        "empty.gcode: the G-code extrudes nothing, so it gives no layer boundaries");
  // A spiral vase rises along its moves.
  const std::string vase = "G1 Z0.2\nG1 X1 Y0 E1\nG1 X2 Y0 Z0.201 E2\nG1 X3 Y0 Z0.202 E3\n";
  CHECK(config_error([&] { layer_tops_from_gcode(vase, "vase.gcode"); }).starts_with(
      "vase.gcode: it extrudes at Z 0.2 and then 0.201 mm"));
  // Relative moves (G91) are followed: this extrudes at 0.2, then 0.4.
  const std::string relative = "G1 Z0.2\nG1 X1 Y0 E1\nG91\nG1 Z0.2\nG1 X1 E1\nG90\n";
  check_tops(layer_tops_from_gcode(relative, "rel.gcode"), {0.2, 0.4});
}

TEST_CASE("homing_firmware_retraction_and_inches_are_followed") {
  // G28 Z puts Z at 0 before a relative rise; a G10/G11 pair with a Z-raise lays nothing and
  // leaves Z; G20 reads inches.
  const std::string program =
      "G1 Z5\nG28 Z\nG91\nG1 Z0.3\nG90\nG1 X10 Y10 E1\nM207 Z1\nG10\nG0 X20\nG11\n"
      "G1 X30 E2\nG20\nG1 Z0.023622047\nG21\nG1 X40 E3\n";
  check_tops(layer_tops_from_gcode(program, "rules.gcode"), {0.3, 0.6});
}

TEST_CASE("layer_top_lists_take_commas_lines_and_comments") {
  check_tops(layer_tops_from_list("0.3, 0.5,0.7", "--boundaries"), {0.3, 0.5, 0.7});
  check_tops(layer_tops_from_list("# tops, mm\n0.3\n0.45  # thin\n\n0.85\n", "plan.txt"),
             {0.3, 0.45, 0.85});
  CHECK(config_error([] { layer_tops_from_list("0.3,0.2", "--boundaries"); }) ==
        "--boundaries: layer top 0.2 mm is not above the one before it (0.3 mm); give the tops "
        "rising");
  CHECK(config_error([] { layer_tops_from_list("0.3\nabc\n", "plan.txt"); }) ==
        "plan.txt line 2: 'abc' is not a layer top in mm (give positive numbers, e.g. "
        "0.3,0.5,0.7)");
  CHECK(config_error([] { layer_tops_from_list("# nothing\n", "plan.txt"); }) ==
        "plan.txt: no layer tops in it; give numbers in mm, e.g. 0.3,0.5,0.7");
  CHECK(config_error([] { layer_tops_from_list("-0.3", "--boundaries"); }).starts_with(
      "--boundaries: '-0.3' is not a layer top"));
}

TEST_CASE("boundaries_argument_is_a_file_or_a_list") {
  check_tops(read_layer_tops("0.3,0.6"), {0.3, 0.6});
  const auto dir = std::filesystem::temp_directory_path() / ("layer-tops-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const std::string list = (dir / "plan.txt").string(), gcode = (dir / "peer.gcode").string();
  std::ofstream(list) << "0.3\n0.5\n";
  std::ofstream(gcode) << ";LAYER:0\nG1 Z0.3\nG1 X1 Y1 E1\n;LAYER:1\nG1 Z0.55\nG1 X2 Y1 E2\n";
  check_tops(read_layer_tops(list), {0.3, 0.5});
  check_tops(read_layer_tops(gcode), {0.3, 0.55});
  CHECK(config_error([&] { read_layer_tops((dir / "missing.gcode").string()); }) ==
        "--boundaries " + (dir / "missing.gcode").string() +
            ": no such file, and not a list of layer tops; give a file (G-code, or one top per "
            "line) or tops in mm, e.g. --boundaries 0.3,0.5,0.7");
  std::filesystem::remove_all(dir);
}

}  // namespace layer_tops_test
