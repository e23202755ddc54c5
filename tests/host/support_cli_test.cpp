// Supports, bridges, brim, raft and orientation as a user slices with them: the
// G-code read back bead by bead and judged by the unsupported-extrusion check
// (sim/unsupported_extrusion.h), which knows nothing of how the supports were planned; the
// gaps that let supports come off, measured between the printed beads; the options refused
// in one line.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <numbers>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <doctest/doctest.h>

#include "geometry/core/clipper.h"
#include "geometry/mesh/stl_io.h"
#include "sim/gcode_deposition.h"
#include "sim/unsupported_extrusion.h"
#include "support/gcode_beads.h"
#include "support/run_command.h"
#include "support/solids.h"

namespace support_cli_test {

using test_support::run_mahost;
namespace clipper = geometry::clipper;

namespace {

std::string read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// The UP Plus 2 with ABS: 10 mm bridges, 0.2 mm top and bottom contact distances, 0.2 mm
// layers after a 0.3 mm first layer, 0.45 mm beads.
sim::SupportCheckOptions up_plus_2_check() {
  sim::SupportCheckOptions o;
  o.filament_diameter = 1.75;
  o.bridge_length = 10;
  o.contact_gap = 0.2;
  o.stretches_kept = 100000;
  return o;
}

struct Sliced {
  std::string gcode;
  sim::SupportCheck check;
};

Sliced slice(const std::string& dir, const std::string& name, const geometry::Mesh& mesh,
             std::vector<std::string> options) {
  const std::string stl = dir + "/" + name + ".stl", out = dir + "/" + name + ".gcode";
  geometry::write_stl_binary(stl, mesh);
  std::vector<std::string> args{"slice", stl, "-o", out};
  args.insert(args.end(), options.begin(), options.end());
  const auto result = run_mahost(args);
  REQUIRE(result.exit_code == 0);
  Sliced s;
  s.gcode = read_file(out);
  s.check = sim::check_unsupported_extrusion(sim::deposition_from_gcode(s.gcode), up_plus_2_check());
  return s;
}

const std::vector<std::string> kSupported{"--support", "everywhere", "--no-raft", "--layer", "0.2"};

double longest(const sim::SupportCheck& check) {
  double most = 0;
  for (const sim::UnsupportedStretch& s : check.stretches) most = std::max(most, s.length);
  return most;
}

double in_the_open(const sim::SupportCheck& check) { return check.unsupported_mm - check.between_mm; }

// A T, one closed mesh: a 10 x 10 x 20 mm stem under a 10 x 50 x 5 mm bar, its two wings
// 20 mm long along y.
geometry::Mesh tee() {
  return solids::lying_prism({{-5, 0}, {5, 0}, {5, 20}, {25, 20}, {25, 25}, {-25, 25}, {-25, 20}, {-5, 20}},
                             -5, 5).mesh;
}

// A wedge 20 mm wide (x), 10 mm deep at its foot, 20 mm tall, its +y face leaning out at
// `degrees` from vertical.
geometry::Mesh wedge(double degrees) {
  const double lean = 20 * std::tan(degrees * std::numbers::pi / 180);
  return solids::lying_prism({{0, 0}, {10, 0}, {10 + lean, 20}, {0, 20}}, -10, 10).mesh;
}

// An arch 40 x 10 x 25 mm with a semicircular opening 24 mm across.
geometry::Mesh arch() {
  std::vector<geometry::Vec2> profile{{-20, 0}, {-12, 0}};
  for (int i = 1; i < 64; ++i) {
    const double a = std::numbers::pi * (1 - i / 64.0);
    profile.push_back({12 * std::cos(a), 12 * std::sin(a)});
  }
  profile.insert(profile.end(), {{12, 0}, {20, 0}, {20, 25}, {-20, 25}});
  return solids::lying_prism(profile, -5, 5).mesh;
}

// Bead outlines rebuilt from the G-code (E rounded to 10 nm of filament, joins round within
// 2 um) touch in specks of a few tens of micrometres: a layer's touching adds up to less.
constexpr double kSpecks = 0.01;  // mm^2
constexpr double kCorners = 0.05;  // mm

bool is_support(const std::string& type) {
  return type == "SUPPORT" || type == "SUPPORT-INTERFACE";
}
bool is_part(const std::string& type) {
  return !is_support(type) && type != "SKIRT" && type != "BRIM" && type != "RAFT";
}

}  // namespace

TEST_CASE("parts_with_overhangs_print_nothing_into_the_air_with_supports") {
  const std::string dir = test_support::scratch_dir("support_overhangs");
  struct Part {
    std::string name;
    geometry::Mesh mesh;
  };
  std::vector<Part> parts{{"tee", tee()}, {"wedge30", wedge(30)}, {"wedge45", wedge(45)},
                          {"wedge60", wedge(60)}, {"wedge75", wedge(75)}, {"arch", arch()}};
  for (const Part& part : parts) {
    CAPTURE(part.name);
    const Sliced s = slice(dir, part.name, part.mesh, kSupported);
    MESSAGE(part.name << ": " << sim::unsupported_summary(s.check, up_plus_2_check()));
    // What is left: specks at the corners of loops and skins, none longer than a bead is
    // wide (a bead's own corner over the edge of the one below), half a millimetre in all
    // (none on any of them when written).
    CHECK(s.check.unsupported_mm <= 0.5);
    CHECK(longest(s.check) <= 0.45);
    CHECK(s.check.extruded_mm > 10000);
    if (part.name == "wedge30" || part.name == "wedge45") {
      // Within the 50 degrees ABS stands unsupported: at 0.2 mm a 45 degree face steps out
      // 0.2 mm a layer, less than 0.2 tan 50 = 0.24. Its flat top lands on a boundary at
      // 20.0 mm with the two layers under it a step thinner (0.15 mm), not thicker, which
      // would step out past that reach.
      CHECK(s.gcode.find(";TYPE:SUPPORT") == std::string::npos);
    } else {
      CHECK(s.gcode.find(";TYPE:SUPPORT\n") != std::string::npos);
      CHECK(s.gcode.find(";TYPE:SUPPORT-INTERFACE\n") != std::string::npos);
    }
  }
}

TEST_CASE("a_sphere_prints_nothing_into_the_air_with_supports") {
  const std::string dir = test_support::scratch_dir("support_sphere");
  const Sliced s = slice(dir, "sphere", solids::sphere(15, 64, 32, {0, 0, 15}).mesh, kSupported);
  MESSAGE("sphere: " << sim::unsupported_summary(s.check, up_plus_2_check()));
  // Nothing when written. The dome's top skins lie over its own sparse infill: their line
  // ends rest on the line the infill lays under each skin edge (skin_edge_lines), the ring
  // inside its walls is one path along it, not dashes across it; so nothing hangs between
  // the sparse lines either (0.1% before those). Bounded at a bead's width.
  CHECK(s.check.unsupported_mm <= 0.45);
}

TEST_CASE("the_bunny_prints_nothing_into_the_air_with_supports") {
  const std::string dir = test_support::scratch_dir("support_bunny");
  const std::string out = dir + "/bunny.gcode";
  const auto result = run_mahost({"slice", MAHOST_DATA_DIR "/bunny.stl", "--up", "y", "--units",
                                  "m", "--height", "50", "-o", out, "--support", "everywhere",
                                  "--no-raft"});
  REQUIRE(result.exit_code == 0);
  const sim::SupportCheck check =
      sim::check_unsupported_extrusion(sim::deposition_from_gcode(read_file(out)), up_plus_2_check());
  MESSAGE("bunny: " << sim::unsupported_summary(check, up_plus_2_check()));
  // In the open: a few millimetres of support (6.4 mm when this was written), sheath and
  // line pieces of thin columns beside the part whose line is missing below, none longer
  // than a few millimetres; between sparse lines (0.05% when written, 0.15% before the lines
  // under skin edges): support interface ends between the support's lines below, specks of
  // the sheath, and the part's sparse lines past the layer below's where its skin edges run
  // close along the walls.
  CHECK(in_the_open(check) <= 10.0);
  for (const sim::UnsupportedStretch& s : check.stretches) {
    if (!s.between) CHECK(s.length <= 5.0);
  }
  CHECK(check.unsupported_mm <= 0.001 * check.extruded_mm);
}

TEST_CASE("an_adaptive_bunny_prints_nothing_into_the_air_and_its_supports_keep_the_gap_in_mm") {
  // Layers of their own thicknesses (--adaptive, 0.15 to 0.4 mm): the support's top contact
  // distance is 0.2 mm of air, measured against the layers there, and the check reads each
  // layer at its own height.
  const std::string dir = test_support::scratch_dir("support_bunny_adaptive");
  const std::string out = dir + "/bunny.gcode";
  const auto result = run_mahost({"slice", MAHOST_DATA_DIR "/bunny.stl", "--up", "y", "--units",
                                  "m", "--height", "50", "-o", out, "--support", "everywhere",
                                  "--no-raft", "--adaptive", "--tolerance", "0.3"});
  REQUIRE(result.exit_code == 0);
  const std::string gcode = read_file(out);
  const test_support::PrintedProgram program = test_support::read_printed_program(gcode);
  std::set<long> heights;  // in um
  for (const auto& layer : program.layers) heights.insert(std::lround(layer.height * 1000));
  CHECK(heights.size() >= 3);  // a variable stack indeed
  const sim::SupportCheck check =
      sim::check_unsupported_extrusion(sim::deposition_from_gcode(gcode), up_plus_2_check());
  MESSAGE("adaptive bunny: " << sim::unsupported_summary(check, up_plus_2_check()));
  // In the open, the uniform bunny's bounds (3.9 mm when this was written). Between sparse
  // lines below: 0.08% when written (0.25% before the lines under skin edges), none into the
  // air; bounded at 0.15%.
  CHECK(in_the_open(check) <= 10.0);
  for (const sim::UnsupportedStretch& s : check.stretches) {
    if (!s.between) CHECK(s.length <= 5.0);
  }
  CHECK(check.unsupported_mm <= 0.0015 * check.extruded_mm);
  // No part bead in any layer that starts less than 0.2 mm above a support layer's top lies
  // over its support (the same 10 um and 50 um allowances as for the uniform gaps). From
  // layer 1: on the bed, the support's 0.5 mm first-layer beads end round up to 0.1 mm past
  // the edge of the part 0.15 mm above them (two crescents of 0.02 mm^2 when written).
  std::size_t layers_with_support = 0;
  for (std::size_t j = 1; j + 1 < program.layers.size(); ++j) {
    const clipper::Paths support = geometry::to_clipper(test_support::bead_region(program.layers[j], is_support));
    if (support.empty()) continue;
    ++layers_with_support;
    const clipper::Paths inner = clipper::offset(support, -kCorners);
    for (std::size_t i = j + 1; i < program.layers.size(); ++i) {
      const auto& above_layer = program.layers[i];
      if (above_layer.z - above_layer.height >= program.layers[j].z + 0.2 - 1e-6) break;
      CAPTURE(j);
      CAPTURE(i);
      const clipper::Paths above = clipper::offset(geometry::to_clipper(test_support::bead_region(above_layer, is_part)), -0.01);
      CHECK(clipper::area_mm2(clipper::intersection(inner, above)) < kSpecks);
    }
  }
  CHECK(layers_with_support > 20);
}

TEST_CASE("without_supports_the_check_finds_the_overhangs_extruded_into_the_air") {
  const std::string dir = test_support::scratch_dir("support_none");
  const Sliced s = slice(dir, "tee", tee(), {"--support", "none", "--no-raft", "--layer", "0.2"});
  // The bar's first layer over its two 20 x 10 mm wings: about 400 mm^2 of 0.407 mm shares,
  // nearly all of it in the open.
  CHECK(s.check.unsupported_mm > 800);
  CHECK(in_the_open(s.check) > 800);
  CHECK(s.gcode.find(";TYPE:SUPPORT") == std::string::npos);
}

TEST_CASE("supports_keep_the_xy_gap_and_the_top_contact_distance_on_every_layer") {
  const std::string dir = test_support::scratch_dir("support_gaps");
  for (const std::string xy : {"0.2", "0.6"}) {
    CAPTURE(xy);
    std::vector<std::string> options = kSupported;
    options.insert(options.end(), {"--support-xy-gap", xy, "--support-top-distance", "0.2"});
    for (const auto& [name, mesh] : {std::pair{std::string("tee"), tee()},
                                     std::pair{std::string("sphere"), solids::sphere(15, 64, 32, {0, 0, 15}).mesh}}) {
      CAPTURE(name);
      const Sliced s = slice(dir, name + xy, mesh, options);
      const test_support::PrintedProgram program = test_support::read_printed_program(s.gcode);
      const double gap = std::stod(xy);
      std::size_t layers_with_support = 0;
      for (std::size_t j = 0; j + 1 < program.layers.size(); ++j) {
        CAPTURE(j);
        const clipper::Paths support = geometry::to_clipper(test_support::bead_region(program.layers[j], is_support));
        if (support.empty()) continue;
        ++layers_with_support;
        // Beside the part: its beads in the same layer stay the gap away (less 20 um for the
        // beads' rebuilt round joins and the E rounding).
        const clipper::Paths part = geometry::to_clipper(test_support::bead_region(program.layers[j], is_part));
        CHECK(clipper::area_mm2(clipper::intersection(support, clipper::offset(part, gap - 0.02, ClipperLib::jtRound))) < kSpecks);
        // Under the part: 0.2 mm of air, one layer: nothing of the layer above is part (the
        // part's beads taken 10 um in, for the same rebuilt joins and rounding, and the
        // support's 50 um: an interface line meeting its loop slantwise ends square-cut here,
        // its corner past the loop, where a printed bead ends round).
        const clipper::Paths above = clipper::offset(
            geometry::to_clipper(test_support::bead_region(program.layers[j + 1], is_part)), -0.01);
        CHECK(clipper::area_mm2(clipper::intersection(clipper::offset(support, -kCorners), above)) < kSpecks);
      }
      // The T's wings from the bed to 19.8 mm; the sphere's cap, as far as its surface leans
      // more than 50 degrees from vertical: up to 15 (1 - cos 40) = 3.5 mm.
      CHECK(layers_with_support > (name == "tee" ? 90u : 12u));
    }
  }
}

TEST_CASE("a_bridge_within_the_bridge_length_is_laid_as_bridge_lines") {
  // Two pillars 8 mm apart joined by a 2 mm beam: at 10 mm (ABS) a bridge, at 5 mm support.
  // The beam's underside at 10.1 mm, on a layer boundary (0.3 mm, then 0.2 mm layers).
  const std::string dir = test_support::scratch_dir("support_bridge");
  const geometry::Mesh mesh =
      solids::lying_prism({{-10, 0}, {-4, 0}, {-4, 10.1}, {4, 10.1}, {4, 0}, {10, 0}, {10, 12.1}, {-10, 12.1}},
                          -5, 5).mesh;
  // Mid sections: the layer under the beam is empty (the ma contour of the slab whose top
  // is the beam's underside keeps a piece of that face).
  std::vector<std::string> mid = kSupported;
  mid.insert(mid.end(), {"--contour", "mid"});
  const Sliced bridged = slice(dir, "beam", mesh, mid);
  CHECK(bridged.gcode.find(";TYPE:BRIDGE\n") != std::string::npos);
  CHECK(bridged.gcode.find(";TYPE:SUPPORT") == std::string::npos);
  CHECK(bridged.gcode.find("; support: everywhere") != std::string::npos);
  CHECK(bridged.check.unsupported_mm <= 1.0);
  // The material's bridge fan with the bridge lines (ABS: 40% = M106 S102), off after them.
  const std::size_t at = bridged.gcode.find(";TYPE:BRIDGE\n");
  const std::size_t next = bridged.gcode.find(";TYPE:", at + 1);
  CHECK(bridged.gcode.find("M106 S102\n", at) < next);
  CHECK(bridged.gcode.find("M107\n", at) < bridged.gcode.find(";LAYER:", at));

  std::vector<std::string> short_bridges = mid;
  short_bridges.insert(short_bridges.end(), {"--bridge-length", "5"});
  const Sliced held = slice(dir, "beam5", mesh, short_bridges);
  CHECK(held.gcode.find(";TYPE:BRIDGE\n") == std::string::npos);
  CHECK(held.gcode.find(";TYPE:SUPPORT\n") != std::string::npos);
  CHECK(held.check.unsupported_mm <= 1.0);
}

TEST_CASE("blocker_and_enforcer_boxes_take_and_give_support") {
  const std::string dir = test_support::scratch_dir("support_boxes");
  // The UP Plus 2's bed is 140 x 140 mm: the part's centre is at X70 Y70. A blocker over
  // the -y wing leaves it bare.
  std::vector<std::string> blocked = kSupported;
  blocked.insert(blocked.end(), {"--support-blocker", "60,40,0,80,70,30"});
  const Sliced s = slice(dir, "tee", tee(), blocked);
  const test_support::PrintedProgram program = test_support::read_printed_program(s.gcode);
  double left = 0, right = 0;
  for (const auto& layer : program.layers) {
    const clipper::Paths support = geometry::to_clipper(test_support::bead_region(layer, is_support));
    for (const auto& path : support) {
      for (const auto& p : path) (geometry::from_clipper(p).y < 70 ? left : right) += 1;
    }
  }
  CHECK(right > 0);
  CHECK(left == 0);
  CHECK(s.check.unsupported_mm > 400);  // the blocked wing's first layer

  const auto bad = run_mahost({"slice", dir + "/tee.stl", "-o", dir + "/x.gcode", "--support-enforcer", "1,2,3"});
  CHECK(bad.exit_code == 2);
  CHECK(bad.err.starts_with("mahost: --support-enforcer '1,2,3': needs six numbers x0,y0,z0,x1,y1,z1"));
}

TEST_CASE("brim_and_raft_hold_the_part_down") {
  const std::string dir = test_support::scratch_dir("support_brim_raft");
  const Sliced brim = slice(dir, "brim", solids::box({0, 0, 0}, {20, 20, 5}).mesh,
                            {"--support", "none", "--no-raft", "--brim", "3", "--layer", "0.2"});
  const test_support::PrintedProgram b = test_support::read_printed_program(brim.gcode);
  REQUIRE_FALSE(b.layers.empty());
  // 3 mm of 0.5 mm first-layer beads: six loops round the square, on the first layer only.
  std::size_t loops = 0;
  for (std::size_t c = 0; c < b.layers[0].chains.size(); ++c) loops += b.layers[0].chain_types[c] == "BRIM";
  CHECK(loops == 6);
  for (std::size_t i = 1; i < b.layers.size(); ++i) {
    for (const std::string& type : b.layers[i].chain_types) CHECK(type != "BRIM");
  }
  CHECK(brim.gcode.find("; brim: 3 mm") != std::string::npos);

  // The UP Plus 2's own raft: base, interface and two surface layers, then 0.2 mm of air
  // under the part's 0.3 mm first layer.
  const Sliced raft = slice(dir, "raft", solids::box({0, 0, 0}, {20, 20, 5}).mesh, {"--layer", "0.2"});
  const test_support::PrintedProgram r = test_support::read_printed_program(raft.gcode);
  REQUIRE(r.layers.size() == 4 + 25);
  const double raft_z[] = {0.3, 0.5, 0.7, 0.9};
  for (std::size_t i = 0; i < 4; ++i) {
    CAPTURE(i);
    CHECK(r.layers[i].z == doctest::Approx(raft_z[i]));
    for (const std::string& type : r.layers[i].chain_types) CHECK((type == "RAFT" || type == "SKIRT"));
  }
  CHECK(r.layers[4].z == doctest::Approx(0.9 + 0.2 + 0.3));
  CHECK(raft.check.unsupported_mm <= 1.0);
  CHECK(raft.gcode.find("; raft: 4 layers, 1.10 mm under the part (air gap 0.2 mm), margin 3 mm") != std::string::npos);
}

TEST_CASE("rotate_and_orient_auto_turn_the_model_before_it_is_placed") {
  const std::string dir = test_support::scratch_dir("support_orient");
  const std::string box = dir + "/box.stl", t = dir + "/tee.stl";
  geometry::write_stl_binary(box, solids::box({0, 0, 0}, {10, 20, 30}).mesh);
  geometry::write_stl_binary(t, tee());
  auto r = run_mahost({"info", box, "--rotate", "x:90"});
  REQUIRE(r.exit_code == 0);
  CHECK(r.out.find("size          10.000 x 30.000 x 20.000 mm") != std::string::npos);
  r = run_mahost({"info", box, "--rotate", "x:90", "--rotate", "z:90"});  // in order
  CHECK(r.out.find("size          30.000 x 10.000 x 20.000 mm") != std::string::npos);
  r = run_mahost({"info", box, "--rotate", "1,1,0:180"});  // swaps x and y, turns z over
  CHECK(r.out.find("size          20.000 x 10.000 x 30.000 mm") != std::string::npos);

  r = run_mahost({"info", t, "--orient", "auto"});
  REQUIRE(r.exit_code == 0);
  CHECK(r.out.find(" x 10.000 mm\n") != std::string::npos);  // on its front or back
  CHECK(r.out.find("overhangs     ~0 mm^3 of support under walls leaning past 50 deg") != std::string::npos);
  // As given: the wings' undersides, 2 x 20 x 10 mm^2, 20 mm up, costed as the stock profile
  // lays support there: 0.2 mm of air, 0.4 mm of interface at 80%, then lines of 0.45 mm
  // beads 2.5 mm apart: 400 (0.4 0.8 + 19.4 0.45 / 2.5) = 1524.8 mm^3.
  CHECK(r.out.find("support material ~0 mm^3 against 1525 mm^3 as given, 10.0 mm tall "
                    "against 25.0 mm") != std::string::npos);
  // Sliced the same way: nothing to support.
  const auto sliced = run_mahost({"slice", t, "-o", dir + "/tee.gcode", "--orient", "auto", "--no-raft"});
  REQUIRE(sliced.exit_code == 0);
  CHECK(sliced.err.find("--orient auto: resting on the face") != std::string::npos);
  CHECK(read_file(dir + "/tee.gcode").find(";TYPE:SUPPORT") == std::string::npos);

  for (const std::string bad : {"q:90", "x90", "0,0,0:90", "x:ninety", "1,2:5"}) {
    CAPTURE(bad);
    r = run_mahost({"info", box, "--rotate", bad});
    CHECK(r.exit_code == 2);
    CHECK(r.err.starts_with("mahost: --rotate '" + bad + "': needs AXIS:DEGREES"));
  }
  r = run_mahost({"info", box, "--orient", "sideways"});
  CHECK(r.exit_code == 2);
}

TEST_CASE("dry_run_reports_the_unsupported_extrusion") {
  const std::string dir = test_support::scratch_dir("support_dry_run");
  const std::string stl = dir + "/tee.stl";
  geometry::write_stl_binary(stl, tee());
  auto r = run_mahost({"print", stl, "--dry-run", "--no-raft", "--support", "everywhere"});
  REQUIRE(r.exit_code == 0);
  std::size_t at = r.out.find("unsupported extrusion: ");
  REQUIRE(at != std::string::npos);
  CHECK(std::stod(r.out.substr(at + 23)) <= 1.0);
  CHECK(r.out.find(" m (", at) != std::string::npos);
  r = run_mahost({"print", stl, "--dry-run", "--no-raft", "--support", "none"});
  REQUIRE(r.exit_code == 0);
  at = r.out.find("unsupported extrusion: ");
  REQUIRE(at != std::string::npos);
  CHECK(std::stod(r.out.substr(at + 23)) > 800);
  CHECK(r.out.find("in the open") != std::string::npos);
  CHECK(r.out.find("  the first at layer ") != std::string::npos);
}

TEST_CASE("support_options_are_checked_and_listed_in_the_help") {
  const std::string dir = test_support::scratch_dir("support_options");
  const std::string stl = dir + "/cube.stl";
  geometry::write_stl_binary(stl, solids::cube(10).mesh);
  for (const std::vector<std::string>& args :
       {std::vector<std::string>{"--support", "sometimes"}, {"--overhang-angle", "95"},
        {"--brim", "-1"}, {"--raft", "--no-raft"}, {"--support-pattern", "honeycomb"}}) {
    std::vector<std::string> all{"slice", stl, "-o", dir + "/c.gcode"};
    all.insert(all.end(), args.begin(), args.end());
    const auto r = run_mahost(all);
    CAPTURE(args.front());
    CHECK(r.exit_code == 2);
    CHECK(r.err.starts_with("mahost: "));
  }
  const auto help = run_mahost({"slice", "--help"});
  for (const std::string option : {"--support", "--overhang-angle", "--support-xy-gap",
                                   "--support-top-distance", "--support-bottom-distance",
                                   "--support-interface-thickness", "--support-pattern",
                                   "--support-spacing", "--support-enforcer", "--support-blocker",
                                   "--bridge-length", "--brim", "--raft", "--no-raft", "--rotate",
                                   "--orient"}) {
    CAPTURE(option);
    CHECK(help.out.find(option + " ") != std::string::npos);
  }
}

}  // namespace support_cli_test
