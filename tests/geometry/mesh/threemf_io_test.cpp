// 3MF files read as their build places them, against closed forms: cubes of known sides moved,
// turned, mirrored and scaled by the items' and components' transforms, in every unit; a 3MF
// that PrusaSlicer itself wrote (when prusa-slicer is installed); and damaged files refused in
// one line.
#include <zip.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <doctest/doctest.h>
#include <fmt/core.h>

#include "geometry/core/error.h"
#include "geometry/mesh/model_io.h"
#include "geometry/mesh/repair.h"
#include "geometry/mesh/stl_io.h"
#include "geometry/mesh/threemf_io.h"
#include "support/run_command.h"
#include "support/solids.h"

namespace threemf_io_test {

using namespace geometry;

namespace {

// A zip archive of the given parts (name, bytes), in memory.
std::string zip_of(const std::vector<std::pair<std::string, std::string>>& parts) {
  zip_error_t error;
  zip_error_init(&error);
  zip_source_t* buffer = zip_source_buffer_create(nullptr, 0, 0, &error);
  REQUIRE(buffer);
  zip_source_keep(buffer);
  zip_t* zip = zip_open_from_source(buffer, ZIP_TRUNCATE, &error);
  REQUIRE(zip);
  for (const auto& [name, bytes] : parts) {
    zip_source_t* part = zip_source_buffer(zip, bytes.data(), bytes.size(), 0);
    REQUIRE(zip_file_add(zip, name.c_str(), part, ZIP_FL_OVERWRITE) >= 0);
  }
  REQUIRE(zip_close(zip) == 0);
  zip_source_open(buffer);
  zip_source_seek(buffer, 0, SEEK_END);
  const zip_int64_t size = zip_source_tell(buffer);
  zip_source_seek(buffer, 0, SEEK_SET);
  std::string out(static_cast<std::size_t>(size), '\0');
  zip_source_read(buffer, out.data(), out.size());
  zip_source_close(buffer);
  zip_source_free(buffer);
  return out;
}

const std::string kRels =
    R"(<?xml version="1.0" encoding="UTF-8"?>
<Relationships xmlns="http://schemas.openxmlformats.org/package/2006/relationships">
 <Relationship Target="/3D/3dmodel.model" Id="rel0" Type="http://schemas.microsoft.com/3dmanufacturing/2013/01/3dmodel"/>
</Relationships>)";

// A cube's <mesh>: side `side`, corner at the origin, outward.
std::string cube_mesh(double side) {
  const solids::Solid cube = solids::cube(side);
  std::string xml = "<mesh><vertices>";
  for (const Vec3& v : cube.mesh.vertices) xml += fmt::format("<vertex x=\"{}\" y=\"{}\" z=\"{}\"/>", v.x, v.y, v.z);
  xml += "</vertices><triangles>";
  for (const auto& f : cube.mesh.faces) xml += fmt::format("<triangle v1=\"{}\" v2=\"{}\" v3=\"{}\"/>", f[0], f[1], f[2]);
  return xml + "</triangles></mesh>";
}

std::string model(const std::string& resources, const std::string& build, const std::string& unit = "millimeter") {
  return fmt::format(
      R"(<?xml version="1.0" encoding="UTF-8"?>
<model unit="{}" xmlns="http://schemas.microsoft.com/3dmanufacturing/core/2015/02"
       xmlns:p="http://schemas.microsoft.com/3dmanufacturing/production/2015/06">
<resources>{}</resources><build>{}</build></model>)",
      unit, resources, build);
}

std::string threemf(const std::string& model_xml, std::vector<std::pair<std::string, std::string>> extra = {}) {
  extra.insert(extra.begin(), {{"_rels/.rels", kRels}, {"3D/3dmodel.model", model_xml}});
  return zip_of(extra);
}

struct Figures {
  double volume = 0;
  Box3 box;
  std::size_t reoriented = 0;
  bool closed = false;
};

Figures figures(const std::vector<Triangle>& triangles) {
  RepairReport report;
  const Mesh mesh = repair(triangles, &report);
  return {report.volume, bounding_box(mesh), report.faces_reoriented, report.closed};
}

std::string refusal(const std::string& bytes) {
  try {
    read_3mf_bytes(bytes, "part.3mf");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("two_objects_are_placed_by_their_build_items_transforms") {
  // A 10 mm cube moved by (30, 5, 0); a 20 mm cube turned 90 degrees about z (x' = -y, y' = x)
  // and moved by (0, 0, 2), so it spans x -20..0, y 0..20, z 2..22.
  const std::string xml = model(
      "<object id=\"1\" type=\"model\">" + cube_mesh(10) + "</object>"
      "<object id=\"2\" type=\"model\">" + cube_mesh(20) + "</object>",
      "<item objectid=\"1\" transform=\"1 0 0 0 1 0 0 0 1 30 5 0\"/>"
      "<item objectid=\"2\" transform=\"0 1 0 -1 0 0 0 0 1 0 0 2\"/>");
  const ThreeMfModel m = read_3mf_bytes(threemf(xml), "two.3mf");
  CHECK(m.items == 2);
  CHECK(m.unit == "millimeter");
  REQUIRE(m.triangles.size() == 24);
  const Figures f = figures(m.triangles);
  CHECK(f.closed);
  CHECK(f.volume == doctest::Approx(1000 + 8000));
  CHECK(f.reoriented == 0);
  CHECK(f.box.min.x == doctest::Approx(-20));
  CHECK(f.box.max.x == doctest::Approx(40));
  CHECK(f.box.min.y == doctest::Approx(0));
  CHECK(f.box.max.y == doctest::Approx(20));
  CHECK(f.box.min.z == doctest::Approx(0));
  CHECK(f.box.max.z == doctest::Approx(22));
  // Each object where its item put it: the first cube's triangles alone.
  const Figures first = figures({m.triangles.begin(), m.triangles.begin() + 12});
  CHECK(first.box.min.x == doctest::Approx(30));
  CHECK(first.box.max.y == doctest::Approx(15));
}

TEST_CASE("components_nest_their_transforms_inside_the_items") {
  // Object 3 holds object 1 (a 10 mm cube) twice: as it is, and scaled by 2 and moved by
  // (20, 0, 0); the item moves the whole by (0, 0, 5). Volumes 1000 + 8000.
  const std::string xml = model(
      "<object id=\"1\">" + cube_mesh(10) + "</object>"
      "<object id=\"3\"><components><component objectid=\"1\"/>"
      "<component objectid=\"1\" transform=\"2 0 0 0 2 0 0 0 2 20 0 0\"/></components></object>",
      "<item objectid=\"3\" transform=\"1 0 0 0 1 0 0 0 1 0 0 5\"/>");
  const Figures f = figures(read_3mf_bytes(threemf(xml), "nested.3mf").triangles);
  CHECK(f.volume == doctest::Approx(9000));
  CHECK(f.box.max.x == doctest::Approx(40));
  CHECK(f.box.min.z == doctest::Approx(5));
  CHECK(f.box.max.z == doctest::Approx(25));
}

TEST_CASE("a_mirroring_transform_keeps_the_outside_out") {
  const std::string xml = model("<object id=\"1\">" + cube_mesh(10) + "</object>",
                                "<item objectid=\"1\" transform=\"-1 0 0 0 1 0 0 0 1 0 0 0\"/>");
  const Figures f = figures(read_3mf_bytes(threemf(xml), "mirror.3mf").triangles);
  CHECK(f.volume == doctest::Approx(1000));
  CHECK(f.reoriented == 0);  // the reader reversed each triangle; repair had nothing to turn
  CHECK(f.box.min.x == doctest::Approx(-10));
}

TEST_CASE("units_are_read_to_millimetres") {
  for (const auto& [unit, mm] : std::vector<std::pair<std::string, double>>{
           {"micron", 0.001}, {"millimeter", 1}, {"centimeter", 10}, {"inch", 25.4}, {"foot", 304.8}, {"meter", 1000}}) {
    CAPTURE(unit);
    const std::string xml = model("<object id=\"1\">" + cube_mesh(2) + "</object>", "<item objectid=\"1\"/>", unit);
    const Figures f = figures(read_3mf_bytes(threemf(xml), "units.3mf").triangles);
    CHECK(f.box.max.x == doctest::Approx(2 * mm));
    CHECK(f.volume == doctest::Approx(8 * mm * mm * mm));
  }
}

TEST_CASE("components_in_other_parts_are_read") {
  // The production extension: a component names the part its object is in (p:path).
  const std::string part = model("<object id=\"7\">" + cube_mesh(10) + "</object>", "");
  const std::string xml = model(
      "<object id=\"1\"><components><component p:path=\"/3D/Objects/cube.model\" objectid=\"7\" "
      "transform=\"1 0 0 0 1 0 0 0 1 5 5 0\"/></components></object>",
      "<item objectid=\"1\"/>");
  const Figures f = figures(read_3mf_bytes(threemf(xml, {{"3D/Objects/cube.model", part}}), "prod.3mf").triangles);
  CHECK(f.volume == doctest::Approx(1000));
  CHECK(f.box.min.x == doctest::Approx(5));
}

TEST_CASE("prusaslicer_modifiers_and_items_not_printed_are_left_out") {
  // One object whose mesh holds a 10 mm part (triangles 0-11) and a modifier volume (12-23), as
  // PrusaSlicer writes them, and an item PrusaSlicer marks not printable.
  std::string both = cube_mesh(10);
  const solids::Solid modifier = solids::box({2, 2, 2}, {4, 4, 4});
  std::string vertices, triangles;
  for (const Vec3& v : modifier.mesh.vertices) vertices += fmt::format("<vertex x=\"{}\" y=\"{}\" z=\"{}\"/>", v.x, v.y, v.z);
  for (const auto& f : modifier.mesh.faces) {
    triangles += fmt::format("<triangle v1=\"{}\" v2=\"{}\" v3=\"{}\"/>", f[0] + 8, f[1] + 8, f[2] + 8);
  }
  both.insert(both.find("</vertices>"), vertices);
  both.insert(both.find("</triangles>"), triangles);
  const std::string xml = model("<object id=\"1\">" + both + "</object><object id=\"2\">" + cube_mesh(30) + "</object>",
                                "<item objectid=\"1\" printable=\"1\"/><item objectid=\"2\" printable=\"0\"/>");
  const std::string config =
      R"(<?xml version="1.0" encoding="UTF-8"?><config><object id="1" instances_count="1">
<volume firstid="0" lastid="11"><metadata type="volume" key="volume_type" value="ModelPart"/></volume>
<volume firstid="12" lastid="23"><metadata type="volume" key="volume_type" value="ParameterModifier"/></volume>
</object></config>)";
  const ThreeMfModel m = read_3mf_bytes(threemf(xml, {{"Metadata/Slic3r_PE_model.config", config}}), "mod.3mf");
  CHECK(m.items == 1);
  CHECK(m.triangles.size() == 12);
  CHECK(figures(m.triangles).volume == doctest::Approx(1000));
  const std::string negative = config.substr(0, config.find("ParameterModifier")) + "NegativeVolume" +
                               config.substr(config.find("ParameterModifier") + 17);
  CHECK(refusal(threemf(xml, {{"Metadata/Slic3r_PE_model.config", negative}})).find(
            "part.3mf: object 1 has a negative volume") == 0);
}

TEST_CASE("damaged_files_are_refused_in_one_line") {
  CHECK(refusal("") == "part.3mf: empty file (0 bytes): not a 3MF model");
  CHECK(refusal("PK\3\4 not really a zip").find("part.3mf: not a 3MF file: the zip archive cannot be read") == 0);
  CHECK(refusal(zip_of({{"readme.txt", "hello"}})) ==
        "part.3mf: not a 3MF file: the archive has no 3D model part (/3D/3dmodel.model)");
  const std::string cube = "<object id=\"1\">" + cube_mesh(10) + "</object>";
  CHECK(refusal(threemf("<model><resources>")).find("part.3mf: /3D/3dmodel.model: not well-formed XML at byte") == 0);
  CHECK(refusal(threemf(model(cube, "<item objectid=\"9\"/>"))) == "part.3mf: /3D/3dmodel.model: no object with id 9");
  CHECK(refusal(threemf(model(cube, "<item objectid=\"1\"/>", "parsec"))).find("unknown unit 'parsec'") != std::string::npos);
  CHECK(refusal(threemf(model(cube, "<item objectid=\"1\" transform=\"1 0 0\"/>"))) ==
        "part.3mf: /3D/3dmodel.model: transform \"1 0 0\" is not 12 numbers");
  std::string bad_index = cube;
  bad_index.replace(bad_index.find("v1=\"0\""), 6, "v1=\"99\"");
  CHECK(refusal(threemf(model(bad_index, "<item objectid=\"1\"/>"))).find("v1=\"99\" is not a vertex (the mesh has 8)") !=
        std::string::npos);
  CHECK(refusal(threemf(model(cube, ""))) == "part.3mf: /3D/3dmodel.model: the build places no triangles: nothing to print");
  const std::string cycle = model("<object id=\"1\"><components><component objectid=\"1\"/></components></object>",
                                  "<item objectid=\"1\"/>");
  CHECK(refusal(threemf(cycle)).find("more than 32 deep (a cycle?)") != std::string::npos);
}

TEST_CASE("a_3mf_prusaslicer_wrote_with_a_transform_reads_to_its_closed_form") {
  // prusa-slicer scales a 20 mm cube by half, turns it 30 degrees about z and centres it at
  // (100, 80): a 10 mm cube, 1000 mm^3, its centre there, its box sqrt(2) cos(15 deg) x 10
  // wide. PrusaSlicer keeps the scale and turn in the item's transform.
  if (std::system("command -v prusa-slicer >/dev/null 2>&1") != 0) {
    MESSAGE("prusa-slicer is not installed (scripts/setup installs it): skipped");
    return;
  }
  const std::string dir = test_support::scratch_dir("threemf_prusaslicer");
  write_stl_binary(dir + "/cube.stl", solids::cube(20).mesh);
  const auto run = test_support::run_command({"prusa-slicer", "--export-3mf", "--scale", "0.5", "--rotate", "30",
                                              "--center", "100,80", "-o", dir + "/cube.3mf", dir + "/cube.stl"});
  REQUIRE(run.exit_code == 0);
  const ModelFile file = read_model(dir + "/cube.3mf");
  CHECK(file.format == ModelFormat::threemf);
  CHECK(file.units_recorded);
  CHECK(file.objects == 1);
  const Figures f = figures(file.triangles);
  CHECK(f.closed);
  CHECK(f.volume == doctest::Approx(1000).epsilon(1e-6));
  const double half = 5 * std::sqrt(2.0) * std::cos(15 * M_PI / 180);
  CHECK((f.box.max.x - f.box.min.x) / 2 == doctest::Approx(half).epsilon(1e-5));
  CHECK((f.box.min.x + f.box.max.x) / 2 == doctest::Approx(100).epsilon(1e-5));
  CHECK((f.box.min.y + f.box.max.y) / 2 == doctest::Approx(80).epsilon(1e-5));
  CHECK(f.box.min.z == doctest::Approx(0).epsilon(1e-6));
  CHECK(f.box.max.z == doctest::Approx(10).epsilon(1e-6));
  // Two models arranged on one plate (--merge): two objects, apart, their volumes summed.
  write_stl_binary(dir + "/small.stl", solids::cube(5).mesh);
  REQUIRE(test_support::run_command({"prusa-slicer", "--export-3mf", "--merge", "-o", dir + "/two.3mf",
                                     dir + "/cube.stl", dir + "/small.stl"}).exit_code == 0);
  const ModelFile two = read_model(dir + "/two.3mf");
  CHECK(two.objects == 2);
  const Figures both = figures(two.triangles);
  CHECK(both.volume == doctest::Approx(8000 + 125).epsilon(1e-6));
  CHECK(both.box.max.z == doctest::Approx(20).epsilon(1e-6));
  // Side by side, not one inside the other: the box holds both footprints.
  CHECK((both.box.max.x - both.box.min.x) * (both.box.max.y - both.box.min.y) >= 400 + 25);
}

}  // namespace threemf_io_test
