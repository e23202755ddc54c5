// PrusaSlicer's macro language as its PlaceholderParser evaluates it: each expected text is what
// PrusaSlicer 2.5 prints for the same template and values (its arithmetic on integers and reals,
// its number formatting, its if/elsif/else, legacy [placeholders]), and every construct mahost
// does not take, or a name it does not know, is refused naming the placeholder and its line.
#include <string>

#include <doctest/doctest.h>

#include "printer/error.h"
#include "printer/prusa_macro.h"

namespace prusa_macro_test {

using namespace printer;

namespace {

MacroVariables variables() {
  MacroVariables v;
  v["first_layer_temperature"] = macro_vector({215LL});
  v["first_layer_bed_temperature"] = macro_vector({60LL});
  v["nozzle_diameter"] = macro_vector({0.4});
  v["layer_height"] = macro_scalar(0.2);
  v["max_print_height"] = macro_scalar(250.0);
  v["max_layer_z"] = macro_scalar(20.0);
  v["z_offset"] = macro_scalar(0.0);
  v["travel_speed"] = macro_scalar(150.0);
  v["print_bed_max"] = macro_vector({228.0, 228.0});
  v["printer_model"] = macro_scalar(std::string("MK3S"));
  v["printer_notes"] = macro_scalar(std::string("Don't remove\nPRINTER_VENDOR_PRUSA3D\nPRINTER_MODEL_MK3"));
  v["print_settings_id"] = macro_scalar(std::string("0.15mm QUALITY @MK3"));
  v["filament_type"] = macro_vector({std::string("PLA")});
  v["initial_tool"] = macro_scalar(0LL);
  v["has_wipe_tower"] = macro_scalar(false);
  v["total_layer_count"] = macro_scalar(100LL);
  return v;
}

std::string expand(const std::string& text) { return expand_prusa_macro(text, variables(), "test"); }

std::string refusal(const std::string& text) {
  try {
    expand(text);
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("legacy_placeholders_give_the_current_extruders_element") {
  CHECK(expand("M104 S[first_layer_temperature] ; t") == "M104 S215 ; t");
  CHECK(expand("M862.1 P[nozzle_diameter]") == "M862.1 P0.4");
  CHECK(expand("[first_layer_temperature_0] [first_layer_temperature[initial_tool]]") == "215 215");
  CHECK(expand("M862.3 P \"[printer_model]\"") == "M862.3 P \"MK3S\"");
  CHECK(expand("[layer_height]") == "0.2");
}

TEST_CASE("arithmetic_follows_integers_and_reals_as_prusaslicer_does") {
  CHECK(expand("{2 + 3 * 4}") == "14");
  CHECK(expand("{7 / 2}") == "3");        // two integers: integer division
  CHECK(expand("{7.0 / 2}") == "3.5");
  CHECK(expand("{7 % 3}") == "1");
  CHECK(expand("{0.1 + 0.2}") == "0.3");  // six significant digits, no trailing zeros
  CHECK(expand("{first_layer_temperature[0] * 0.791}") == "170.065");
  CHECK(expand("{first_layer_temperature[0] - 60}") == "155");
  CHECK(expand("{travel_speed*60}") == "9000");
  CHECK(expand("{print_bed_max[1]*0.8}") == "182.4");
  CHECK(expand("{z_offset+min(max_layer_z+2, max_print_height)}") == "22");
  CHECK(expand("{max(first_layer_bed_temperature[0] - 5, 50)}") == "55");
  CHECK(expand("{-3 + +2}") == "-1");
  CHECK(expand("{int(2.7)} {round(2.5)} {int(-2.7)}") == "2 3 -2");
  CHECK(expand("{1e-5 * 1.0}") == "1e-05");
}

TEST_CASE("strings_join_with_plus_and_compare") {
  CHECK(expand("{\"\" + ((filament_type[0]==\"FLEX\") ? 1 : ((filament_type[0]==\"PVA\") ? 2 : 0))}") == "0");
  CHECK(expand("{\"T\" + 1 + \"/\" + 2.5}") == "T1/2.5");
  CHECK(expand("{\"a\\\"b\\\\c\"}") == "a\"b\\c");
  CHECK(expand("{printer_model == \"MK3S\"} {printer_model != \"MK3S\"} {\"a\" < \"b\"}") == "true false true");
}

TEST_CASE("comparisons_of_reals_allow_rounding") {
  CHECK(expand("{nozzle_diameter[0]==0.4}") == "true");
  CHECK(expand("{0.1 + 0.2 == 0.3}") == "true");
  CHECK(expand("{layer_height<0.075} {layer_height>=0.2} {layer_height<=0.19} {3 <> 4}") ==
        "false true false true");
}

TEST_CASE("if_elsif_else_takes_the_first_true_branch") {
  CHECK(expand("M221 S{if layer_height<0.075}100{else}95{endif}") == "M221 S95");
  const std::string chain = "{if max_layer_z > 30}a{elsif max_layer_z > 10}b{elsif true}c{else}d{endif}";
  CHECK(expand(chain) == "b");
  CHECK(expand("{if has_wipe_tower}x{endif}y") == "y");
  CHECK(expand("{if not has_wipe_tower}x{endif}") == "x");
  CHECK(expand("{if ! has_wipe_tower and (true or false)}x{endif}") == "x");
  // Nested, across lines, with placeholders inside the branches.
  CHECK(expand("{if max_layer_z < max_print_height}G1 Z{z_offset+min(max_layer_z+2, max_print_height)}"
               "{if layer_height > 0.1} ; up{endif}\n{endif}M84") == "G1 Z22 ; up\nM84");
}

TEST_CASE("a_branch_not_taken_may_name_anything") {
  CHECK(expand("{if has_wipe_tower}[wipe_tower_x] {1/0}{endif}ok") == "ok");
  CHECK(expand("{if false}{unknown_thing + 1}{else}{2}{endif}") == "2");
  CHECK(expand("{has_wipe_tower ? unknown_thing : 3}") == "3");
}

TEST_CASE("regular_expressions_match_the_whole_string_and_dots_cross_lines") {
  CHECK(expand("{if print_settings_id=~/.*(DETAIL @MK3|QUALITY @MK3).*/}M907 E430{endif}") == "M907 E430");
  CHECK(expand("{print_settings_id=~/QUALITY/}") == "false");  // the whole string must match
  CHECK(expand("{printer_notes=~/.*PRINTER_MODEL_MK3.*/}") == "true");  // printer_notes has line breaks
  CHECK(expand("{printer_model!~/MK2.*/}") == "true");
  CHECK(expand("{one_of(printer_model, \"MK2\", /MK3.*/)} {one_of(printer_model, \"MK2\")}") == "true false");
}

TEST_CASE("digits_pad_numbers") {
  CHECK(expand("{digits(5, 3)}|{zdigits(5, 3)}|{digits(3.14159, 6, 2)}|{zdigits(3.14159, 6, 2)}") ==
        "  5|005|  3.14|003.14");
}

TEST_CASE("a_stray_closing_brace_is_dropped") {
  CHECK(expand("G1 X1 } Y2") == "G1 X1  Y2");
}

TEST_CASE("unknown_names_and_bad_syntax_are_refused_with_their_line") {
  CHECK(refusal("G28\nM109 [filament_notes]") ==
        "test: line 2: [filament_notes]: 'filament_notes' is not a value mahost knows");
  CHECK(refusal("G28\n\nM104 S{if true}{temp}{endif}") ==
        "test: line 3: {temp}: 'temp' is not a value mahost knows");
  CHECK(refusal("{first_layer_temperature}").find("is a vector: name one element") != std::string::npos);
  CHECK(refusal("{layer_height[0]}").find("is not a vector") != std::string::npos);
  CHECK(refusal("{if layer_height}x{endif}").find("not a boolean") != std::string::npos);
  CHECK(refusal("{1 + \"a\" * 2}").find("needs numbers") != std::string::npos);
  CHECK(refusal("{1 / 0}").find("division by zero") != std::string::npos);
  CHECK(refusal("{if true}x").find("without {endif}") != std::string::npos);
  CHECK(refusal("x{endif}").find("without an {if}") != std::string::npos);
  CHECK(refusal("{layer_height").find("never closed") != std::string::npos);
  CHECK(refusal("[").find("expected a variable name") != std::string::npos);
  CHECK(refusal("{local x = 1}").find("not supported") != std::string::npos);
  CHECK(refusal("{x = 1}").find("not a value mahost knows") != std::string::npos);
  CHECK(refusal("{layer_height = 1}").find("assignments are not supported") != std::string::npos);
  CHECK(refusal("{random(1, 2)}").find("random() is not supported") != std::string::npos);
  CHECK(refusal("{if true then 1; endif}").find("'if ... then' blocks are not supported") != std::string::npos);
  CHECK(refusal("{printer_model =~ /(/}").find("does not compile") != std::string::npos);
}

TEST_CASE("elements_past_the_known_ones_say_why") {
  MacroVariables v = variables();
  MacroVariable types = macro_vector({std::string("PLA"), std::string("PLA")});
  types.known = 1;
  types.unknown_why = "only the first is known";
  v["filament_type"] = types;
  CHECK(expand_prusa_macro("{filament_type[0]} {filament_type[5]}", v, "t") == "PLA PLA");  // past the end: element 0
  try {
    expand_prusa_macro("{filament_type[1]}", v, "t");
    FAIL("filament_type[1] was evaluated");
  } catch (const ConfigError& e) {
    CHECK(std::string(e.what()) == "t: line 1: {filament_type[1]}: filament_type[1]: only the first is known");
  }
}

}  // namespace prusa_macro_test
