// `mahost slice` as a user runs it: the G-code it writes, read back as a printer would lay it
// (tests/support/gcode_beads), against closed-form sections and the layer regions; and every
// kind of bad input refused in one line with exit code 2.
#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <doctest/doctest.h>

#include "geometry/slicing/layer_stack.h"
#include "geometry/contour/ma_contour.h"
#include "geometry/mesh/placement.h"
#include "geometry/mesh/repair.h"
#include "geometry/mesh/stl_io.h"
#include "printer/layer_tops.h"
#include "printer/print_time.h"
#include "printer/profile.h"
#include "support/gcode_beads.h"
#include "support/run_command.h"
#include "support/solids.h"

namespace slice_cli_test {

using test_support::run_mahost;

namespace {

const std::string kConfigDir = MAHOST_SOURCE_DIR "/configs";
// The shipped profiles as the mahost under test finds them: its build tree's share/mahost.
const std::string kShipped = std::filesystem::path(MAHOST_BINARY).parent_path().string() + "/share/mahost";

std::string read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

geometry::Region shifted(geometry::Region region, geometry::Vec2 by) {
  for (geometry::Loop& loop : region.loops) {
    for (geometry::Vec2& p : loop) p = p + by;
  }
  return region;
}

// Checks each printed layer's beads against `region_of(layer index)`: at least 98% of the
// region covered, at most 2% of its area outside it. A region under `min_area` is only held to
// staying inside, and may spill up to half a bead's square (0.125 mm^2 for 0.5 mm beads): a
// sliver a bead wide cannot be drawn to 2% with beads of one width, nor filled to 98%.
// Returns the least share covered of a layer held to 98%, and which layer that is.
template <class RegionOf>
std::pair<double, std::size_t> check_coverage(const test_support::PrintedProgram& program,
                                              RegionOf&& region_of, double min_area = 0) {
  std::pair<double, std::size_t> least{1.0, 0};
  for (std::size_t i = 0; i < program.layers.size(); ++i) {
    const geometry::Region region = region_of(i);
    const double area = geometry::area(region);
    if (!(area > 0)) continue;
    CAPTURE(i);
    CAPTURE(area);
    const test_support::Coverage c =
        test_support::coverage(test_support::bead_region(program.layers[i]), region);
    if (area >= min_area) {
      CHECK(c.covered >= 0.98);
      CHECK(c.outside <= 0.02);
      if (c.covered < least.first) least = {c.covered, i};
    } else {
      CHECK(c.outside * area <= std::max(0.02 * area, 0.125));
    }
  }
  return least;
}

}  // namespace

TEST_CASE("slice_writes_gcode_and_reports_one_line") {
  const std::string dir = test_support::scratch_dir("slice_writes_gcode");
  const std::string stl = dir + "/cube.stl", out = dir + "/cube.gcode";
  geometry::write_stl_binary(stl, solids::cube(20).mesh);
  const auto result = run_mahost({"slice", stl, "-o", out, "--contour", "mid"});
  CHECK(result.exit_code == 0);
  CHECK(result.err.empty());
  // UP Plus 2 defaults: 0.3 mm first layer, then 0.2 up to the flat top, which lands on a
  // boundary at 20.0 mm: 19.7 mm, 98.5 layers of 0.2, = 97 x 0.2 + 2 x 0.15 (half way: the two
  // under the top a step thinner, not 96 x 0.2 + 2 x 0.25), 1 + 99 = 100 layers, on a raft of
  // 4 (base, interface, two surface layers). A cube needs no support.
  CHECK(result.out.starts_with(out + ": 100 layers, on 4 raft layers, estimated print time "));
  CHECK(result.out.find(" g ABS; ") != std::string::npos);
  CHECK(result.out.find(" m of it support and raft), ") != std::string::npos);
  CHECK(std::count(result.out.begin(), result.out.end(), '\n') == 1);
  const std::string gcode = read_file(out);
  const test_support::PrintedProgram program = test_support::read_printed_program(gcode);
  CHECK(program.layers.size() == 104);
  CHECK(program.header.at("LAYER_COUNT") == "104");
  CHECK(program.layers.back().z == doctest::Approx(20.0 + 1.1));  // on the 1.1 mm raft
  CHECK(gcode.find(";TYPE:RAFT\n") != std::string::npos);
  CHECK(gcode.find(";TYPE:SUPPORT\n") == std::string::npos);
  CHECK(program.problems.empty());
  CHECK_FALSE(std::filesystem::exists(out + ".part"));
}

TEST_CASE("each_set_takes_one_key_and_the_model_may_follow") {
  const std::string dir = test_support::scratch_dir("slice_set_order");
  const std::string stl = dir + "/cube.stl", out = dir + "/cube.gcode";
  geometry::write_stl_binary(stl, solids::cube(10).mesh);
  const auto result = run_mahost({"slice", "--set", "print.perimeters=3", stl, "--set",
                                  "print.infill_density=15", "-o", out, "--contour", "mid"});
  CHECK(result.exit_code == 0);
  CHECK(read_file(out).find("; perimeters: 3, infill: 15% grid") != std::string::npos);
}

TEST_CASE("cube_with_hole_beads_cover_each_layer") {
  const std::string dir = test_support::scratch_dir("slice_cube_with_hole");
  const std::string stl = dir + "/part.stl", out = dir + "/part.gcode";
  const solids::Solid part = solids::cube_with_round_hole(20, 5, 48);
  geometry::write_stl_binary(stl, part.mesh);
  const auto result = run_mahost({"slice", stl, "-o", out, "--printer", "generic-marlin",
                                  "--layer", "0.25", "--contour", "mid", "--infill", "100", "--set", "print.infill_pattern=rectilinear",
                                  "--set", "print.skirt_loops=0"});
  REQUIRE(result.exit_code == 0);
  const printer::PrinterProfile marlin = printer::load_printer_profile("generic-marlin", kConfigDir);
  const test_support::PrintedProgram program = test_support::read_printed_program(read_file(out));
  // A 0.2 mm first layer, then 0.25 up to the top, which lands on a boundary at 20.0 mm:
  // 19.8 mm = 74 x 0.25 + 5 x 0.26 (generic-marlin's 0.01 mm step, one on each of the five
  // layers under the top), 1 + 79 = 80 layers.
  const auto tops = printer::layer_tops_from_gcode(read_file(out), out);
  const auto layers = geometry::layers_from_tops(tops);
  REQUIRE(program.layers.size() == layers.size());
  CHECK(program.layers.size() == 80);
  CHECK(layers.back().z_hi == doctest::Approx(20.0));
  for (std::size_t i = 1; i < layers.size(); ++i) {
    CHECK(layers[i].thickness() == doctest::Approx(i + 5 < layers.size() ? 0.25 : 0.26));
  }
  // The exact section is the same at every height: the square less the 48-gon hole.
  const auto [least, at] = check_coverage(program, [&](std::size_t i) {
    return shifted(part.section(layers[i].z_mid()), {marlin.bed_x / 2, marlin.bed_y / 2});
  });
  MESSAGE("holed cube: least covered " << least << " on layer " << at);
}

TEST_CASE("every_contour_strategy_prints_a_vertical_wall_part_alike") {
  // Walls straight up: every strategy's region is the section, so the beads cover it the same
  // on every layer, the last too, since the flat top lands on a boundary: [11.75, 12.0], not
  // [11.9, 12.1] (whose middle is above the part: mid and optimal-height printed nothing).
  const std::string dir = test_support::scratch_dir("slice_contours");
  const std::string stl = dir + "/part.stl";
  const solids::Solid part = solids::cube_with_square_hole(12, 4);
  geometry::write_stl_binary(stl, part.mesh);
  const printer::PrinterProfile up = printer::load_printer_profile("up-plus-2", kConfigDir);
  double top_filament = -1;
  for (const std::string contour : {"lower", "mid", "optimal-height", "ma", "best"}) {
    CAPTURE(contour);
    const std::string out = dir + "/" + contour + ".gcode";
    const auto result = run_mahost({"slice", stl, "--support", "none", "--no-raft", "-o", out, "--contour", contour, "--infill", "100",
                                    "--set", "print.infill_pattern=rectilinear", "--set",
                                    "print.skirt_loops=0"});
    REQUIRE(result.exit_code == 0);
    const test_support::PrintedProgram program = test_support::read_printed_program(read_file(out));
    // 0.3 mm, then 11.7 mm = 57 x 0.2 + 2 x 0.15 up to the top at 12.0 (58.5 layers of 0.2:
    // half way, thinner): 1 + 59 layers.
    CHECK(program.layers.size() == 1 + 59);
    CHECK(read_file(out).find("; contour: " + contour + "\n") != std::string::npos);
    const auto layers = geometry::layers_from_tops(printer::layer_tops_from_gcode(read_file(out), out));
    REQUIRE(layers.size() == program.layers.size());
    CHECK(layers.back().z_hi == doctest::Approx(12.0));
    check_coverage(program, [&](std::size_t i) {
      return shifted(part.section(layers[i].z_mid()), {up.bed_x / 2, up.bed_y / 2});
    });
    // The top layer is laid alike by every strategy (the section there is the whole part's).
    if (top_filament < 0) top_filament = program.layers.back().filament;
    CHECK(program.layers.back().filament == doctest::Approx(top_filament).epsilon(1e-3));
    CHECK(top_filament > 0);
  }
}

TEST_CASE("sphere_beads_cover_each_layer") {
  const std::string dir = test_support::scratch_dir("slice_sphere");
  const std::string stl = dir + "/sphere.stl", out = dir + "/sphere.gcode";
  const solids::Solid sphere = solids::sphere(12, 96, 48, {0, 0, 12});
  geometry::write_stl_binary(stl, sphere.mesh);
  const auto result = run_mahost({"slice", stl, "--support", "none", "--no-raft", "-o", out, "--contour", "mid", "--layer", "0.2",
                                  "--infill", "100", "--set", "print.infill_pattern=rectilinear", "--set", "print.skirt_loops=0"});
  REQUIRE(result.exit_code == 0);
  const printer::PrinterProfile up = printer::load_printer_profile("up-plus-2", kConfigDir);
  const test_support::PrintedProgram program = test_support::read_printed_program(read_file(out));
  const auto layers = geometry::uniform_layers(24, 0.2, up.first_layer_height);
  REQUIRE(program.layers.size() == layers.size());
  // Every layer, the poles' small discs too: the infill lines join into zig-zags along the
  // inner wall and gap fill takes what their ends leave.
  const auto [least, at] = check_coverage(program, [&](std::size_t i) {
    return shifted(sphere.section(layers[i].z_mid()), {up.bed_x / 2, up.bed_y / 2});
  });
  MESSAGE("sphere: least covered " << least << " on layer " << at);
}

TEST_CASE("bunny_ma_layers_are_covered_inside_the_bed_and_timed_exactly") {
  const std::string dir = test_support::scratch_dir("slice_bunny");
  const std::string stl = MAHOST_DATA_DIR "/bunny.stl", out = dir + "/bunny.gcode";
  const auto result = run_mahost({"slice", stl, "--support", "none", "--no-raft", "--up", "y", "--units", "m", "--height", "50",
                                  "-o", out, "--layer", "0.2", "--contour", "ma", "--infill", "100", "--set", "print.infill_pattern=rectilinear",
                                  "--set", "print.skirt_loops=0"});
  REQUIRE(result.exit_code == 0);
  const std::string gcode = read_file(out);
  const printer::PrinterProfile up = printer::load_printer_profile("up-plus-2", kConfigDir);
  const test_support::PrintedProgram program = test_support::read_printed_program(gcode);

  // 50 mm: 0.3 mm first layer, then 0.2 mm: 1 + ceil(49.7 / 0.2) = 250 layers.
  CHECK(program.layers.size() == 250);
  CHECK(program.header.at("LAYER_COUNT") == "250");
  for (std::size_t i = 0; i < program.layers.size(); ++i) CHECK(program.layers[i].number == long(i));
  CHECK(program.problems.empty());

  CHECK(program.min_xy.x >= 0);
  CHECK(program.min_xy.y >= 0);
  CHECK(program.max_xy.x <= up.bed_x);
  CHECK(program.max_xy.y <= up.bed_y);
  CHECK(program.max_z <= up.bed_z);

  const double reread = printer::estimate_print_time(gcode, up.motion);
  CHECK(std::abs(std::stod(program.header.at("PRINT_TIME_S")) - reread) <= 0.0005);

  // The layer regions, computed here the way mahost does: the same file, repair, placement.
  geometry::RepairReport report;
  geometry::Placement placement;
  placement.units_to_mm = 1000;
  placement.height = 50;
  placement.up = geometry::Axis::y;
  const geometry::Mesh mesh = geometry::place(
      geometry::repair(geometry::read_stl(stl), &report), placement);
  const auto layers = geometry::uniform_layers(50, 0.2, up.first_layer_height);
  REQUIRE(layers.size() == program.layers.size());
  const geometry::LayerStack stack(mesh, layers);
  const auto [least, at] = check_coverage(
      program,
      [&](std::size_t i) {
        return shifted(geometry::ma_contour(stack, i), {up.bed_x / 2, up.bed_y / 2});
      },
      /*min_area=*/80.0);  // as for the sphere: the ears' tips are small discs
  MESSAGE("bunny: least covered " << least << " on layer " << at);
}

TEST_CASE("layer_not_allowed_by_the_printer_is_refused_with_the_list") {
  const std::string dir = test_support::scratch_dir("slice_bad_layer");
  const std::string stl = dir + "/cube.stl";
  geometry::write_stl_binary(stl, solids::cube(10).mesh);
  const auto result = run_mahost({"slice", stl, "-o", dir + "/cube.gcode", "--layer", "0.17"});
  CHECK(result.exit_code == 2);
  CHECK(result.err == "mahost: layer thickness 0.17 mm is not allowed on the UP Plus 2 (" +
                          kShipped + "/printers/up-plus-2.toml); allowed: 0.15, 0.2, 0.25, "
                          "0.3, 0.35, 0.4 mm\n");
  CHECK_FALSE(std::filesystem::exists(dir + "/cube.gcode"));
}

TEST_CASE("part_whose_last_layer_ends_above_the_build_height_is_refused_before_slicing") {
  // The UP Plus 2 builds 135 mm high; a 135 mm cone (its top a point: no flat level to land a
  // boundary on) in 0.2 mm layers after a 0.3 mm first layer needs 673.5 of them, so its last
  // layer ends at 135.1 mm. 134.9 mm is the tallest part whose layers fit (0.3 + 673 x 0.2).
  const std::string dir = test_support::scratch_dir("slice_last_layer_too_high");
  const std::string stl = dir + "/cube.stl";
  geometry::write_stl_binary(stl, solids::cone(1, 10, 32).mesh);
  const auto result =
      run_mahost({"slice", stl, "-o", dir + "/cube.gcode", "--height", "135", "--no-raft"});
  CHECK(result.exit_code == 2);
  CHECK(result.err == "mahost: the part is 135.00 mm tall, but its last layer of 0.2 mm ends at "
                      "135.10 mm, above the UP Plus 2's build height of 135 mm; make the part at "
                      "most 134.90 mm tall (--height 134.90), or choose a bigger printer "
                      "(--printer)\n");
  CHECK_FALSE(std::filesystem::exists(dir + "/cube.gcode"));
  // With a z-hop the travels over the last layer must fit too.
  const auto hop = run_mahost({"slice", stl, "-o", dir + "/cube.gcode", "--height", "134.9",
                               "--set", "retraction.z_hop=0.5", "--no-raft"});
  CHECK(hop.exit_code == 2);
  CHECK(hop.err.find("ends at 134.90 mm and travels lift 0.5 mm more") != std::string::npos);
  CHECK(hop.err.find("(--height 134.50)") != std::string::npos);
  // On the profile's raft (0.3 + 3 x 0.2 mm and a 0.2 mm air gap: 1.1 mm) the part's layers
  // end 1.1 mm higher: 133.9 mm is the tallest that fits (0.3 + 668 x 0.2 + 1.1 = 135).
  const auto raft = run_mahost({"slice", stl, "-o", dir + "/cube.gcode", "--height", "134"});
  CHECK(raft.exit_code == 2);
  CHECK(raft.err == "mahost: the part is 134.00 mm tall, but on its 1.10 mm raft its last layer "
                    "of 0.2 mm ends at 135.20 mm, above the UP Plus 2's build height of 135 mm; "
                    "make the part at most 133.90 mm tall (--height 133.90), print it without "
                    "the raft (--no-raft), or choose a bigger printer (--printer)\n");
}

TEST_CASE("bad_set_is_refused_naming_the_key") {
  const std::string dir = test_support::scratch_dir("slice_bad_set");
  const std::string stl = dir + "/cube.stl";
  geometry::write_stl_binary(stl, solids::cube(10).mesh);
  auto result = run_mahost({"slice", stl, "-o", dir + "/c.gcode", "--set", "retraction.length=25"});
  CHECK(result.exit_code == 2);
  CHECK(result.err == "mahost: --set retraction.length=25: key 'retraction.length' = 25 is not "
                      "allowed; it must be a number from 0 to 20 mm\n");
  result = run_mahost({"slice", stl, "-o", dir + "/c.gcode", "--set", "speed.wall=30"});
  CHECK(result.exit_code == 2);
  CHECK(result.err.starts_with("mahost: --set speed.wall=30: unknown key 'speed.wall'; keys "
                               "under 'speed': outer_wall, inner_wall,"));
}

TEST_CASE("unknown_printer_is_refused_with_the_available_ones") {
  const std::string dir = test_support::scratch_dir("slice_bad_printer");
  const std::string stl = dir + "/cube.stl";
  geometry::write_stl_binary(stl, solids::cube(10).mesh);
  ::setenv("MAHOST_CONFIG_DIR", kConfigDir.c_str(), 1);
  const auto result = run_mahost({"slice", stl, "-o", dir + "/c.gcode", "--printer", "ender9"});
  ::unsetenv("MAHOST_CONFIG_DIR");
  CHECK(result.exit_code == 2);
  CHECK(result.err == "mahost: printer profile 'ender9' not found in " + kConfigDir +
                          "/printers (available: generic-marlin, up-plus-2); give one of these "
                          "names or a path to a .toml file\n");
}

TEST_CASE("config_dir_from_the_environment_is_used") {
  const std::string dir = test_support::scratch_dir("slice_config_env");
  std::filesystem::create_directories(dir + "/configs/printers");
  std::filesystem::create_directories(dir + "/configs/materials");
  std::filesystem::copy_file(kConfigDir + "/materials/pla.toml", dir + "/configs/materials/pla.toml");
  std::string profile = read_file(kConfigDir + "/printers/generic-marlin.toml");
  const std::string name = "name = \"Generic Marlin\"";
  profile.replace(profile.find(name), name.size(), "name = \"Workshop Printer\"");
  std::ofstream(dir + "/configs/printers/workshop.toml") << profile;
  const std::string stl = dir + "/cube.stl";
  geometry::write_stl_binary(stl, solids::cube(5).mesh);
  ::setenv("MAHOST_CONFIG_DIR", (dir + "/configs").c_str(), 1);
  const auto result = run_mahost({"slice", stl, "-o", dir + "/c.gcode", "--printer", "workshop",
                                  "--contour", "mid"});
  ::unsetenv("MAHOST_CONFIG_DIR");
  CHECK(result.err == "");
  CHECK(result.exit_code == 0);
  CHECK(read_file(dir + "/c.gcode").find("; printer: Workshop Printer") != std::string::npos);
}

TEST_CASE("part_too_big_for_the_bed_is_refused_with_both_sizes") {
  const std::string dir = test_support::scratch_dir("slice_too_big");
  const std::string stl = dir + "/big.stl";
  geometry::write_stl_binary(stl, solids::box({0, 0, 0}, {150, 60, 30}).mesh);
  const auto result = run_mahost({"slice", stl, "-o", dir + "/big.gcode"});
  CHECK(result.exit_code == 2);
  CHECK(result.err == "mahost: the part is 150.0 x 60.0 x 30.0 mm but the UP Plus 2 builds at "
                      "most 140 x 140 x 135 mm; scale it down (--scale, --height) or choose a "
                      "bigger printer (--printer)\n");
  CHECK_FALSE(std::filesystem::exists(dir + "/big.gcode"));
  // The same part fits the generic printer's 220 mm bed.
  CHECK(run_mahost({"slice", stl, "-o", dir + "/big.gcode", "--printer", "generic-marlin",
                    "--contour", "mid"}).exit_code == 0);
}

TEST_CASE("bad_flags_are_refused_with_exit_code_2") {
  const std::string dir = test_support::scratch_dir("slice_bad_flags");
  const std::string stl = dir + "/cube.stl";
  geometry::write_stl_binary(stl, solids::cube(10).mesh);
  for (const std::vector<std::string>& args : std::vector<std::vector<std::string>>{
           {"slice", stl, "-o", dir + "/c.gcode", "--contour", "median"},
           {"slice", stl, "-o", dir + "/c.gcode", "--infill", "120"},
           {"slice", stl, "-o", dir + "/c.gcode", "--perimeters", "-1"},
           {"slice", stl, "-o", dir + "/c.gcode", "--layer", "abc"},
           {"slice", stl},
           {"slice", dir + "/missing.stl", "-o", dir + "/c.gcode"}}) {
    const auto result = run_mahost(args);
    CAPTURE(args.back());
    CHECK(result.exit_code == 2);
    CHECK(std::count(result.err.begin(), result.err.end(), '\n') == 1);
    CHECK(result.err.starts_with("mahost: "));
  }
}

TEST_CASE("a_number_out_of_range_is_refused_with_the_range_as_a_user_reads_it") {
  const std::string dir = test_support::scratch_dir("slice_bad_numbers");
  const std::string stl = dir + "/cube.stl";
  geometry::write_stl_binary(stl, solids::cube(10).mesh);
  const std::vector<std::pair<std::vector<std::string>, std::string>> cases{
      {{"--layer", "-1"}, "--layer: needs a number greater than 0, not '-1'"},
      {{"--layer", "inf"}, "--layer: needs a number greater than 0, not 'inf'"},
      {{"--tolerance", "0"}, "--tolerance: needs a number greater than 0, not '0'"},
      {{"--brim", "-3"}, "--brim: needs a number from 0 to 50, not '-3'"},
      {{"--overhang-angle", "95"}, "--overhang-angle: needs a number from 0 to 89, not '95'"},
      {{"--infill", "nan"}, "--infill: needs a number from 0 to 100, not 'nan'"},
      {{"--perimeters", "x"}, "--perimeters: needs a whole number from 0 to 50, not 'x'"},
      {{"--max-layers", "1.5"}, "--max-layers: needs a whole number from 1 to 100000, not '1.5'"}};
  for (const auto& [flag, message] : cases) {
    std::vector<std::string> args{"slice", stl, "-o", dir + "/c.gcode"};
    args.insert(args.end(), flag.begin(), flag.end());
    const auto result = run_mahost(args);
    CAPTURE(result.err);
    CHECK(result.exit_code == 2);
    CHECK(result.err == "mahost: " + message + " (see mahost --help)\n");
  }
  // In range, the same flags are taken.
  const auto fine = run_mahost({"slice", stl, "-o", dir + "/c.gcode", "--brim", "0",
                                "--overhang-angle", "89", "--layer", "0.2", "--infill", "100"});
  CHECK(fine.exit_code == 0);
}

TEST_CASE("unwritable_output_is_refused_naming_it") {
  const std::string dir = test_support::scratch_dir("slice_unwritable");
  const std::string stl = dir + "/cube.stl";
  geometry::write_stl_binary(stl, solids::cube(10).mesh);
  const auto result = run_mahost({"slice", stl, "-o", dir + "/no/such/folder/c.gcode",
                                  "--contour", "mid"});
  CHECK(result.exit_code == 2);
  CHECK(result.err.starts_with("mahost: cannot write '" + dir + "/no/such/folder/c.gcode'"));
}

}  // namespace slice_cli_test
