// The five readers of a G-code program (the estimate's clock, the host's print state, the
// layer finder, the deposition record, the tests' bead reader) read one program that uses
// every rule of printer/gcode_interpreter.h, and agree on where filament went.
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include <doctest/doctest.h>

#include "printer/layer_tops.h"
#include "printer/print_state.h"
#include "printer/print_time.h"
#include "sim/gcode_deposition.h"
#include "support/gcode_beads.h"

namespace gcode_deposition_test {

namespace {

// Every rule: homing, G92 with and without axes, mm and inches, absolute and relative modes
// (G91 taking E along, M83 alone), firmware retraction with a Z-raise, the layer and feature
// comments, a G2 half circle in Marlin's chords.
const std::string kProgram =
    "M207 S2 F2400 Z0.5\n"
    "G28\n"
    "G90\n"
    "M82\n"
    "G92 E0\n"
    "G1 Z0.3 F600\n"
    "G1 X10 Y10 F3000\n"
    ";LAYER:0\n"
    ";TYPE:WALL-OUTER\n"
    "G1 X20 Y10 E1\n"       // bead 1: 1 mm of filament
    "G1 X20 Y20 E2\n"       // bead 2: 1 mm
    "G10\n"                 // 2 mm back, nozzle up 0.5
    "G0 X30 Y30\n"
    "G11\n"                 // down, 2 mm forward
    "G91\n"
    "G1 X0 Y10 E0.5\n"      // bead 3: relative X Y and E, to (30, 40)
    "G90\n"
    "M83\n"
    "G1 X40 Y40 E0.5\n"     // bead 4: absolute X Y, relative E
    "G92\n"                 // changes nothing
    "G2 X50 Y40 I5 J0 E0.5\n"  // beads 5-40: clockwise over the top to (50, 40)
    "M82\n"
    "G92 E0\n"
    "G20\n"
    "G1 Z0.023622047\n"     // 0.6 mm in inches
    "G21\n"
    ";LAYER:1\n"
    ";TYPE:FILL\n"
    "G1 X60 Y40 E1\n"       // bead 6: at Z 0.6
    "G28 X\n"
    "G1 Y50\n"              // from (0, 40) to (0, 50), a travel
    "G1 X5 E1.5\n";         // bead 7: from (0, 50)

struct Bead {
  double x0, y0, x1, y1, filament, z;
};
// The G2's half turn about (45, 40), radius 5: 7.85 mm, so MIN_CIRCLE_SEGMENTS' 36 chords
// (Marlin 2.1's G2_G3.cpp), 0.5 mm of filament spread evenly.
std::vector<Bead> half_circle() {
  std::vector<Bead> beads;
  constexpr int kChords = 36;
  for (int k = 1; k <= kChords; ++k) {
    const double a0 = std::numbers::pi * (1 - (k - 1.0) / kChords), a1 = std::numbers::pi * (1 - double(k) / kChords);
    beads.push_back({45 + 5 * std::cos(a0), 40 + 5 * std::sin(a0), 45 + 5 * std::cos(a1),
                     40 + 5 * std::sin(a1), 0.5 / kChords, 0.3});
  }
  return beads;
}

std::vector<Bead> beads() {
  std::vector<Bead> all = {{10, 10, 20, 10, 1, 0.3}, {20, 10, 20, 20, 1, 0.3},
                           {30, 30, 30, 40, 0.5, 0.3}, {30, 40, 40, 40, 0.5, 0.3}};
  for (const Bead& b : half_circle()) all.push_back(b);
  all.push_back({50, 40, 60, 40, 1, 0.6});
  all.push_back({0, 50, 5, 50, 0.5, 0.6});
  return all;
}
const std::vector<Bead> kBeads = beads();

}  // namespace

TEST_CASE("five_readers_agree_on_a_program_using_every_rule") {
  // The deposition record.
  const sim::DepositionRecord record = sim::deposition_from_gcode(kProgram);
  REQUIRE(record.moves.size() == kBeads.size());
  for (std::size_t i = 0; i < kBeads.size(); ++i) {
    CAPTURE(i);
    const sim::DepositedMove& m = record.moves[i];
    CHECK(m.start.x == doctest::Approx(kBeads[i].x0));
    CHECK(m.start.y == doctest::Approx(kBeads[i].y0));
    CHECK(m.end.x == doctest::Approx(kBeads[i].x1));
    CHECK(m.end.y == doctest::Approx(kBeads[i].y1));
    CHECK(m.e == doctest::Approx(kBeads[i].filament));
    CHECK(m.z == doctest::Approx(kBeads[i].z));
  }

  // The bead reader: the same beads, in two layers and their features.
  const test_support::PrintedProgram printed = test_support::read_printed_program(kProgram);
  REQUIRE(printed.layers.size() == 2);
  std::vector<test_support::Bead> beads;
  for (const test_support::PrintedLayer& layer : printed.layers) {
    for (const auto& chain : layer.chains) beads.insert(beads.end(), chain.begin(), chain.end());
  }
  REQUIRE(beads.size() == kBeads.size());
  for (std::size_t i = 0; i < kBeads.size(); ++i) {
    CAPTURE(i);
    CHECK(beads[i].from.x == doctest::Approx(kBeads[i].x0));
    CHECK(beads[i].to.y == doctest::Approx(kBeads[i].y1));
    CHECK(beads[i].filament == doctest::Approx(kBeads[i].filament));
  }
  CHECK(printed.layers[0].z == doctest::Approx(0.3));
  CHECK(printed.layers[1].z == doctest::Approx(0.6));
  CHECK(printed.layers[0].chain_types.front() == "WALL-OUTER");
  CHECK(printed.layers[1].chain_types.front() == "FILL");
  CHECK(printed.retractions == 1);  // G10; G11 feeds
  CHECK(printed.problems.empty());

  // The layer finder: the heights filament was laid at.
  const std::vector<double> tops = printer::layer_tops_from_gcode(kProgram, "program");
  REQUIRE(tops.size() == 2);
  CHECK(tops[0] == doctest::Approx(0.3));
  CHECK(tops[1] == doctest::Approx(0.6));

  // The host's print state and the estimate's clock: where the program ends, and the net
  // filament fed (the beads' 5 mm, the retraction given back).
  printer::PrintState state;
  printer::PrintClock clock(printer::MotionLimits{});
  std::size_t start = 0;
  while (start < kProgram.size()) {
    const std::size_t end = kProgram.find('\n', start);
    const std::string line = kProgram.substr(start, end - start);
    printer::apply(state, line);
    clock.line(line);
    start = end + 1;
  }
  CHECK(state.x == 5);
  CHECK(state.y == 50);
  CHECK(state.z == doctest::Approx(0.6));
  CHECK(state.e == 1.5);
  CHECK(state.filament_fed == doctest::Approx(5));
  CHECK(clock.position().x == 5);
  CHECK(clock.position().y == 50);
  CHECK(clock.position().z == doctest::Approx(0.6));
  CHECK(clock.position().e == 1.5);
}

}  // namespace gcode_deposition_test
