// Printer and material profiles: the shipped files load with the machine's figures, and every
// kind of bad key or value is refused with a message naming the file, the key and what is allowed.
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <string>

#include <doctest/doctest.h>

#include "printer/error.h"
#include "printer/profile.h"
#include "support/run_command.h"

namespace profile_test {

using namespace printer;

namespace {

const std::string kConfigDir = MAHOST_SOURCE_DIR "/configs";

// The message a ConfigError carries, or "" if `f` does not throw one.
template <class F>
std::string config_error(F&& f) {
  try {
    f();
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

// A small valid printer profile to break one key at a time.
const std::string kMinimalPrinter = R"(name = "Test"
[build_volume]
x = 100
y = 120
z = 80
[nozzle]
diameter = 0.4
[filament]
diameter = 1.75
)";

}  // namespace

TEST_CASE("up_plus_2_profile_has_the_machine_figures") {
  const PrinterProfile p = load_printer_profile("up-plus-2", kConfigDir);
  CHECK(p.name == "UP Plus 2");
  CHECK(p.source == kConfigDir + "/printers/up-plus-2.toml");
  CHECK(p.bed_x == 140);
  CHECK(p.bed_y == 140);
  CHECK(p.bed_z == 135);
  CHECK(p.nozzle_diameter == 0.4);
  CHECK(p.filament_diameter == 1.75);
  CHECK(p.baud == 115200);
  CHECK(p.default_material == "abs");
  CHECK(p.layer.describe() == "0.15, 0.2, 0.25, 0.3, 0.35, 0.4 mm");
  for (double t : {0.15, 0.2, 0.25, 0.3, 0.35, 0.4}) CHECK(p.layer.allows(t));
  for (double t : {0.1, 0.17, 0.225, 0.45}) CHECK_FALSE(p.layer.allows(t));
}

TEST_CASE("generic_marlin_allows_layers_from_0_05_to_0_3_in_steps_of_0_01") {
  const PrinterProfile p = load_printer_profile("generic-marlin", kConfigDir);
  CHECK(p.bed_x == 220);
  CHECK(p.bed_y == 220);
  CHECK(p.bed_z == 250);
  CHECK(p.relative_e);
  CHECK(p.layer.describe() == "0.05 to 0.3 mm in steps of 0.01 mm");
  for (double t : {0.05, 0.17, 0.12, 0.3}) CHECK(p.layer.allows(t));
  for (double t : {0.04, 0.31, 0.123}) CHECK_FALSE(p.layer.allows(t));
}

TEST_CASE("materials_have_temperatures_fan_flow_density") {
  const MaterialProfile abs = load_material_profile("abs", kConfigDir);
  CHECK(abs.name == "ABS");
  CHECK(abs.nozzle_temperature == 245);
  CHECK(abs.first_layer_bed_temperature == 105);
  CHECK(abs.fan_speed == 0);
  CHECK(abs.density == 1.04);
  const MaterialProfile pla = load_material_profile("pla", kConfigDir);
  CHECK(pla.fan_speed == 100);
  CHECK(pla.fan_start_layer == 1);
  CHECK(pla.flow == 1.0);
}

TEST_CASE("first_layer_temperatures_default_to_the_regular_ones") {
  const MaterialProfile m = parse_material_profile(
      "name = \"X\"\n[temperature]\nnozzle = 200\nbed = 55\n", "x.toml");
  CHECK(m.first_layer_nozzle_temperature == 200);
  CHECK(m.first_layer_bed_temperature == 55);
}

TEST_CASE("layer_not_on_the_printers_steps_is_refused_with_the_allowed_list") {
  const PrinterProfile p = load_printer_profile("up-plus-2", kConfigDir);
  CHECK(config_error([&] { check_layer_thickness(p, 0.17); }) ==
        "layer thickness 0.17 mm is not allowed on the UP Plus 2 (" + kConfigDir +
            "/printers/up-plus-2.toml); allowed: 0.15, 0.2, 0.25, 0.3, 0.35, 0.4 mm");
  CHECK(config_error([&] { check_layer_thickness(p, 0.25); }).empty());
}

TEST_CASE("unknown_key_names_file_line_and_the_keys_of_its_section") {
  const std::string text = kMinimalPrinter + "[speed]\nouter_wal = 30\n";
  CHECK(config_error([&] { parse_printer_profile(text, "my.toml"); }) ==
        "my.toml:11: unknown key 'speed.outer_wal'; keys under 'speed': outer_wall, inner_wall, "
        "thin_wall, skirt, top_skin, bottom_skin, solid_infill, sparse_infill, support, "
                "support_interface, bridge, brim, raft, travel, z");
}

TEST_CASE("unknown_section_lists_the_known_ones") {
  const std::string text = kMinimalPrinter + "[sped]\nouter_wall = 30\n";
  const std::string message = config_error([&] { parse_printer_profile(text, "my.toml"); });
  CHECK(message.starts_with("my.toml:11: unknown key 'sped.outer_wall'; known sections and keys: "));
  CHECK(message.find("speed") != std::string::npos);
  CHECK(message.find("retraction") != std::string::npos);
}

TEST_CASE("wrong_type_names_the_key_and_the_expected_type") {
  std::string text = kMinimalPrinter;
  text.replace(text.find("diameter = 0.4"), 14, "diameter = \"0.4\"");
  CHECK(config_error([&] { parse_printer_profile(text, "my.toml"); }) ==
        "my.toml:7: key 'nozzle.diameter' must be a number from 0.1 to 2 mm, not a string");
}

TEST_CASE("whole_number_key_refuses_a_fraction") {
  const std::string text = kMinimalPrinter + "[print]\nperimeters = 2.5\n";
  CHECK(config_error([&] { parse_printer_profile(text, "my.toml"); }) ==
        "my.toml:11: key 'print.perimeters' must be a whole number from 0 to 50, not a number");
}

TEST_CASE("out_of_range_value_names_the_range") {
  std::string text = kMinimalPrinter;
  text.replace(text.find("x = 100"), 7, "x = 5");
  CHECK(config_error([&] { parse_printer_profile(text, "my.toml"); }) ==
        "my.toml:3: key 'build_volume.x' = 5 is not allowed; it must be a number from 10 to 2000 mm");
}

TEST_CASE("text_choice_names_the_choices") {
  const std::string text = kMinimalPrinter + "[print]\ninfill_pattern = \"honeycomb\"\n";
  CHECK(config_error([&] { parse_printer_profile(text, "my.toml"); }) ==
        "my.toml:11: key 'print.infill_pattern' = \"honeycomb\" is not allowed; it must be one "
        "of grid, rectilinear");
}

TEST_CASE("missing_required_key_is_named") {
  std::string text = kMinimalPrinter;
  text.replace(text.find("[nozzle]\ndiameter = 0.4\n"), 24, "");
  CHECK(config_error([&] { parse_printer_profile(text, "my.toml"); }) ==
        "my.toml: key 'nozzle.diameter' is missing; it must be a number from 0.1 to 2 mm");
}

TEST_CASE("toml_syntax_error_names_file_and_line") {
  const std::string message =
      config_error([&] { parse_printer_profile(kMinimalPrinter + "[speed\n", "my.toml"); });
  CHECK(message.starts_with("my.toml:10:"));
  CHECK(message.find("not valid TOML") != std::string::npos);
}

TEST_CASE("default_layer_must_be_allowed") {
  const std::string text = kMinimalPrinter + "[layer]\nallowed = [0.1, 0.2]\ndefault = 0.15\n";
  CHECK(config_error([&] { parse_printer_profile(text, "my.toml"); }) ==
        "my.toml: layer.default = 0.15 mm is not a layer thickness this printer allows "
        "(0.1, 0.2 mm)");
}

TEST_CASE("unknown_placeholder_in_start_gcode_is_refused") {
  const std::string text = kMinimalPrinter + "[gcode]\nstart = \"M104 S{hotend}\"\n";
  CHECK(config_error([&] { parse_printer_profile(text, "my.toml"); })
            .starts_with("my.toml: gcode.start: unknown placeholder '{hotend}'; known: "
                         "nozzle_temperature, first_layer_nozzle_temperature,"));
}

TEST_CASE("placeholders_expand_from_both_profiles") {
  Profiles profiles{load_printer_profile("up-plus-2", kConfigDir),
                    load_material_profile("abs", kConfigDir)};
  PlaceholderValues values;
  values.layer_height = 0.15;
  CHECK(expand_placeholders("M190 S{first_layer_bed_temperature}\nG1 X{bed_x} Y{bed_y} ; "
                            "{material_name} {layer_height}",
                            profiles, values, "test") == "M190 S105\nG1 X140 Y140 ; ABS 0.15");
}

TEST_CASE("set_overrides_a_dotted_key_with_the_same_checks") {
  Profiles profiles{load_printer_profile("up-plus-2", kConfigDir),
                    load_material_profile("abs", kConfigDir)};
  apply_override(profiles, "retraction.length=2.5");
  CHECK(profiles.printer.retraction.length == 2.5);
  apply_override(profiles, "material.temperature.nozzle=255");
  CHECK(profiles.material.nozzle_temperature == 255);
  apply_override(profiles, "printer.speed.travel = 150");
  CHECK(profiles.printer.speed.travel == 150);
  apply_override(profiles, "layer.allowed=[0.1,0.2,0.3]");
  CHECK(profiles.printer.layer.describe() == "0.1, 0.2, 0.3 mm");
  apply_override(profiles, "extrusion.e_mode=relative");
  CHECK(profiles.printer.relative_e);

  CHECK(config_error([&] { apply_override(profiles, "retraction.length=25"); }) ==
        "--set retraction.length=25: key 'retraction.length' = 25 is not allowed; it must be a "
        "number from 0 to 20 mm");
  CHECK(config_error([&] { apply_override(profiles, "retraction.length=long"); }) ==
        "--set retraction.length=long: key 'retraction.length' must be a number from 0 to 20 mm");
  CHECK(config_error([&] { apply_override(profiles, "retraction.lenght=1"); })
            .starts_with("--set retraction.lenght=1: unknown key 'retraction.lenght'; keys under "
                         "'retraction': length, speed,"));
  CHECK(config_error([&] { apply_override(profiles, "retraction.length"); })
            .starts_with("--set retraction.length: expected key=value"));
  CHECK(config_error([&] { apply_override(profiles, "material.fan.speed=120"); }) ==
        "--set material.fan.speed=120: key 'fan.speed' = 120 is not allowed; it must be a number "
        "from 0 to 100 %");
}

TEST_CASE("set_that_breaks_the_profile_as_a_whole_is_refused") {
  Profiles profiles{load_printer_profile("up-plus-2", kConfigDir),
                    load_material_profile("abs", kConfigDir)};
  const std::string message =
      config_error([&] { apply_override(profiles, "first_layer.height=0.27"); });
  CHECK(message.find("first_layer.height = 0.27 mm is not a layer thickness this printer allows "
                     "(0.15, 0.2, 0.25, 0.3, 0.35, 0.4 mm)") != std::string::npos);
  CHECK(message.ends_with("(after --set first_layer.height=0.27)"));
}

TEST_CASE("load_profiles_uses_the_printers_default_material_and_applies_overrides") {
  ProfileRequest request;
  request.printer = "up-plus-2";
  request.config_dir = kConfigDir;
  request.overrides = {"material.flow=0.95", "print.perimeters=3"};
  const Profiles profiles = load_profiles(request);
  CHECK(profiles.material.name == "ABS");
  CHECK(profiles.material.flow == 0.95);
  CHECK(profiles.printer.print.perimeters == 3);
}

TEST_CASE("profile_not_found_lists_the_available_ones") {
  CHECK(config_error([&] { load_printer_profile("prusa-mk4", kConfigDir); }) ==
        "printer profile 'prusa-mk4' not found in " + kConfigDir +
            "/printers (available: generic-marlin, up-plus-2); give one of these names or a path "
            "to a .toml file");
  CHECK(config_error([&] { load_material_profile("/nonexistent/petg.toml", kConfigDir); }) ==
        "cannot read material profile '/nonexistent/petg.toml': no such file");
}

TEST_CASE("profile_by_path_loads") {
  const PrinterProfile p =
      load_printer_profile(kConfigDir + "/printers/generic-marlin.toml", "/nonexistent");
  CHECK(p.name == "Generic Marlin");
}

TEST_CASE("part_too_big_is_refused_with_both_sizes") {
  const PrinterProfile p = load_printer_profile("up-plus-2", kConfigDir);
  CHECK(config_error([&] { check_part_fits(p, 139.9, 100, 135); }).empty());
  CHECK(config_error([&] { check_part_fits(p, 150, 80.25, 40); }) ==
        "the part is 150.0 x 80.2 x 40.0 mm but the UP Plus 2 builds at most 140 x 140 x 135 mm; "
        "scale it down (--scale, --height) or choose a bigger printer (--printer)");
}

TEST_CASE("firmware_key_names_the_dialect_the_gcode_is_written_for") {
  printer::Profiles p;
  p.printer = printer::load_printer_profile("generic-marlin", kConfigDir);
  CHECK(p.printer.firmware == printer::Firmware::marlin);
  printer::apply_override(p, "firmware=teacup");
  CHECK(p.printer.firmware == printer::Firmware::teacup);
  CHECK_THROWS_WITH_AS(printer::apply_override(p, "firmware=klipper"),
                       doctest::Contains("one of marlin, teacup, repetier"), printer::ConfigError);
}

TEST_CASE("shipped_profiles_print_with_supports_and_the_up_plus_2_on_a_raft") {
  const PrinterProfile up = load_printer_profile("up-plus-2", kConfigDir);
  CHECK(up.support.type == "everywhere");
  CHECK(up.raft.enabled);
  CHECK(up.raft.base_thickness == 0.3);
  CHECK(up.brim_width == 0);
  const PrinterProfile marlin = load_printer_profile("generic-marlin", kConfigDir);
  CHECK(marlin.support.type == "everywhere");
  CHECK_FALSE(marlin.raft.enabled);
  CHECK(up.support.interface_thickness == 0.4);  // mm, whatever the layers
  CHECK(marlin.support.interface_thickness == 0.4);
  const MaterialProfile abs = load_material_profile("abs", kConfigDir);
  CHECK(abs.overhang_angle == 50);
  CHECK(abs.bridge_length == 10);
  const MaterialProfile pla = load_material_profile("pla", kConfigDir);
  CHECK(pla.bridge_length == 20);
  CHECK(pla.bridge_fan == 100);
}

TEST_CASE("support_keys_are_checked_like_every_key") {
  CHECK(config_error([] { parse_printer_profile(kMinimalPrinter + "[support]\ntype = \"sometimes\"\n", "my.toml"); }) ==
        "my.toml:11: key 'support.type' = \"sometimes\" is not allowed; it must be one of none, "
        "buildplate, everywhere");
  CHECK(config_error([] { parse_printer_profile(kMinimalPrinter + "[support]\nxy_gap = -1\n", "my.toml"); })
            .starts_with("my.toml:11: key 'support.xy_gap' = -1 is not allowed"));
  // The interface in mm; the count of layers it was once is no key any more, and the error
  // names the one that is.
  CHECK(parse_printer_profile(kMinimalPrinter + "[support]\ninterface_thickness = 0.25\n", "my.toml")
            .support.interface_thickness == 0.25);
  CHECK(config_error([] { parse_printer_profile(kMinimalPrinter + "[support]\ninterface_thickness = 6\n", "my.toml"); })
            .starts_with("my.toml:11: key 'support.interface_thickness' = 6 is not allowed"));
  const std::string old_key =
      config_error([] { parse_printer_profile(kMinimalPrinter + "[support]\ninterface_layers = 2\n", "my.toml"); });
  CHECK(old_key.find("unknown key 'support.interface_layers': it is now "
                      "'support.interface_thickness', in mm") != std::string::npos);
  // Boxes: a list of [x0, y0, z0, x1, y1, z1], each with its corners in order.
  const PrinterProfile boxes = parse_printer_profile(
      kMinimalPrinter + "[support]\nenforcers = [[0, 0, 0, 10, 10, 5], [20, 20, 1, 30, 25, 2]]\n", "my.toml");
  REQUIRE(boxes.support.enforcers.size() == 2);
  CHECK(boxes.support.enforcers[1] == SupportBoxMm{20, 20, 1, 30, 25, 2});
  CHECK(config_error([] { parse_printer_profile(kMinimalPrinter + "[support]\nblockers = [[0, 0, 0, 1, 2]]\n", "my.toml"); })
            .starts_with("my.toml:11: key 'support.blockers' must be a list of boxes [x0, y0, z0, x1, y1, z1]"));
  CHECK(config_error([] { parse_printer_profile(kMinimalPrinter + "[support]\nblockers = [[5, 0, 0, 1, 2, 3]]\n", "my.toml"); })
            .starts_with("my.toml:11: key 'support.blockers' = [[5, 0, 0, 1, 2, 3]] is not allowed"));
  // On the command line, boxes by semicolons; "none" clears them.
  Profiles p{load_printer_profile("up-plus-2", kConfigDir), load_material_profile("abs", kConfigDir)};
  apply_override(p, "support.blockers=1,2,3,4,5,6; 7,8,9,10,11,12");
  CHECK(p.printer.support.blockers.size() == 2);
  apply_override(p, "support.blockers=none");
  CHECK(p.printer.support.blockers.empty());
  CHECK(config_error([&] { apply_override(p, "support.blockers=1,2,3"); })
            .starts_with("--set support.blockers=1,2,3: key 'support.blockers' must be a list of boxes"));
  // A raft's layers must be thicknesses the printer prints.
  CHECK(config_error([&] { apply_override(p, "raft.base_thickness=0.33"); })
            .starts_with(kConfigDir + "/printers/up-plus-2.toml: raft.base_thickness = 0.33 mm is not a "
                         "layer thickness this printer allows"));
  CHECK(config_error([&] { apply_override(p, "material.bridge.flow=2"); })
            .starts_with("--set material.bridge.flow=2: key 'bridge.flow' = 2 is not allowed"));
}

TEST_CASE("layer_tops_are_checked_against_the_printers_thicknesses") {
  const PrinterProfile up = load_printer_profile("up-plus-2", kConfigDir);
  // First layer 0.3 mm, then any of 0.15 to 0.4 mm in steps of 0.05 mm.
  const std::vector<double> fine{0.3, 0.45, 0.85, 1.1, 1.3};
  CHECK_NOTHROW(check_layer_tops(up, fine));
  const std::vector<double> thin{0.3, 0.45, 0.55};
  CHECK(config_error([&] { check_layer_tops(up, thin); }) ==
        "layer 3 (z 0.45 to 0.55 mm) is 0.1 mm thick, which the UP Plus 2 (" + kConfigDir +
            "/printers/up-plus-2.toml) cannot print; allowed: 0.15, 0.2, 0.25, 0.3, 0.35, 0.4 mm");
  const std::vector<double> off_step{0.3, 0.52};
  CHECK(config_error([&] { check_layer_tops(up, off_step); }).starts_with(
      "layer 2 (z 0.3 to 0.52 mm) is 0.22 mm thick"));
  const std::vector<double> first{0.2, 0.4};
  CHECK(config_error([&] { check_layer_tops(up, first); }) ==
        "layer 1 (z 0 to 0.2 mm) is 0.2 mm thick, which the UP Plus 2 (" + kConfigDir +
            "/printers/up-plus-2.toml) cannot print; allowed: 0.3 mm for the first layer "
            "(first_layer.height)");
  // Generic Marlin: 0.2 mm first, then 0.05 to 0.3 mm in steps of 0.01 mm.
  const PrinterProfile marlin = load_printer_profile("generic-marlin", kConfigDir);
  const std::vector<double> marlin_fine{0.2, 0.27, 0.33, 0.38};
  CHECK_NOTHROW(check_layer_tops(marlin, marlin_fine));
  const std::vector<double> marlin_off{0.2, 0.275};
  CHECK(config_error([&] { check_layer_tops(marlin, marlin_off); }).ends_with(
      "allowed: 0.05 to 0.3 mm in steps of 0.01 mm"));
}

TEST_CASE("skin_thicknesses_are_profile_keys_in_mm") {
  const PrinterProfile up = load_printer_profile("up-plus-2", kConfigDir);
  CHECK(up.print.top_thickness == doctest::Approx(0.6));
  CHECK(up.print.bottom_thickness == doctest::Approx(0.6));
  Profiles profiles{up, MaterialProfile{}};
  apply_override(profiles, "print.top_thickness=1.2");
  CHECK(profiles.printer.print.top_thickness == doctest::Approx(1.2));
  CHECK(config_error([&] { apply_override(profiles, "print.bottom_thickness=-1"); }) != "");
}

}  // namespace profile_test

namespace profile_test {

namespace {

// A search path of scratch folders, each with printers/ and materials/.
struct Folders {
  std::string root;
  explicit Folders(const std::string& name) : root(test_support::scratch_dir(name)) {}
  std::string add(const std::string& folder, const std::string& file, const std::string& text) const {
    const std::string dir = root + "/" + folder + "/" + file.substr(0, file.find('/'));
    std::filesystem::create_directories(dir);
    std::ofstream(root + "/" + folder + "/" + file) << text;
    return root + "/" + folder;
  }
};

std::string named(const std::string& name) {
  std::string text = kMinimalPrinter;
  text.replace(text.find("\"Test\""), 6, "\"" + name + "\"");
  return text;
}

}  // namespace

TEST_CASE("the_first_folder_of_the_search_path_with_a_name_wins") {
  const Folders f("profile_search_path");
  const std::string user = f.add("user", "printers/shared.toml", named("Mine"));
  f.add("user", "printers/creality-ender-3-0.4-mm-nozzle.toml", named("Creality Ender-3 (0.4 mm nozzle)"));
  const std::string shipped = f.add("shipped", "printers/shared.toml", named("Shipped"));
  f.add("shipped", "printers/only-shipped.toml", named("Only shipped"));
  const std::string path = user + ":" + shipped;
  CHECK(load_printer_profile("shared", path).name == "Mine");
  CHECK(load_printer_profile("only-shipped", path).name == "Only shipped");
  // By the profile's name as well as by its file's: the file name is the name's stem.
  CHECK(load_printer_profile("Creality Ender-3 (0.4 mm nozzle)", path).source ==
        user + "/printers/creality-ender-3-0.4-mm-nozzle.toml");
  const auto found = find_profiles(path, "printers");
  REQUIRE(found.size() == 3);
  CHECK(found[0].id == "creality-ender-3-0.4-mm-nozzle");
  CHECK(found[2].id == "shared");
  CHECK(found[2].path == user + "/printers/shared.toml");
  CHECK(config_error([&] { load_printer_profile("prusa-mk4", path); }) ==
        "printer profile 'prusa-mk4' not found in " + user + "/printers, " + shipped +
            "/printers (available: creality-ender-3-0.4-mm-nozzle, only-shipped, shared); give one "
            "of these names or a path to a .toml file");
}

TEST_CASE("the_search_path_is_the_users_then_the_systems_then_the_installed_folder") {
  ::unsetenv("MAHOST_CONFIG_DIR");
  ::setenv("XDG_CONFIG_HOME", "/home/u/.config", 1);
  ::setenv("XDG_CONFIG_DIRS", "/etc/xdg:relative:/opt/xdg", 1);
  CHECK(config_directory("/usr/share/mahost") ==
        "/home/u/.config/mahost:/etc/xdg/mahost:/opt/xdg/mahost:/usr/share/mahost");
  CHECK(user_config_directory() == "/home/u/.config/mahost");
  ::unsetenv("XDG_CONFIG_DIRS");
  ::setenv("XDG_CONFIG_HOME", "not/absolute", 1);  // ignored, as the XDG rules say
  ::setenv("HOME", "/home/v", 1);
  CHECK(config_directory("") == "/home/v/.config/mahost:/etc/xdg/mahost");
  ::setenv("MAHOST_CONFIG_DIR", "/tests/configs", 1);
  CHECK(config_directory("/usr/share/mahost") == "/tests/configs");
  ::unsetenv("MAHOST_CONFIG_DIR");
  ::unsetenv("XDG_CONFIG_HOME");
}

TEST_CASE("profile_file_stems_are_lower_case_words_joined_by_dashes") {
  CHECK(profile_file_stem("Creality Ender-3 (0.4 mm nozzle)") == "creality-ender-3-0.4-mm-nozzle");
  CHECK(profile_file_stem("Original Prusa i3 MK3S & MK3S+") == "original-prusa-i3-mk3s-mk3s+");
  CHECK(profile_file_stem("Generic PLA @CREALITY") == "generic-pla-creality");
  CHECK(profile_file_stem("a/b") == "a-b");
  CHECK(profile_file_stem("...") == "");
}

TEST_CASE("a_round_bed_and_gcode_constants_load_and_check") {
  const std::string text = kMinimalPrinter + R"(
[gcode]
syntax = "prusaslicer"
[gcode.constants]
printer_model = "MK3S"
speeds = [1.5, 2]
silent = false
count = 3
)";
  PrinterProfile p = parse_printer_profile(text, "t.toml");
  CHECK(p.gcode_syntax == GcodeSyntax::prusaslicer);
  REQUIRE(p.gcode_constants.size() == 4);
  CHECK(std::get<std::string>(p.gcode_constants.at("printer_model").values[0]) == "MK3S");
  CHECK(p.gcode_constants.at("speeds").is_vector);
  CHECK(std::get<double>(p.gcode_constants.at("speeds").values[0]) == 1.5);
  CHECK(std::get<long long>(p.gcode_constants.at("speeds").values[1]) == 2);  // TOML's types
  CHECK(std::get<long long>(p.gcode_constants.at("count").values[0]) == 3);
  Profiles both{p, MaterialProfile{}};
  apply_override(both, "gcode.constants.printer_model=MINI");
  CHECK(std::get<std::string>(both.printer.gcode_constants.at("printer_model").values[0]) == "MINI");
  CHECK(config_error([&] { parse_printer_profile(text + "[gcode.constants.more]\nx = 1\n", "t.toml"); })
            .ends_with(": key 'gcode.constants' has a name 'more.x' that is not a placeholder's (letters, "
                       "digits and _)"));
  CHECK(config_error([&] { apply_override(both, "build_volume.shape=circle"); }) ==
        "t.toml: build_volume.shape = \"circle\" needs x = y (the circle's diameter), not 100 and 120 mm "
        "(after --set build_volume.shape=circle)");
}

}  // namespace profile_test
