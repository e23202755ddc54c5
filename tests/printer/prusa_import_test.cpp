// PrusaSlicer's printers as mahost profiles: each setting where mahost keeps it (percents of
// what they refer to, PrusaSlicer's defaults where a profile is silent, round beds of deltas),
// the print and filament profile found as PrusaSlicer finds them, and every printer mahost
// cannot drive refused with why.
#include <algorithm>
#include <string>

#include <doctest/doctest.h>

#include "printer/error.h"
#include "printer/profile.h"
#include "printer/prusa_import.h"

namespace prusa_import_test {

using namespace printer;

namespace {

const std::string kBundle = R"([vendor]
name = Acme

[printer_model:CUBE]
name = Acme Cube
[printer_model:DELTA]
name = Acme Delta
[printer_model:OTHER]
name = Acme Other

[printer:*common*]
printer_technology = FFF
gcode_flavor = marlin2
use_relative_e_distances = 1
nozzle_diameter = 0.4
min_layer_height = 0.08
max_layer_height = 0.32
machine_max_feedrate_e = 8000,120
machine_max_acceleration_extruding = 1000,800
retract_length = 5
retract_speed = 45
deretract_speed = 0 # 0: the retract speed
retract_lift = 0.2
max_print_height = 250
printer_notes = PRINTER_VENDOR_ACME
start_gcode = M862.3 P "[printer_model]"\nM140 S[first_layer_bed_temperature]\nM104 S{first_layer_temperature[0]}\nG28 ; home\n{if print_settings_id=~/.*FINE.*/}M907 E430{endif}
end_gcode = G1 Z{min(max_layer_z+10, max_print_height)}\nM84
default_print_profile = 0.20mm NORMAL @ACME
default_filament_profile = "Acme PLA"

[printer:Acme Cube]
inherits = *common*
printer_model = CUBE
bed_shape = 3x3,228x3,228x228,3x228

[printer:Acme Delta]
inherits = *common*
printer_model = DELTA
gcode_flavor = reprapfirmware
bed_shape = 100x0,70.7107x70.7107,0x100,-70.7107x70.7107,-100x0,-70.7107x-70.7107,0x-100,70.7107x-70.7107
default_print_profile = 0.15mm FINE ACME

[printer:Acme Cube Resin]
inherits = *common*
printer_model = CUBE
printer_technology = SLA

[printer:Acme Cube Offset]
inherits = Acme Cube
z_offset = -0.1

[printer:Acme Cube X3G]
inherits = Acme Cube
gcode_flavor = sailfish

[printer:Acme Cube Notes]
inherits = Acme Cube
start_gcode = G28\nM117 [filament_notes]

[printer:Acme Cube Duo]
inherits = Acme Cube
nozzle_diameter = 0.4,0.4
start_gcode = T0 ; {filament_type[0]}\nM104 T1 S{first_layer_temperature[1]}

[printer:Acme Cube Lonely]
inherits = Acme Cube
printer_model = OTHER
default_print_profile = gone

[print:*common*]
perimeters = 2
perimeter_speed = 60
external_perimeter_speed = 50%
infill_speed = 100
solid_infill_speed = 80%
top_solid_infill_speed = 50%
travel_speed = 200
first_layer_height = 0.2
first_layer_extrusion_width = 0.42
extrusion_width = 0.45
fill_density = 15%
fill_pattern = gyroid
support_material_xy_spacing = 50%

[print:0.20mm NORMAL @ACME]
inherits = *common*
layer_height = 0.2
compatible_printers_condition = printer_model=="CUBE" and nozzle_diameter[0]==0.4

[print:0.15mm FINE @ACME]
inherits = *common*
layer_height = 0.15
compatible_printers_condition = printer_notes=~/.*ACME.*/

[filament:Acme PLA]
filament_type = PLA
temperature = 205
first_layer_temperature = 210
bed_temperature = 60
first_layer_bed_temperature = 65
fan_always_on = 1
min_fan_speed = 80
disable_fan_first_layers = 2
filament_density = 1.24
)";

const ImportedPrinter& find(const PrusaImport& result, const std::string& name) {
  const auto it = std::find_if(result.printers.begin(), result.printers.end(),
                               [&](const ImportedPrinter& p) { return p.printer.name == name; });
  REQUIRE(it != result.printers.end());
  return *it;
}

std::string refusal(const PrusaImport& result, const std::string& name) {
  for (const ImportRefusal& r : result.refused) {
    if (r.printer == name) return r.reason;
  }
  return "";
}

Profiles profiles_of(const ImportedPrinter& p) {
  return {parse_printer_profile(p.printer.toml, p.printer.stem), parse_material_profile(p.material.toml, p.material.stem)};
}

}  // namespace

TEST_CASE("a_vendor_printer_becomes_a_printer_and_a_material_profile") {
  const PrusaImport result = import_prusa_ini(kBundle, "acme.ini");
  const ImportedPrinter& cube = find(result, "Acme Cube");
  CHECK(cube.printer.stem == "acme-cube");
  CHECK(cube.material.stem == "acme-pla");
  CHECK(cube.print_profile == "0.20mm NORMAL @ACME");
  const Profiles p = profiles_of(cube);
  const PrinterProfile& printer = p.printer;
  CHECK(printer.name == "Acme Cube");
  CHECK(printer.default_material == "Acme PLA");
  CHECK(printer.firmware == Firmware::marlin);
  CHECK(printer.bed_x == 225);
  CHECK(printer.bed_y == 225);
  CHECK(printer.bed_origin_x == 3);
  CHECK(printer.bed_origin_y == 3);
  CHECK(!printer.round_bed);
  CHECK(printer.bed_z == 250);
  CHECK(printer.relative_e);
  CHECK(printer.layer.min == 0.08);
  CHECK(printer.layer.max == 0.32);
  CHECK(printer.layer.step == 0.01);
  CHECK(printer.layer.default_thickness == 0.2);
  CHECK(printer.first_layer_height == 0.2);
  CHECK(printer.first_layer_width == 0.42);
  CHECK(printer.extrusion_width == 0.45);
  // Percents of what they refer to: external perimeters of perimeters, solid of sparse infill,
  // top of solid.
  CHECK(printer.speed.inner_wall == 60);
  CHECK(printer.speed.outer_wall == 30);
  CHECK(printer.speed.sparse_infill == 100);
  CHECK(printer.speed.solid_infill == 80);
  CHECK(printer.speed.top_skin == 40);
  CHECK(printer.speed.travel == 200);
  CHECK(printer.first_layer_speed == 30);  // PrusaSlicer's default
  CHECK(printer.motion.max_speed[3] == 2000);  // 8000 mm/s, past mahost's largest
  CHECK(printer.motion.print_acceleration == 1000);
  CHECK(printer.retraction.length == 5);
  CHECK(printer.retraction.prime_speed == 45);  // deretract 0: the retract speed
  CHECK(printer.retraction.z_hop == 0.2);
  CHECK(printer.print.perimeters == 2);
  CHECK(printer.print.infill_density == 15);
  CHECK(printer.print.infill_pattern == "grid");
  CHECK(printer.support.xy_gap == doctest::Approx(0.225));
  CHECK(printer.gcode_syntax == GcodeSyntax::prusaslicer);
  CHECK(printer.gcode_constants.count("printer_model"));
  CHECK(printer.gcode_constants.count("print_settings_id"));
  const MaterialProfile& m = p.material;
  CHECK(m.name == "Acme PLA");
  CHECK(m.type == "PLA");
  CHECK(m.nozzle_temperature == 205);
  CHECK(m.first_layer_nozzle_temperature == 210);
  CHECK(m.first_layer_bed_temperature == 65);
  CHECK(m.fan_speed == 80);
  CHECK(m.fan_start_layer == 2);
  // The start G-code as PrusaSlicer writes it for this printer and filament.
  PlaceholderValues values;
  values.max_layer_z = 20;
  CHECK(expand_placeholders(printer.start_gcode, p, values, "gcode.start") ==
        "M862.3 P \"CUBE\"\nM140 S65\nM104 S210\nG28 ; home\n");
  CHECK(expand_placeholders(printer.end_gcode, p, values, "gcode.end") == "G1 Z30\nM84");
}

TEST_CASE("a_delta_has_a_round_bed_around_the_origin_and_its_compatible_print_profile") {
  const PrusaImport result = import_prusa_ini(kBundle, "acme.ini");
  const ImportedPrinter& delta = find(result, "Acme Delta");
  // "0.15mm FINE ACME" is the print's name before it took an '@'; PrusaSlicer finds it so.
  CHECK(delta.print_profile == "0.15mm FINE @ACME");
  const Profiles p = profiles_of(delta);
  CHECK(p.printer.round_bed);
  CHECK(p.printer.bed_x == 200);
  CHECK(p.printer.bed_origin_x == -100);
  CHECK(p.printer.bed_origin_y == -100);
  CHECK(bed_centre_x(p.printer) == 0);
  CHECK(on_bed(p.printer, 70, 70));
  CHECK(!on_bed(p.printer, 80, 80));
  CHECK(p.printer.firmware == Firmware::marlin);  // RepRapFirmware takes Marlin's G-code
  CHECK(p.printer.layer.default_thickness == 0.15);
  CHECK(expand_placeholders(p.printer.start_gcode, p, {}, "gcode.start").ends_with("G28 ; home\nM907 E430"));
  // A print profile named nowhere: the first one the printer is compatible with.
  CHECK(find(result, "Acme Cube Lonely").print_profile == "0.15mm FINE @ACME");
}

TEST_CASE("printers_mahost_cannot_drive_are_refused_with_why") {
  const PrusaImport result = import_prusa_ini(kBundle, "acme.ini");
  CHECK(result.printers.size() == 3);
  CHECK(result.refused.size() == 5);
  CHECK(refusal(result, "Acme Cube Resin") == "printer_technology SLA: mahost prints with filament (FFF) only");
  CHECK(refusal(result, "Acme Cube Offset") == "z_offset = -0.1 mm: mahost moves Z as planned, with no offset");
  CHECK(refusal(result, "Acme Cube X3G").starts_with("gcode_flavor sailfish: mahost writes G-code for Marlin"));
  CHECK(refusal(result, "Acme Cube Notes") ==
        "gcode.start: line 2: [filament_notes]: 'filament_notes' is not a value mahost knows; mahost "
        "evaluates PrusaSlicer's placeholders for the printer, the material and the slice, and the "
        "printer's gcode.constants");
  CHECK(refusal(result, "Acme Cube Duo") ==
        "gcode.start: line 2: {first_layer_temperature[1]}: first_layer_temperature[1]: mahost "
        "prints with the first extruder and knows only its material");
}

TEST_CASE("one_printer_by_name_and_a_name_the_file_lacks") {
  const PrusaImport result = import_prusa_ini(kBundle, "acme.ini", {"Acme Delta"});
  REQUIRE(result.printers.size() == 1);
  CHECK(result.refused.empty());
  try {
    import_prusa_ini(kBundle, "acme.ini", {"cube"});
    FAIL("a missing printer was accepted");
  } catch (const ConfigError& e) {
    CHECK(std::string(e.what()).starts_with(
        "acme.ini has no printer 'cube'; did you mean: Acme Cube; Acme Cube Resin; Acme Cube Offset"));
  }
}

TEST_CASE("an_exported_config_ini_imports_its_one_printer") {
  const std::string config =
      "# generated by PrusaSlicer 2.5.0+linux-x64-GTK3\n"
      "bed_shape = 0x0,250x0,250x210,0x210\nmax_print_height = 210\nnozzle_diameter = 0.6\n"
      "layer_height = 0.3\nfirst_layer_height = 0.3\nmax_layer_height = 0.45\n"
      "gcode_flavor = marlin\nstart_gcode = G28\\nM109 S[first_layer_temperature]\n"
      "printer_settings_id = My MK3S\nprint_settings_id = 0.30mm DRAFT\n"
      "filament_settings_id = \"My PETG\"\nfilament_type = PETG\ntemperature = 240\n"
      "first_layer_temperature = 235\nbed_temperature = 90\nfirst_layer_bed_temperature = 85\n";
  const PrusaImport result = import_prusa_ini(config, "config.ini");
  REQUIRE(result.printers.size() == 1);
  const Profiles p = profiles_of(result.printers[0]);
  CHECK(p.printer.name == "My MK3S");
  CHECK(p.printer.nozzle_diameter == 0.6);
  CHECK(p.printer.bed_y == 210);
  CHECK(p.printer.extrusion_width == doctest::Approx(0.675));  // 1.125 x the nozzle
  CHECK(p.material.name == "My PETG");
  CHECK(p.material.bed_temperature == 90);
  CHECK(expand_placeholders(p.printer.start_gcode, p, {}, "gcode.start") == "G28\nM109 S235");
}

}  // namespace prusa_import_test
