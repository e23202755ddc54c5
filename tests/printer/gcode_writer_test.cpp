// The G-code writer, with hand-made toolpaths: read the program back as a printer would
// (tests/support/gcode_beads) and check what it lays, where it moves, and what it claims.
#include <cmath>
#include <cstdio>
#include <fstream>
#include <initializer_list>
#include <sstream>
#include <string>
#include <vector>

#include <doctest/doctest.h>

#include "geometry/core/polygon.h"
#include "geometry/toolpaths/toolpaths.h"
#include "printer/bead_model.h"
#include "printer/error.h"
#include "printer/gcode_line.h"
#include "printer/gcode_writer.h"
#include "printer/print_time.h"
#include "printer/profile.h"
#include "support/gcode_beads.h"

namespace gcode_writer_test {

using geometry::ExtrusionPath;
using geometry::LayerToolpaths;
using geometry::Loop;
using geometry::PathRole;
using geometry::Region;
using geometry::Vec2;
using namespace printer;

namespace {

const std::string kConfigDir = MAHOST_SOURCE_DIR "/configs";

Profiles profiles(const std::string& printer, const std::string& material,
                  std::vector<std::string> overrides = {}) {
  ProfileRequest request;
  request.printer = printer;
  request.material = material;
  request.config_dir = kConfigDir;
  request.overrides = std::move(overrides);
  return load_profiles(request);
}

// A closed square loop of side `side` centred on the origin, counter-clockwise.
std::vector<Vec2> square_loop(double side) {
  const double h = side / 2;
  return {{-h, -h}, {h, -h}, {h, h}, {-h, h}, {-h, -h}};
}

// One layer of a `side` mm square, filled solid by hand: two walls of width w (outer wall's
// outer edge on the square's edge), then lines w apart across the inside of the inner wall.
LayerToolpaths square_layer(double z_lo, double z_hi, double side, double w) {
  LayerToolpaths layer;
  layer.z_lo = z_lo;
  layer.z_hi = z_hi;
  layer.paths.push_back({PathRole::inner_wall, square_loop(side - 3 * w), w, true});
  layer.paths.push_back({PathRole::outer_wall, square_loop(side - w), w, false});
  const double inside = side / 2 - 2 * w;
  int k = 0;
  for (double y = -inside + w / 2; y < inside; y += w, ++k) {
    const double from = k % 2 ? inside : -inside;  // alternate directions: short travels
    layer.paths.push_back({PathRole::solid_infill, {{from, y}, {-from, y}}, w, false});
  }
  return layer;
}

// Three layers of the 20 mm square: 0.3 mm first layer, then 0.2 mm.
std::vector<LayerToolpaths> square_part(double w = 0.5) {
  return {square_layer(0, 0.3, 20, w), square_layer(0.3, 0.5, 20, w),
          square_layer(0.5, 0.7, 20, w)};
}

Region square_region(double side, Vec2 centre) {
  const double h = side / 2;
  return {{Loop{{centre.x - h, centre.y - h}, {centre.x + h, centre.y - h},
                {centre.x + h, centre.y + h}, {centre.x - h, centre.y + h}}}};
}

std::string write(const std::vector<LayerToolpaths>& layers, const Profiles& p,
                  GcodeSummary* summary = nullptr, GcodeOptions options = {}) {
  std::ostringstream out;
  const GcodeSummary s = write_gcode(out, layers, p, options);
  if (summary) *summary = s;
  return out.str();
}

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

std::size_t index_of(const std::vector<std::string>& lines, const std::string& line,
                     std::size_t from = 0) {
  for (std::size_t i = from; i < lines.size(); ++i) {
    if (lines[i] == line) return i;
  }
  return lines.size();
}

template <class F>
std::string config_error(F&& f) {
  try {
    f();
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("beads_cover_the_square_and_stay_inside_it") {
  for (const std::string printer : {"up-plus-2", "generic-marlin"}) {
    CAPTURE(printer);
    const Profiles p = profiles(printer, "abs");
    const std::string text = write(square_part(), p);
    const test_support::PrintedProgram program =
        test_support::read_printed_program(text, {p.printer.filament_diameter, p.material.flow});
    CHECK(program.problems.empty());
    REQUIRE(program.layers.size() == 3);
    const Region square = square_region(20, {p.printer.bed_x / 2, p.printer.bed_y / 2});
    for (const test_support::PrintedLayer& layer : program.layers) {
      CAPTURE(layer.number);
      const test_support::Coverage c = test_support::coverage(test_support::bead_region(layer), square);
      CHECK(c.covered >= 0.98);
      CHECK(c.outside <= 0.02);
    }
  }
}

TEST_CASE("extrusion_per_mm_matches_the_bead_model") {
  for (const std::string printer : {"up-plus-2", "generic-marlin"}) {  // absolute and relative E
    CAPTURE(printer);
    const Profiles p = profiles(printer, "abs", {"material.flow=0.95"});
    const test_support::PrintedProgram program = test_support::read_printed_program(
        write(square_part(0.5), p), {p.printer.filament_diameter, p.material.flow});
    REQUIRE(program.layers.size() == 3);
    const double heights[] = {0.3, 0.2, 0.2};
    std::size_t beads = 0;
    for (std::size_t n = 0; n < 3; ++n) {
      const test_support::PrintedLayer& layer = program.layers[n];
      CHECK(layer.height == doctest::Approx(heights[n]).epsilon(1e-9));
      const double per_mm = bead_area(0.5, heights[n]) / filament_area(1.75) * 0.95;
      for (const auto& chain : layer.chains) {
        for (const test_support::Bead& bead : chain) {
          // E is written to 0.00001 mm: each end of a move rounds by half of that at most.
          CHECK(std::abs(bead.filament - per_mm * bead.length()) <= 1e-5 + 1e-12);
          CHECK(bead.width == doctest::Approx(0.5).epsilon(1e-3));
          ++beads;
        }
      }
    }
    CHECK(beads > 100);
  }
}

TEST_CASE("every_move_stays_inside_the_build_volume") {
  const Profiles p = profiles("up-plus-2", "abs");
  const test_support::PrintedProgram program = test_support::read_printed_program(write(square_part(), p));
  CHECK(program.min_xy.x >= 0);
  CHECK(program.min_xy.y >= 0);
  CHECK(program.max_xy.x <= p.printer.bed_x);
  CHECK(program.max_xy.y <= p.printer.bed_y);
  CHECK(program.min_z >= 0);
  CHECK(program.max_z <= p.printer.bed_z);
  // The part itself is centred: its beads span the bed centre +- 10 mm.
  double min_x = 1e9, max_x = -1e9;
  for (const auto& layer : program.layers) {
    for (const auto& chain : layer.chains) {
      for (const auto& bead : chain) {
        min_x = std::min({min_x, bead.from.x, bead.to.x});
        max_x = std::max({max_x, bead.from.x, bead.to.x});
      }
    }
  }
  CHECK(min_x == doctest::Approx(70 - 9.75));
  CHECK(max_x == doctest::Approx(70 + 9.75));
}

TEST_CASE("layer_comments_count_the_layers") {
  const Profiles p = profiles("up-plus-2", "abs");
  GcodeSummary summary;
  const std::string text = write(square_part(), p, &summary);
  const auto lines = lines_of(text);
  std::vector<long> layers;
  std::vector<std::string> zs;
  for (std::size_t i = 0; i < lines.size(); ++i) {
    if (lines[i].starts_with(";LAYER:")) {
      layers.push_back(std::stol(lines[i].substr(7)));
      REQUIRE(i + 1 < lines.size());
      zs.push_back(lines[i + 1]);
    }
  }
  CHECK(layers == std::vector<long>{0, 1, 2});
  CHECK(zs == std::vector<std::string>{";Z:0.3", ";Z:0.5", ";Z:0.7"});
  const test_support::PrintedProgram program = test_support::read_printed_program(text);
  CHECK(program.header.at("LAYER_COUNT") == "3");
  CHECK(summary.layers == 3);
}

TEST_CASE("estimate_equals_the_motion_model_over_the_written_program") {
  for (const std::string printer : {"up-plus-2", "generic-marlin"}) {
    CAPTURE(printer);
    const Profiles p = profiles(printer, printer == "up-plus-2" ? "abs" : "pla");
    GcodeSummary summary;
    const std::string text = write(square_part(), p, &summary);
    const double reread = estimate_print_time(text, p.printer.motion);
    CHECK(summary.print_seconds == doctest::Approx(reread).epsilon(1e-12));
    const test_support::PrintedProgram program = test_support::read_printed_program(text);
    CHECK(std::abs(std::stod(program.header.at("PRINT_TIME_S")) - reread) <= 0.0005);  // 3 decimals
    CHECK(std::stol(program.header.at("TIME")) == std::lround(reread));
    CHECK(summary.print_seconds > 0);
  }
}

TEST_CASE("timing_without_the_text_is_the_written_programs_time_layer_by_layer") {
  const Profiles p = profiles("up-plus-2", "abs");
  GcodeSummary written;
  const std::string text = write(square_part(), p, &written);
  const GcodeSummary timed = time_gcode(square_part(), p);
  CHECK(timed.print_seconds == doctest::Approx(estimate_print_time(text, p.printer.motion)).epsilon(1e-12));
  REQUIRE(timed.layer_starts.size() == written.layer_starts.size());
  REQUIRE(timed.layer_starts.size() == 3);
  for (std::size_t k = 0; k < timed.layer_starts.size(); ++k) {
    CHECK(timed.layer_starts[k] == written.layer_starts[k]);
  }
  CHECK(timed.filament_mm == doctest::Approx(written.filament_mm).epsilon(1e-12));
  CHECK(timed.bytes == 0);
}

TEST_CASE("filament_in_header_is_the_filament_in_the_beads") {
  const Profiles p = profiles("up-plus-2", "abs");
  GcodeSummary summary;
  const std::string text = write(square_part(), p, &summary);
  const test_support::PrintedProgram program = test_support::read_printed_program(text);
  CHECK(summary.filament_mm == doctest::Approx(program.filament).epsilon(1e-6));
  CHECK(std::stod(program.header.at("FILAMENT_MM")) == doctest::Approx(program.filament).epsilon(1e-5));
  CHECK(summary.filament_grams ==
        doctest::Approx(filament_weight(program.filament, 1.75, 1.04)).epsilon(1e-6));
  // By hand: per layer, two square loops, 36 lines of 18 mm (less the ones that cross nothing).
  const double loops = 4 * (20 - 0.5) + 4 * (20 - 1.5);
  const double lines = 36 * 18.0;
  const double expected = (loops + lines) * (bead_area(0.5, 0.3) + 2 * bead_area(0.5, 0.2)) /
                          filament_area(1.75);
  CHECK(program.filament == doctest::Approx(expected).epsilon(1e-6));
}

TEST_CASE("heats_to_first_layer_temperatures_then_regular_ones") {
  const Profiles p = profiles("up-plus-2", "abs");
  const auto lines = lines_of(write(square_part(), p));
  const std::size_t bed = index_of(lines, "M190 S105");
  const std::size_t nozzle = index_of(lines, "M109 S250");
  const std::size_t home = index_of(lines, "G28 ; home all axes");
  CHECK(index_of(lines, "M140 S105") < bed);
  CHECK(index_of(lines, "M104 S250") < nozzle);
  CHECK(bed < home);
  CHECK(nozzle < home);
  // The start G-code's placeholder was expanded.
  CHECK(index_of(lines, "G1 Z0.3 F600") < lines.size());
  // Back to 245 / 100 C once the first layer is done.
  const std::size_t layer1 = index_of(lines, ";LAYER:1");
  CHECK(index_of(lines, "M104 S245", layer1) < index_of(lines, ";LAYER:2"));
  CHECK(index_of(lines, "M140 S100", layer1) < index_of(lines, ";LAYER:2"));
  CHECK(index_of(lines, "M104 S245") > layer1);
}

TEST_CASE("extruder_mode_follows_the_profile_after_g90") {
  const auto absolute = lines_of(write(square_part(), profiles("up-plus-2", "abs")));
  CHECK(index_of(absolute, "M82") == index_of(absolute, "G90", index_of(absolute, "G92 E0")) + 1);
  CHECK(index_of(absolute, "M83") == absolute.size());
  const auto relative = lines_of(write(square_part(), profiles("generic-marlin", "pla")));
  CHECK(index_of(relative, "M83") < index_of(relative, ";LAYER:0"));
  CHECK(index_of(relative, "M83") > index_of(relative, "G28 ; home all axes"));
}

TEST_CASE("each_layer_resets_e_and_reports_progress") {
  const auto lines = lines_of(write(square_part(), profiles("up-plus-2", "abs")));
  int last_percent = -1;
  for (std::size_t i = 0; i < lines.size(); ++i) {
    if (!lines[i].starts_with(";LAYER:")) continue;
    REQUIRE(i + 4 < lines.size());
    CHECK(lines[i + 2].starts_with(";HEIGHT:"));
    const GcodeCommand m73 = parse_gcode_line(lines[i + 3]);
    REQUIRE(m73.is('M', 73));
    const int percent = static_cast<int>(*m73.get('P'));
    CHECK(percent >= last_percent);
    last_percent = percent;
    CHECK(lines[i + 4] == "G92 E0");
  }
  CHECK(index_of(lines, "M73 P100 R0") < lines.size());
}

TEST_CASE("retraction_and_z_hop_before_marked_travels") {
  // generic-marlin: relative E, 5 mm retraction at 45 mm/s, 0.2 mm z-hop, prime at 40 mm/s.
  const auto lines = lines_of(write(square_part(), profiles("generic-marlin", "pla")));
  const std::size_t layer1 = index_of(lines, ";LAYER:1");
  const std::size_t retract = index_of(lines, "G1 E-5 F2700", layer1);
  REQUIRE(retract < lines.size());
  CHECK(lines[retract + 1] == "G1 Z0.7 F300");  // the layer's 0.5 plus 0.2 hop
  CHECK(lines[retract + 2].starts_with("G0 X"));
  CHECK(parse_gcode_line(lines[retract + 2]).get('F') == 9000);
  CHECK(lines[retract + 3] == "G1 Z0.5 F300");
  CHECK(lines[retract + 4] == "G1 E5 F2400");
  // Unmarked travels (infill line to infill line) do not retract.
  const std::size_t infill = index_of(lines, ";TYPE:FILL-SOLID", layer1);
  CHECK(index_of(lines, "G1 E-5", infill) > index_of(lines, ";LAYER:2"));
}

TEST_CASE("absolute_e_retracts_below_the_current_e") {
  const auto lines = lines_of(write(square_part(), profiles("up-plus-2", "abs")));
  const std::size_t layer1 = index_of(lines, ";LAYER:1");
  // After G92 E0 the first thing is the retraction: E back to -1 (1 mm at 30 mm/s).
  CHECK(lines[layer1 + 5] == "M104 S245");
  CHECK(index_of(lines, "G1 E-1 F1800", layer1) < index_of(lines, ";TYPE:WALL-OUTER", layer1));
  CHECK(index_of(lines, "G1 E0 F1500", layer1) < index_of(lines, ";TYPE:WALL-OUTER", layer1));
}

TEST_CASE("first_layer_runs_at_first_layer_speed") {
  const Profiles p = profiles("up-plus-2", "abs");  // first layer 15 mm/s; infill 40 mm/s
  const auto lines = lines_of(write(square_part(), p));
  const std::size_t layer0 = index_of(lines, ";LAYER:0"), layer1 = index_of(lines, ";LAYER:1");
  for (std::size_t i = layer0; i < lines.size(); ++i) {
    const GcodeCommand c = parse_gcode_line(lines[i]);
    if (!c.is('G', 1) || !c.has('X') || !c.has('F')) continue;
    CAPTURE(lines[i]);
    if (i < layer1) CHECK(*c.get('F') == 900);
    else if (i < index_of(lines, ";LAYER:2")) CHECK(*c.get('F') != 900);
  }
  const std::size_t fill = index_of(lines, ";TYPE:FILL-SOLID", layer1);
  bool found = false;
  for (std::size_t i = fill; i < index_of(lines, ";LAYER:2") && !found; ++i) {
    const GcodeCommand c = parse_gcode_line(lines[i]);
    if (c.is('G', 1) && c.has('E') && c.has('F')) {
      CHECK(*c.get('F') == 2400);
      found = true;
    }
  }
  CHECK(found);
}

TEST_CASE("feature_comments_mark_each_change_of_role") {
  const auto lines = lines_of(write(square_part(), profiles("up-plus-2", "abs")));
  const test_support::PrintedProgram program = test_support::read_printed_program(
      [&] { std::string s; for (auto& l : lines) s += l + "\n"; return s; }());
  for (const auto& layer : program.layers) {
    CHECK(layer.types == std::vector<std::string>{"WALL-INNER", "WALL-OUTER", "FILL-SOLID"});
  }
}

TEST_CASE("fan_turns_on_at_the_materials_layer") {
  // PLA: off on layer 0, 100% from layer 1. ABS: never on.
  const auto pla = lines_of(write(square_part(), profiles("generic-marlin", "pla")));
  const std::size_t on = index_of(pla, "M106 S255");
  CHECK(on > index_of(pla, ";LAYER:1"));
  CHECK(on < index_of(pla, ";LAYER:2"));
  CHECK(index_of(pla, "M107") < index_of(pla, ";LAYER:0"));
  const auto abs = lines_of(write(square_part(), profiles("up-plus-2", "abs")));
  for (const auto& line : abs) CHECK_FALSE(line.starts_with("M106"));
}

TEST_CASE("end_gcode_follows_the_last_layer") {
  const auto lines = lines_of(write(square_part(), profiles("up-plus-2", "abs")));
  CHECK(index_of(lines, "M104 S0 ; nozzle off") > index_of(lines, ";LAYER:2"));
  CHECK(index_of(lines, "G1 X0 Y140 F6000 ; present the part") < lines.size());
  CHECK(lines.back() == "M73 P100 R0");
}

TEST_CASE("part_larger_than_the_bed_is_refused_with_both_sizes") {
  LayerToolpaths layer;
  layer.z_lo = 0;
  layer.z_hi = 0.3;
  layer.paths.push_back({PathRole::outer_wall, square_loop(150), 0.5, true});
  const Profiles p = profiles("up-plus-2", "abs");
  std::ostringstream out;
  CHECK(config_error([&] { write_gcode(out, {layer}, p); }) ==
        "the toolpaths (part and skirt) span 150.0 x 150.0 x 0.3 mm but the UP Plus 2 builds at "
        "most 140 x 140 x 135 mm; scale the part down (--scale, --height), set a smaller "
        "print.skirt_distance, or choose a bigger printer (--printer)");
  CHECK(out.str().empty());
}

TEST_CASE("part_taller_than_the_build_volume_is_refused") {
  LayerToolpaths layer = square_layer(135, 135.2, 10, 0.5);
  std::ostringstream out;
  CHECK(config_error([&] { write_gcode(out, {layer}, profiles("up-plus-2", "abs")); })
            .starts_with("the toolpaths (part and skirt) span 9.5 x 9.5 x 135.2 mm"));
}

TEST_CASE("empty_and_degenerate_layers_give_a_valid_program") {
  LayerToolpaths empty;
  empty.z_lo = 0;
  empty.z_hi = 0.3;
  LayerToolpaths flat = square_layer(0.3, 0.3, 10, 0.5);  // zero thickness: lays nothing
  LayerToolpaths single_point;
  single_point.z_lo = 0.3;
  single_point.z_hi = 0.5;
  single_point.paths.push_back({PathRole::outer_wall, {{1, 1}}, 0.5, true});
  const Profiles p = profiles("up-plus-2", "abs");
  GcodeSummary summary;
  const std::string text = write({empty, flat, single_point}, p, &summary);
  const test_support::PrintedProgram program = test_support::read_printed_program(text);
  CHECK(program.layers.size() == 3);
  CHECK(program.filament == 0);
  CHECK(summary.filament_mm == 0);
  CHECK(summary.layers == 3);
  GcodeSummary none;
  write({}, p, &none);
  CHECK(none.layers == 0);
  CHECK(none.filament_mm == 0);
}

TEST_CASE("written_numbers_reread_exactly") {
  // Coordinates off the 0.001 mm grid are rounded once, and beads are measured between the
  // rounded points, so no drift accumulates along a path.
  LayerToolpaths layer;
  layer.z_lo = 0;
  layer.z_hi = 0.3;
  std::vector<Vec2> zigzag;
  for (int i = 0; i <= 200; ++i) zigzag.push_back({-10 + 0.1000004 * i, (i % 2) * 0.3333333});
  layer.paths.push_back({PathRole::thin_wall, zigzag, 0.5, true});
  const Profiles p = profiles("up-plus-2", "abs");
  GcodeSummary summary;
  const std::string text = write({layer}, p, &summary);
  const test_support::PrintedProgram program = test_support::read_printed_program(text);
  REQUIRE(program.layers.size() == 1);
  const double per_mm = bead_area(0.5, 0.3) / filament_area(1.75);
  double length = 0;
  for (const auto& chain : program.layers[0].chains) {
    for (const auto& bead : chain) length += bead.length();
  }
  CHECK(program.filament == doctest::Approx(per_mm * length).epsilon(1e-6));
  CHECK(std::abs(program.filament - per_mm * length) <= 1e-5);
}

TEST_CASE("numbers_are_written_in_shortest_fixed_form") {
  // Every word's number: an optional minus, digits, and a fraction only if it is not zero,
  // without trailing zeros, never "-0"; and it is the value the reader sees (3 decimals for
  // X, Y, Z; 5 for E; whole for F). Relative E on generic-marlin writes negative E words.
  LayerToolpaths layer;
  layer.z_lo = 0;
  layer.z_hi = 0.3;
  std::vector<Vec2> zigzag;
  for (int i = 0; i <= 300; ++i) zigzag.push_back({-20.0004 + 0.1300049 * i, (i % 7) * -0.1000005});
  layer.paths.push_back({PathRole::thin_wall, zigzag, 0.5, true});
  layer.paths.push_back({PathRole::outer_wall, square_loop(3.0000005), 0.5, true});
  for (const char* printer : {"up-plus-2", "generic-marlin"}) {
    const auto lines = lines_of(write({layer, square_layer(0.3, 0.5, 20, 0.5)},
                                      profiles(printer, printer == std::string("up-plus-2") ? "abs" : "pla")));
    int words = 0, negative = 0;
    for (const std::string& line : lines) {
      // Moves the writer makes (the profile's start G-code is copied as written).
      if (!line.starts_with("G0 ") && !line.starts_with("G1 ")) continue;
      if (line.find(';') != std::string::npos) continue;
      std::istringstream in(line.substr(3));
      for (std::string word; in >> word;) {
        const std::string number = word.substr(1);
        INFO(line);
        REQUIRE(!number.empty());
        const bool minus = number[0] == '-';
        negative += minus;
        const std::string digits = number.substr(minus ? 1 : 0);
        const std::size_t dot = digits.find('.');
        CHECK(digits.find_first_not_of("0123456789.") == std::string::npos);
        CHECK(digits.find('.', dot == std::string::npos ? 0 : dot + 1) == std::string::npos);
        if (dot != std::string::npos) {
          CHECK(dot > 0);
          CHECK(digits.back() != '0');
          CHECK(digits.back() != '.');
        }
        CHECK(number != "-0");
        const int decimals = word[0] == 'E' ? 5 : word[0] == 'F' ? 0 : 3;
        const std::size_t fraction = dot == std::string::npos ? 0 : digits.size() - dot - 1;
        CHECK(fraction <= std::size_t(decimals));
        ++words;
      }
    }
    CHECK(words > 500);
    if (printer == std::string("generic-marlin")) CHECK(negative > 0);
  }
}

TEST_CASE("format_duration_reads_as_hours_minutes_seconds") {
  CHECK(format_duration(0) == "0 s");
  CHECK(format_duration(59.6) == "1 min 0 s");
  CHECK(format_duration(3 * 3600 + 25 * 60 + 7) == "3 h 25 min 7 s");
}

TEST_CASE("refused_file_is_neither_written_nor_clobbered") {
  const std::string path = "gcode_writer_test_refused.gcode";
  {
    std::ofstream previous(path);
    previous << "previous program\n";
  }
  LayerToolpaths layer;
  layer.z_lo = 0;
  layer.z_hi = 0.3;
  layer.paths.push_back({PathRole::outer_wall, square_loop(150), 0.5, true});
  CHECK_FALSE(config_error([&] { write_gcode_file(path, {layer}, profiles("up-plus-2", "abs")); }).empty());
  std::ifstream in(path);
  std::string first;
  std::getline(in, first);
  CHECK(first == "previous program");
  CHECK_FALSE(std::ifstream(path + ".part").good());
  std::remove(path.c_str());
}

TEST_CASE("file_in_a_missing_folder_is_refused_with_its_name") {
  CHECK(config_error([&] {
          write_gcode_file("/nonexistent-folder/part.gcode", square_part(), profiles("up-plus-2", "abs"));
        }).starts_with("cannot write '/nonexistent-folder/part.gcode': No such file or directory"));
}

TEST_CASE("collinear_points_are_written_as_one_move") {
  LayerToolpaths layer;
  layer.z_lo = 0;
  layer.z_hi = 0.3;
  std::vector<Vec2> line;
  for (int i = 0; i <= 1000; ++i) line.push_back({-10 + 0.02 * i, 5});
  layer.paths.push_back({PathRole::outer_wall, line, 0.5, true});
  const test_support::PrintedProgram program =
      test_support::read_printed_program(write({layer}, profiles("up-plus-2", "abs")));
  REQUIRE(program.layers.size() == 1);
  REQUIRE(program.layers[0].chains.size() == 1);
  CHECK(program.layers[0].chains[0].size() == 1);
  CHECK(program.layers[0].chains[0][0].length() == doctest::Approx(20).epsilon(1e-9));
}

TEST_CASE("dense_curve_is_written_within_the_printers_resolution") {
  // A circle of radius 10 sampled every 0.0063 mm: no written chord strays more than
  // gcode.resolution (0.0125 mm) from the circle, plus the 0.001 mm grid the points snap to.
  LayerToolpaths layer;
  layer.z_lo = 0;
  layer.z_hi = 0.3;
  std::vector<Vec2> circle;
  const int n = 10000;
  for (int i = 0; i <= n; ++i) {
    const double a = 2 * 3.141592653589793 * (i % n) / n;
    circle.push_back({10 * std::cos(a), 10 * std::sin(a)});
  }
  layer.paths.push_back({PathRole::outer_wall, circle, 0.5, true});
  const Profiles p = profiles("up-plus-2", "abs");
  REQUIRE(p.printer.resolution == 0.0125);
  const test_support::PrintedProgram program = test_support::read_printed_program(write({layer}, p));
  REQUIRE(program.layers.size() == 1);
  const auto& chain = program.layers[0].chains.at(0);
  // Sagitta of a chord c on radius r is c^2 / (8 r): chords up to sqrt(8 * 10 * 0.0125) = 1 mm.
  CHECK(chain.size() < 200);
  CHECK(chain.size() > 31);  // 2 pi 10 / 1 mm
  for (const test_support::Bead& bead : chain) {
    const Vec2 mid{(bead.from.x + bead.to.x) / 2 - 70, (bead.from.y + bead.to.y) / 2 - 70};
    CHECK(10 - std::hypot(mid.x, mid.y) <= 0.0125 + 0.001);
  }
  // --set gcode.resolution=0 keeps every point not exactly in line with its neighbours on the
  // 0.001 mm grid (near the axes many are).
  const test_support::PrintedProgram exact = test_support::read_printed_program(
      write({layer}, profiles("up-plus-2", "abs", {"gcode.resolution=0"})));
  CHECK(exact.layers[0].chains.at(0).size() > 5000);
}

std::vector<LayerToolpaths> bridged_part();

TEST_CASE("a_teacup_profile_heats_with_m104_m140_and_waits_with_m116_without_m73_or_m107") {
  // Teacup has no M107, M109, M190, M73 (gcode_process.c): not even in the profile's own end
  // G-code (whose M107 becomes M106 S0), nor for a bridge's fan.
  const auto lines = lines_of(write(bridged_part(), profiles("up-plus-2", "abs",
                                                             {"firmware=teacup", "material.bridge.fan=30"})));
  const std::size_t wait = index_of(lines, "M116");
  CHECK(index_of(lines, "M140 S105") < wait);
  CHECK(index_of(lines, "M104 S250") < wait);
  CHECK(wait < index_of(lines, "G28 ; home all axes"));
  for (const std::string& line : lines) {
    CAPTURE(line);
    const GcodeCommand c = parse_gcode_line(line);
    CHECK_FALSE(c.is('M', 109));
    CHECK_FALSE(c.is('M', 190));
    CHECK_FALSE(c.is('M', 73));
    CHECK_FALSE(c.is('M', 107));
  }
  CHECK(index_of(lines, "M106 S0") < index_of(lines, ";LAYER:0"));
  CHECK(index_of(lines, "M106 S77") < lines.size());  // the bridge's fan, then back
  const std::size_t end = index_of(lines, ";end G-code from the printer profile");
  CHECK(index_of(lines, "M106 S0", end) < lines.size());  // the profile's M107
  // Everything else as for Marlin: the same layers and moves.
  const auto marlin = lines_of(write(bridged_part(), profiles("up-plus-2", "abs", {"material.bridge.fan=30"})));
  CHECK(std::count_if(lines.begin(), lines.end(), [](const std::string& l) { return l.starts_with("G1 "); }) ==
        std::count_if(marlin.begin(), marlin.end(), [](const std::string& l) { return l.starts_with("G1 "); }));
}

TEST_CASE("a_profile_line_the_firmware_does_not_have_is_refused_with_the_key_and_the_line") {
  std::string message;
  try {
    write(square_part(), profiles("up-plus-2", "abs", {"firmware=teacup", "gcode.end=M117 Done\nM84"}));
  } catch (const ConfigError& e) {
    message = e.what();
  }
  CHECK(message == "the printer profile's gcode.end has \"M117 Done\", which Teacup does not have: "
                   "remove it from the profile, or set firmware to the printer's (one of marlin, "
                   "teacup, repetier)");
  // Its own equivalents are written instead: M109 as M104 and M116, M400 as G4 P0.
  const auto lines = lines_of(write(square_part(), profiles("up-plus-2", "abs",
                                                            {"firmware=teacup", "gcode.end=M400\nM109 S0\nM84"})));
  const std::size_t end = index_of(lines, ";end G-code from the printer profile");
  CHECK(index_of(lines, "G4 P0", end) < index_of(lines, "M104 S0", end));
  CHECK(index_of(lines, "M104 S0", end) < index_of(lines, "M116", end));
}

// A layer of one bridge line over the square, then one support line beside it.
std::vector<LayerToolpaths> bridged_part() {
  std::vector<LayerToolpaths> layers = square_part(0.5);
  LayerToolpaths top;
  top.z_lo = 0.7;
  top.z_hi = 0.9;
  top.paths.push_back({PathRole::bridge, {{-9, 0}, {9, 0}}, 0.5, true});
  top.paths.push_back({PathRole::support, {{-9, 5}, {9, 5}}, 0.5, false});
  top.paths.push_back({PathRole::support_interface, {{-9, 6}, {9, 6}}, 0.5, false});
  layers.push_back(top);
  return layers;
}

TEST_CASE("bridges_take_the_materials_flow_fan_and_the_bridge_speed") {
  // PLA: the fan at 100% from layer 1 anyway; bridge fan 30% here, flow 0.9, speed 17 mm/s.
  const Profiles p = profiles("generic-marlin", "pla",
                              {"material.bridge.fan=30", "material.bridge.flow=0.9", "speed.bridge=17"});
  const std::string text = write(bridged_part(), p);
  const auto lines = lines_of(text);
  const std::size_t layer = index_of(lines, ";LAYER:3"), type = index_of(lines, ";TYPE:BRIDGE", layer);
  REQUIRE(type < lines.size());
  // 30% = S77, set before the bridge's first extrusion; back to 100% (S255) before the support.
  const std::size_t fan = index_of(lines, "M106 S77", layer);
  CHECK(fan > type);
  CHECK(fan < index_of(lines, ";TYPE:SUPPORT", layer));
  const std::size_t support = index_of(lines, ";TYPE:SUPPORT", layer);
  std::size_t laid = support;  // the support's first extrusion
  while (laid < lines.size() && !(lines[laid].starts_with("G1 X") && lines[laid].find(" E") != std::string::npos)) ++laid;
  CHECK(index_of(lines, "M106 S255", fan) < laid);
  const test_support::PrintedProgram program =
      test_support::read_printed_program(text, {p.printer.filament_diameter, p.material.flow});
  const test_support::Bead& bridge = program.layers[3].chains[0][0];
  CHECK(bridge.filament ==
        doctest::Approx(0.9 * filament_for_bead(0.5, 0.2, 18, 1.75, p.material.flow)).epsilon(1e-5));
  bool fast = false;
  for (const std::string& line : lines) fast = fast || line.find("F1020") != std::string::npos;
  CHECK(fast);  // 17 mm/s
}

TEST_CASE("support_and_raft_filament_is_counted_apart") {
  const Profiles p = profiles("up-plus-2", "abs");
  GcodeSummary summary;
  write(bridged_part(), p, &summary);
  // The two 18 mm support lines, at the layer's 0.2 mm: support and interface both count.
  CHECK(summary.support_filament_mm ==
        doctest::Approx(2 * filament_for_bead(0.5, 0.2, 18, 1.75, p.material.flow)).epsilon(1e-6));
  GcodeSummary plain;
  write(square_part(), p, &plain);
  CHECK(plain.support_filament_mm == 0);
  const auto lines = lines_of(write(bridged_part(), p));
  CHECK(index_of(lines, ";TYPE:SUPPORT") < lines.size());
  CHECK(index_of(lines, ";TYPE:SUPPORT-INTERFACE") < lines.size());
}

TEST_CASE("each_layer_is_laid_at_its_own_thickness") {
  // A stack of mixed thicknesses: 0.3 mm first, then 0.15, 0.4, 0.25 mm. Every layer has
  // ";HEIGHT:" after ";Z:", and its beads, read back at the printer's layer height (its Z
  // less the Z below), are as wide as planned: the filament per mm of bead scales with the
  // layer's own thickness.
  const Profiles p = profiles("up-plus-2", "abs");
  const double w = 0.5;
  const std::vector<LayerToolpaths> part{square_layer(0, 0.3, 20, w), square_layer(0.3, 0.45, 20, w),
                                         square_layer(0.45, 0.85, 20, w),
                                         square_layer(0.85, 1.1, 20, w)};
  GcodeSummary summary;
  const std::string text = write(part, p, &summary);
  const auto lines = lines_of(text);
  std::vector<std::string> zs, heights;
  for (std::size_t i = 0; i + 2 < lines.size(); ++i) {
    if (!lines[i].starts_with(";LAYER:")) continue;
    zs.push_back(lines[i + 1]);
    heights.push_back(lines[i + 2]);
    CHECK(lines[i + 3].starts_with("M73 P"));
  }
  CHECK(zs == std::vector<std::string>{";Z:0.3", ";Z:0.45", ";Z:0.85", ";Z:1.1"});
  CHECK(heights == std::vector<std::string>{";HEIGHT:0.3", ";HEIGHT:0.15", ";HEIGHT:0.4", ";HEIGHT:0.25"});
  const test_support::PrintedProgram program = test_support::read_printed_program(text);
  CHECK(program.problems.empty());
  REQUIRE(program.layers.size() == 4);
  const double expected_height[] = {0.3, 0.15, 0.4, 0.25};
  for (std::size_t i = 0; i < 4; ++i) {
    CAPTURE(i);
    const test_support::PrintedLayer& layer = program.layers[i];
    CHECK(layer.height == doctest::Approx(expected_height[i]));
    double length = 0;
    for (const auto& chain : layer.chains)
      for (const auto& bead : chain) {
        CHECK(bead.width == doctest::Approx(w).epsilon(0.02));
        length += bead.length();
      }
    // Filament over the layer = bead cross-section at this thickness x length / filament area.
    const double expected =
        printer::filament_for_bead(w, expected_height[i], length, p.printer.filament_diameter,
                                   p.material.flow);
    CHECK(layer.filament == doctest::Approx(expected).epsilon(1e-3));
  }
  // The progress lines rise with the time the layers take.
  CHECK(program.header.at("LAYER_COUNT") == "4");
  CHECK(summary.layers == 4);
}

}  // namespace gcode_writer_test

namespace gcode_writer_test {

TEST_CASE("a_start_gcode_that_heats_itself_is_left_to_heat") {
  // The heater a start G-code sets (as PrusaSlicer's vendors' do) is not heated before it again;
  // the other one still is.
  const std::string start = "G28\nM190 S{first_layer_bed_temperature} ; the bed, waiting\nG1 Z5";
  const Profiles p = profiles("generic-marlin", "pla", {"gcode.start=" + start});
  const auto lines = lines_of(write(square_part(), p));
  const std::size_t home = index_of(lines, "G28");
  CHECK(index_of(lines, "M190 S60 ; the bed, waiting") > home);
  CHECK(index_of(lines, "M140 S60") == lines.size());  // no bed heating of the writer's
  CHECK(index_of(lines, "M104 S210") < home);
  CHECK(index_of(lines, "M109 S210") < home);
  // M1040 or an M104 in a comment heats nothing.
  const Profiles q = profiles("generic-marlin", "pla", {"gcode.start=G28 ; M104 S200\\nM1040 S1"});
  CHECK(index_of(lines_of(write(square_part(), q)), "M109 S210") < lines.size());
}

TEST_CASE("a_part_is_centred_on_the_bed_in_the_gcodes_coordinates") {
  // A delta's bed: a circle of 200 mm whose centre is the G-code's origin.
  const Profiles p = profiles("generic-marlin", "pla",
                              {"build_volume.x=200", "build_volume.y=200", "build_volume.origin_x=-100",
                               "build_volume.origin_y=-100", "build_volume.shape=circle"});
  const test_support::PrintedProgram program = test_support::read_printed_program(write(square_part(), p));
  double min_x = 1e9, max_x = -1e9, min_y = 1e9, max_y = -1e9;
  for (const auto& layer : program.layers) {
    for (const auto& chain : layer.chains) {
      for (const auto& bead : chain) {
        min_x = std::min({min_x, bead.from.x, bead.to.x});
        max_x = std::max({max_x, bead.from.x, bead.to.x});
        min_y = std::min({min_y, bead.from.y, bead.to.y});
        max_y = std::max({max_y, bead.from.y, bead.to.y});
      }
    }
  }
  CHECK(min_x == doctest::Approx(-9.75));
  CHECK(max_x == doctest::Approx(9.75));
  CHECK(min_y == doctest::Approx(-9.75));
  CHECK(max_y == doctest::Approx(9.75));
  // The corners of a square that fits the circle's box but not the circle are off the bed.
  std::vector<LayerToolpaths> wide = {square_layer(0, 0.2, 160, 0.5)};
  CHECK(config_error([&] { write(wide, p); }).find("(a round bed)") != std::string::npos);
  std::vector<LayerToolpaths> fits = {square_layer(0, 0.2, 140, 0.5)};
  CHECK(config_error([&] { write(fits, p); }).empty());
}

TEST_CASE("prusaslicer_end_gcode_knows_the_top_of_the_last_layer") {
  Profiles p = profiles("generic-marlin", "pla");
  p.printer.gcode_syntax = GcodeSyntax::prusaslicer;
  p.printer.start_gcode = "G28 ; [first_layer_temperature]";
  p.printer.end_gcode = "G1 Z{max_layer_z + 10} ; of {total_layer_count}";
  const auto lines = lines_of(write(square_part(), p));
  CHECK(index_of(lines, "G28 ; 210") < lines.size());
  CHECK(index_of(lines, "G1 Z10.7 ; of 3") < lines.size());
}

}  // namespace gcode_writer_test
