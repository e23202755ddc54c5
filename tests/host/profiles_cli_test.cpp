// `mahost profiles` as a user runs it: PrusaSlicer's printers imported into the user's folder and
// sliced with by name, every printer of Debian's PrusaSlicer bundles (when prusa-slicer is
// installed) either imported and slicing a 20 mm cube on its bed that starts with the vendor's
// start G-code, or refused for a reason of a known kind; and 3MF and OBJ models sliced.
#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include <doctest/doctest.h>

#include "geometry/mesh/stl_io.h"
#include "printer/profile.h"
#include "support/build_kind.h"
#include "support/run_command.h"
#include "support/solids.h"

namespace profiles_cli_test {

using test_support::run_mahost;

namespace {

namespace fs = std::filesystem;

const std::string kBundles = "/usr/share/PrusaSlicer/profiles";

std::string read_file(const std::string& path) {
  std::ifstream in(path);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

// A user's own config folder for the children this test runs, and only it (the test main's
// folders back after it).
struct UserFolder {
  std::string dir;
  std::string home = std::getenv("XDG_CONFIG_HOME"), system = std::getenv("XDG_CONFIG_DIRS");
  explicit UserFolder(const std::string& name) : dir(test_support::scratch_dir(name)) {
    ::setenv("XDG_CONFIG_HOME", (dir + "/config").c_str(), 1);
    ::setenv("XDG_CONFIG_DIRS", (dir + "/system").c_str(), 1);
  }
  ~UserFolder() {
    ::setenv("XDG_CONFIG_HOME", home.c_str(), 1);
    ::setenv("XDG_CONFIG_DIRS", system.c_str(), 1);
  }
  std::string printers() const { return dir + "/config/mahost/printers"; }
};

const std::string kBundle = R"([vendor]
name = Acme
[printer_model:CUBE]
name = Acme Cube
[printer:*common*]
gcode_flavor = marlin
bed_shape = 0x0,200x0,200x200,0x200
max_print_height = 180
start_gcode = G28 ; home\nM140 S[first_layer_bed_temperature]\nG1 X{print_bed_max[0] - 10} Y0 F3000\nM117 [printer_model] {if layer_height < 0.15}fine{else}normal{endif}
end_gcode = G1 Z{min(max_layer_z + 20, max_print_height)}\nM84
default_print_profile = 0.20mm @ACME
default_filament_profile = Acme PLA
[printer:Acme Cube (0.4 mm nozzle)]
inherits = *common*
printer_model = CUBE
[printer:Acme Cube Resin]
inherits = *common*
printer_model = CUBE
printer_technology = SLA
[print:0.20mm @ACME]
layer_height = 0.2
first_layer_height = 0.2
[filament:Acme PLA]
temperature = 205
first_layer_temperature = 210
bed_temperature = 55
first_layer_bed_temperature = 60
)";

// X and Y of every G0/G1 move from the first layer to the end G-code.
std::vector<std::pair<double, double>> part_moves(const std::vector<std::string>& lines) {
  std::vector<std::pair<double, double>> at;
  bool in_part = false;
  double x = 0, y = 0;
  static const std::regex word(R"(([XY])(-?[0-9.]+))");
  for (const std::string& line : lines) {
    if (line == ";LAYER:0") in_part = true;
    if (line == ";end G-code from the printer profile") break;
    if (!in_part || !(line.rfind("G0 ", 0) == 0 || line.rfind("G1 ", 0) == 0)) continue;
    const std::string code = line.substr(0, line.find(';'));
    bool moved = false;
    for (auto it = std::sregex_iterator(code.begin(), code.end(), word); it != std::sregex_iterator(); ++it) {
      ((*it)[1] == "X" ? x : y) = std::stod((*it)[2]);
      moved = true;
    }
    if (moved) at.emplace_back(x, y);
  }
  return at;
}

std::size_t count(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

// Whether the program's start G-code is the profile's: every line of it that names no
// placeholder and stands outside {if} blocks, in order, after the writer's comment, and no
// placeholder left unexpanded.
std::string start_gcode_problem(const std::vector<std::string>& lines, const std::string& start) {
  std::size_t at = 0;
  while (at < lines.size() && lines[at] != ";start G-code from the printer profile") ++at;
  if (at == lines.size()) return "no start G-code comment";
  std::size_t next = at + 1;
  long depth = 0;  // {if} blocks open around the line
  for (const std::string& raw : lines_of(start)) {
    std::string literal = raw;
    while (!literal.empty() && (literal.back() == ' ' || literal.back() == '\r')) literal.pop_back();
    literal.erase(0, literal.find_first_not_of(' '));
    const bool conditional = depth > 0;
    depth += static_cast<long>(count(raw, "{if")) - static_cast<long>(count(raw, "{endif}"));
    if (literal.empty() || conditional || literal.find_first_of("[]{}") != std::string::npos) continue;
    while (next < lines.size() && lines[next] != literal && lines[next].rfind(";LAYER:0", 0) != 0) ++next;
    if (next == lines.size() || lines[next] != literal) return "line '" + literal + "' is missing";
    ++next;
  }
  for (std::size_t i = at; i < lines.size() && lines[i] != ";LAYER:0"; ++i) {
    if (lines[i].find_first_of("{}") != std::string::npos) return "unexpanded: " + lines[i];
  }
  return "";
}

}  // namespace

TEST_CASE("an_imported_printer_slices_by_its_name_with_the_vendors_start_gcode") {
  const UserFolder user("profiles_import_one");
  const std::string bundle = user.dir + "/acme.ini";
  std::ofstream(bundle) << kBundle;
  auto r = run_mahost({"profiles", "import", bundle});
  CHECK(r.exit_code == 2);
  CHECK(r.err == "mahost: " + bundle + " has 2 printers: name one with --printer (e.g. --printer "
                 "\"Acme Cube (0.4 mm nozzle)\"), or take them all with --all\n");
  r = run_mahost({"profiles", "import", bundle, "--printer", "Acme Cube (0.4 mm nozzle)"});
  CHECK(r.err == "");
  CHECK(r.exit_code == 0);
  const std::string path = user.printers() + "/acme-cube-0.4-mm-nozzle.toml";
  CHECK(r.out == "imported Acme Cube (0.4 mm nozzle) as " + path +
                 " (material Acme PLA, speeds and layers of the print profile 0.20mm @ACME)\n"
                 "slice with: mahost slice MODEL --printer \"Acme Cube (0.4 mm nozzle)\"\n");
  CHECK(fs::exists(user.dir + "/config/mahost/materials/acme-pla.toml"));
  // Listed from the user's folder before the shipped profiles.
  r = run_mahost({"profiles", "list"});
  CHECK(r.exit_code == 0);
  CHECK(r.out.find("  acme-cube-0.4-mm-nozzle  Acme Cube (0.4 mm nozzle)  " + user.printers()) != std::string::npos);
  CHECK(r.out.find("  up-plus-2 ") != std::string::npos);
  CHECK(r.out.find("folders, the first with a name wins:\n  " + user.dir + "/config/mahost\n  " + user.dir +
                   "/system/mahost\n") != std::string::npos);
  // Sliced by the name PrusaSlicer gives it.
  const std::string stl = user.dir + "/cube.stl";
  geometry::write_stl_binary(stl, solids::cube(20).mesh);
  r = run_mahost({"slice", stl, "--printer", "Acme Cube (0.4 mm nozzle)", "-o", user.dir + "/cube.gcode"});
  CHECK(r.err == "");
  REQUIRE(r.exit_code == 0);
  const auto lines = lines_of(read_file(user.dir + "/cube.gcode"));
  std::size_t start = 0;
  while (lines[start] != ";start G-code from the printer profile") ++start;
  // The bed is left to the start G-code, which sets it; the nozzle is heated before it.
  CHECK(lines[start - 2] == "M104 S210");
  CHECK(lines[start - 1] == "M109 S210");
  CHECK(lines[start + 1] == "G28 ; home");
  CHECK(lines[start + 2] == "M140 S60");
  CHECK(lines[start + 3] == "G1 X190 Y0 F3000");
  CHECK(lines[start + 4] == "M117 CUBE normal");
  // The end G-code knows the part's top: 20 mm.
  const auto end = std::find(lines.begin(), lines.end(), ";end G-code from the printer profile");
  REQUIRE(end != lines.end());
  CHECK(*(end + 1) == "G1 Z40");
  for (const auto& [x, y] : part_moves(lines)) {
    CHECK(x >= 0);
    CHECK(x <= 200);
    CHECK(y >= 0);
    CHECK(y <= 200);
  }
  // Importing again replaces what the import wrote, never a profile written by hand.
  std::ofstream(path) << "name = \"mine\"\n";
  r = run_mahost({"profiles", "import", bundle, "--all"});
  CHECK(r.exit_code == 2);
  CHECK(r.out.find("refused Acme Cube (0.4 mm nozzle): " + path + " exists and was not imported") != std::string::npos);
  CHECK(r.out.find("refused Acme Cube Resin: printer_technology SLA") != std::string::npos);
  CHECK(read_file(path) == "name = \"mine\"\n");
}

TEST_CASE("a_bad_ini_an_unknown_placeholder_and_a_missing_printer_are_one_line_errors") {
  const UserFolder user("profiles_import_errors");
  const std::string tail = "[print:P]\nlayer_height = 0.2\n[filament:F]\ntemperature = 200\n";
  auto write = [&](const std::string& name, const std::string& text) {
    std::ofstream(user.dir + "/" + name) << text;
    return user.dir + "/" + name;
  };
  const std::string not_ini = write("notes.ini", "[printer:X]\njust words\n");
  const std::string placeholder = write("placeholder.ini", "[printer:Y]\nstart_gcode = G28\\nM104 S[no_such_thing]\n" + tail);
  const std::string bed = write("bed.ini", "[printer:Z]\nbed_shape = garbage\n" + tail);
  const std::string acme = write("acme.ini", kBundle);
  const std::string cube = user.dir + "/cube.stl";
  geometry::write_stl_binary(cube, solids::cube(20).mesh);
  const std::vector<std::pair<std::vector<std::string>, std::string>> cases{
      {{"profiles", "import", not_ini, "--all"},
       not_ini + ":2: expected key = value, a [section] or a # comment, found 'just words'"},
      {{"profiles", "import", placeholder, "--printer", "Y"},
       placeholder + ": cannot import Y: gcode.start: line 2: [no_such_thing]: 'no_such_thing' is not a value "
       "mahost knows; mahost evaluates PrusaSlicer's placeholders for the printer, the material and the "
       "slice, and the printer's gcode.constants"},
      {{"profiles", "import", bed}, bed + ": cannot import Z: bed_shape 'garbage' is not a list of points"},
      {{"profiles", "import", acme, "--printer", "Acme Box"},
       acme + " has no printer 'Acme Box' (it has 2; mahost profiles import " + acme + " --all takes them all)"},
      {{"profiles", "import", user.dir + "/missing.ini", "--all"}, user.dir + "/missing.ini: no such file (check the path)"},
      {{"slice", cube, "-o", user.dir + "/cube.gcode", "--printer", "Acme Box"}, ""},
  };
  for (const auto& [args, error] : cases) {
    CAPTURE(args.back());
    const auto r = run_mahost(args);
    CHECK(r.exit_code == 2);
    CHECK(r.out == "");
    CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
    if (!error.empty()) CHECK(r.err == "mahost: " + error + "\n");
  }
  CHECK(!fs::exists(user.printers() + "/y.toml"));
  CHECK(!fs::exists(user.printers() + "/z.toml"));
}

TEST_CASE("every_printer_of_debians_prusaslicer_bundles_imports_or_says_why") {
  if (!fs::is_directory(kBundles)) {
    MESSAGE(kBundles << " is not there (scripts/setup installs prusa-slicer): skipped");
    return;
  }
  const UserFolder user("profiles_import_prusaslicer");
  std::size_t bundles = 0;
  std::map<std::string, std::string> refused;  // printer -> reason
  for (const auto& entry : fs::directory_iterator(kBundles)) {
    if (entry.path().extension() != ".ini") continue;
    ++bundles;
    const auto r = run_mahost({"profiles", "import", entry.path().string(), "--all"});
    CAPTURE(entry.path().string());
    CAPTURE(r.err);
    CHECK((r.exit_code == 0 || r.err.find("nothing imported") != std::string::npos));
    for (const std::string& line : lines_of(r.out)) {
      if (line.rfind("refused ", 0) != 0) continue;
      const std::size_t colon = line.find(": ", 8);
      refused[line.substr(8, colon - 8)] = line.substr(colon + 2);
    }
  }
  // The kinds of refusal there are: each says what mahost cannot do for that printer.
  const std::regex known(
      R"(printer_technology SLA: .*)"
      R"(|gcode.start: line [0-9]+: .*: [a-z_]+\[[1-9]\]: mahost prints with the first extruder and knows only its material)"
      R"(|gcode.start: line [0-9]+: \[start_filament_gcode\]: 'start_filament_gcode' is not a value mahost knows.*)");
  for (const auto& [printer, reason] : refused) {
    CAPTURE(printer);
    CAPTURE(reason);
    CHECK(std::regex_match(reason, known));
  }
  const std::string stl = user.dir + "/cube.stl";
  geometry::write_stl_binary(stl, solids::cube(20).mesh);
  // Every imported printer slices the cube in the release build. Under the sanitizers a slice
  // costs about 0.6 s, so that build slices every 16th printer (about 23 of 368 in Debian 12):
  // enough to run each step of slicing under ASan with imported profiles, in seconds, not minutes.
  const std::size_t slice_every = test_support::kSanitizedBuild ? 16 : 1;
  std::size_t sliced = 0;
  std::size_t imported = 0;
  const std::string search_path = user.dir + "/config/mahost";
  for (const printer::ProfileFile& file : printer::find_profiles(search_path, "printers")) {
    if (imported++ % slice_every != 0) continue;
    CAPTURE(file.path);
    const printer::PrinterProfile profile = printer::load_printer_profile(file.path, search_path);
    const std::string gcode = user.dir + "/" + file.id + ".gcode";
    const auto r = run_mahost({"slice", stl, "--printer", profile.name, "-o", gcode, "--contour", "mid"});
    CAPTURE(r.err);
    REQUIRE(r.exit_code == 0);
    const auto lines = lines_of(read_file(gcode));
    CHECK(start_gcode_problem(lines, profile.start_gcode) == "");
    const auto moves = part_moves(lines);
    CHECK(moves.size() > 100);
    std::size_t off = 0;
    for (const auto& [x, y] : moves) off += printer::on_bed(profile, x, y, 1e-3) ? 0 : 1;
    CHECK(off == 0);
    ++sliced;
    fs::remove(gcode);
  }
  MESSAGE(bundles << " bundles: " << imported << " printers imported, " << sliced
                  << " of them slicing the cube on its bed; " << refused.size() << " refused");
  CHECK(bundles > 0);
  CHECK(sliced > 0);
}

TEST_CASE("3mf_and_obj_models_slice_like_their_stl") {
  const std::string dir = test_support::scratch_dir("profiles_models");
  const std::string obj = dir + "/cube.obj";
  std::ofstream(obj) << "v 0 0 0\nv 10 0 0\nv 10 10 0\nv 0 10 0\nv 0 0 10\nv 10 0 10\nv 10 10 10\nv 0 10 10\n"
                        "f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n";
  auto r = run_mahost({"info", obj});
  CHECK(r.exit_code == 0);
  CHECK(r.out.find("format        OBJ\n") != std::string::npos);
  CHECK(r.out.find("volume        1000.000 mm^3\n") != std::string::npos);
  r = run_mahost({"slice", obj, "-o", dir + "/obj.gcode", "--contour", "mid"});
  CHECK(r.err == "");
  CHECK(r.exit_code == 0);
  // --units is for files that record none.
  r = run_mahost({"info", obj, "--units", "in"});
  CHECK(r.out.find("volume        16387064.000 mm^3\n") != std::string::npos);  // 254 mm cubed
}

}  // namespace profiles_cli_test
