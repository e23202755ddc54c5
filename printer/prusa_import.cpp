// PrusaSlicer's printers as mahost profiles; see prusa_import.h.
#include "printer/prusa_import.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <map>
#include <optional>
#include <set>

#include <fmt/core.h>
#include <fmt/format.h>

#include "geometry/mesh/file_bytes.h"
#include "printer/error.h"
#include "printer/profile.h"
#include "printer/prusa_ini.h"
#include "printer/prusa_macro.h"
#include "printer/prusa_variables.h"

namespace printer {
namespace {

// PrusaSlicer's defaults (src/libslic3r/PrintConfig.cpp, as `prusa-slicer --help-fff` lists
// them) for the keys read here: what a profile that leaves a key out means.
const std::map<std::string, std::string, std::less<>>& prusa_defaults() {
  static const std::map<std::string, std::string, std::less<>> defaults = {
      {"bed_shape", "0x0,200x0,200x200,0x200"}, {"max_print_height", "200"},
      {"nozzle_diameter", "0.4"}, {"filament_diameter", "1.75"}, {"extrusion_width", "0"},
      {"perimeter_extrusion_width", "0"}, {"first_layer_extrusion_width", "200%"},
      {"use_relative_e_distances", "0"}, {"min_layer_height", "0.07"}, {"max_layer_height", "0"},
      {"layer_height", "0.3"}, {"first_layer_height", "0.35"}, {"first_layer_speed", "30"},
      {"machine_max_feedrate_x", "500,200"}, {"machine_max_feedrate_y", "500,200"},
      {"machine_max_feedrate_z", "12,12"}, {"machine_max_feedrate_e", "120,120"},
      {"machine_max_acceleration_x", "9000,1000"}, {"machine_max_acceleration_y", "9000,1000"},
      {"machine_max_acceleration_z", "500,200"}, {"machine_max_acceleration_e", "10000,5000"},
      {"machine_max_acceleration_extruding", "1500,1250"},
      {"machine_max_acceleration_travel", "1500,1250"},
      {"machine_max_acceleration_retracting", "1500,1250"}, {"machine_min_extruding_rate", "0,0"},
      {"perimeter_speed", "60"}, {"external_perimeter_speed", "50%"}, {"gap_fill_speed", "20"},
      {"infill_speed", "80"}, {"solid_infill_speed", "20"}, {"top_solid_infill_speed", "15"},
      {"support_material_speed", "60"}, {"support_material_interface_speed", "100%"},
      {"bridge_speed", "60"}, {"travel_speed", "130"}, {"travel_speed_z", "0"},
      {"max_print_speed", "80"}, {"retract_length", "2"}, {"retract_speed", "40"},
      {"deretract_speed", "0"}, {"retract_before_travel", "2"}, {"retract_lift", "0"},
      {"perimeters", "3"}, {"fill_density", "20%"}, {"fill_pattern", "stars"},
      {"top_solid_layers", "3"}, {"bottom_solid_layers", "3"}, {"top_solid_min_thickness", "0"},
      {"bottom_solid_min_thickness", "0"}, {"skirts", "1"}, {"skirt_distance", "6"},
      {"seam_position", "aligned"}, {"support_material", "0"},
      {"support_material_buildplate_only", "0"}, {"support_material_contact_distance", "0.2"},
      {"support_material_bottom_contact_distance", "0"}, {"support_material_xy_spacing", "50%"},
      {"support_material_interface_layers", "3"}, {"support_material_spacing", "2.5"},
      {"support_material_angle", "0"}, {"support_material_pattern", "rectilinear"},
      {"support_material_threshold", "0"}, {"brim_width", "0"}, {"raft_layers", "0"},
      {"gcode_resolution", "0.0125"}, {"gcode_flavor", "reprap"}, {"temperature", "200"},
      {"first_layer_temperature", "200"}, {"bed_temperature", "0"},
      {"first_layer_bed_temperature", "0"}, {"min_fan_speed", "35"}, {"max_fan_speed", "100"},
      {"disable_fan_first_layers", "3"}, {"fan_always_on", "0"}, {"extrusion_multiplier", "1"},
      {"filament_density", "0"}, {"filament_type", "PLA"}, {"bridge_fan_speed", "100"},
{"z_offset", "0"}, {"printer_technology", "FFF"},
      {"start_gcode", "G28 ; home all axes\\nG1 Z5 F5000 ; lift nozzle\\n"},
      {"end_gcode", "M104 S0 ; turn off temperature\\nG28 X0  ; home X axis\\nM84     ; disable motors\\n"},
      {"default_print_profile", ""},
      {"default_filament_profile", ""}};
  return defaults;
}

// PrusaSlicer's settings that are vectors (one value per extruder, or per machine mode), and its
// booleans: how a compatible_printers_condition sees them.
const std::set<std::string, std::less<>> kVectorKeys = {
    "nozzle_diameter", "min_layer_height", "max_layer_height", "retract_length", "retract_lift",
    "retract_lift_above", "retract_lift_below", "retract_speed", "deretract_speed",
    "retract_restart_extra", "retract_before_travel", "retract_layer_change", "wipe",
    "retract_before_wipe", "retract_length_toolchange", "retract_restart_extra_toolchange",
    "extruder_offset", "extruder_colour", "machine_max_feedrate_x", "machine_max_feedrate_y",
    "machine_max_feedrate_z", "machine_max_feedrate_e", "machine_max_acceleration_x",
    "machine_max_acceleration_y", "machine_max_acceleration_z", "machine_max_acceleration_e",
    "machine_max_acceleration_extruding", "machine_max_acceleration_retracting",
    "machine_max_acceleration_travel", "machine_max_jerk_x", "machine_max_jerk_y",
    "machine_max_jerk_z", "machine_max_jerk_e", "machine_min_extruding_rate",
    "machine_min_travel_rate"};
const std::set<std::string, std::less<>> kBoolKeys = {
    "single_extruder_multi_material", "use_relative_e_distances", "use_firmware_retraction",
    "use_volumetric_e", "variable_layer_height", "remaining_times", "silent_mode",
    "high_current_on_filament_swap", "retract_layer_change", "wipe", "thumbnails_with_bed"};

// A printer's setting as PrusaSlicer's macros see it, typed from its text.
MacroVariable typed(std::string_view key, std::string_view raw) {
  const bool is_bool = kBoolKeys.count(key) > 0;
  if (const auto numbers = prusa_numbers(raw)) {
    std::vector<MacroScalar> values;
    for (const PrusaNumber& n : *numbers) {
      if (is_bool) values.emplace_back(n.value != 0);
      else values.emplace_back(n.value);
    }
    if (kVectorKeys.count(key) || values.size() > 1) return macro_vector(std::move(values));
    return macro_scalar(values.front());
  }
  return macro_scalar(prusa_string(raw));
}

// The settings of one printer with its print and filament profiles, each key from the first
// of them that has it, else PrusaSlicer's default.
class Settings {
 public:
  Settings(const PrusaPreset& printer, const PrusaPreset* print, const PrusaPreset* filament)
      : printer_(printer), print_(print), filament_(filament) {}

  std::string_view raw(std::string_view key) const {
    for (const PrusaPreset* p : {&printer_, print_, filament_}) {
      if (!p) continue;
      if (const auto value = p->raw(key)) return *value;
    }
    const auto found = prusa_defaults().find(key);
    if (found == prusa_defaults().end()) throw ConfigError(fmt::format("internal: no default for {}", key));
    return found->second;
  }

  std::string text(std::string_view key) const { return prusa_string(raw(key)); }

  // The first number of the key (a vector's first element), or an error naming it.
  PrusaNumber first(std::string_view key) const {
    const auto numbers = prusa_numbers(raw(key));
    if (!numbers) {
      throw Refused{fmt::format("{} = '{}' is not a number", key, std::string(raw(key)).substr(0, 30))};
    }
    return numbers->front();
  }
  double number(std::string_view key) const { return first(key).value; }

  // A value in mm or mm/s that may be a percent of `base`; 0 stays 0 ("auto" to PrusaSlicer).
  double relative(std::string_view key, double base) const {
    const PrusaNumber n = first(key);
    return n.percent ? n.value / 100 * base : n.value;
  }

  std::size_t count(std::string_view key) const {
    const auto numbers = prusa_numbers(raw(key));
    return numbers ? numbers->size() : 1;
  }

  bool flag(std::string_view key) const { return number(key) != 0; }

  const PrusaPreset& printer() const { return printer_; }

  struct Refused {
    std::string reason;
  };

 private:
  const PrusaPreset& printer_;
  const PrusaPreset* print_;
  const PrusaPreset* filament_;
};

// ---- which print and filament profile -----------------------------------------------------

// The printer's settings as its profiles' compatibility conditions read them.
MacroVariables condition_variables(const PrusaPreset& printer) {
  MacroVariables v;
  for (const auto& [key, raw] : printer.keys) v[key] = typed(key, raw);
  const auto nozzles = printer.raw("nozzle_diameter");
  const auto numbers = prusa_numbers(nozzles ? *nozzles : "0.4");
  if (!v.count("nozzle_diameter")) v["nozzle_diameter"] = typed("nozzle_diameter", "0.4");
  v["num_extruders"] = macro_scalar(static_cast<long long>(numbers ? numbers->size() : 1));
  v["printer_preset"] = macro_scalar(printer.name);
  v["printer_settings_id"] = macro_scalar(printer.name);
  for (const auto& [key, value] : prusa_defaults()) {
    if (!v.count(key)) v[key] = typed(key, value);
  }
  return v;
}

// Whether a print or filament profile may be used with the printer (PrusaSlicer's
// Preset::is_compatible_with_printer): its compatible_printers list, else its condition.
bool compatible(const PrusaPreset& profile, const PrusaPreset& printer, const MacroVariables& variables) {
  if (const auto listed = profile.raw("compatible_printers")) {
    const std::vector<std::string> names = prusa_strings(*listed);
    if (!(names.size() == 1 && names.front().empty())) {
      return std::find(names.begin(), names.end(), printer.name) != names.end();
    }
  }
  const auto condition = profile.raw("compatible_printers_condition");
  if (!condition || prusa_string(*condition).empty()) return true;
  try {
    std::string macro = "{";
    macro += prusa_string(*condition);
    macro += '}';
    return expand_prusa_macro(macro, variables, "condition") == "true";
  } catch (const ConfigError&) {
    return false;  // PrusaSlicer, too, takes a condition it cannot evaluate for false
  }
}

// PrusaSlicer's name of a profile as it was before it was given an '@': "0.10mm DETAIL @0.25
// nozzle" was "0.10mm DETAIL 0.25 nozzle" (its renamed_from), so old names still find it.
bool renamed_from(const PrusaPreset& profile, std::string_view name) {
  if (const auto renamed = profile.raw("renamed_from")) {
    for (const std::string& old : prusa_strings(*renamed)) {
      if (old == name) return true;
    }
    return false;
  }
  std::string old = profile.name;
  const std::size_t at = old.find('@');
  if (at == std::string::npos) return false;
  old.erase(at, 1);
  return old == name;
}

const PrusaPreset* find_profile(const std::map<std::string, PrusaPreset, std::less<>>& profiles,
                                const std::vector<std::string>& wanted, const PrusaPreset& printer,
                                const MacroVariables& variables) {
  for (const std::string& name : wanted) {
    if (name.empty()) continue;
    if (const auto found = profiles.find(name); found != profiles.end()) return &found->second;
    for (const auto& [other, profile] : profiles) {
      if (renamed_from(profile, name) && compatible(profile, printer, variables)) return &profile;
    }
  }
  for (const auto& [other, profile] : profiles) {
    if (compatible(profile, printer, variables)) return &profile;
  }
  return nullptr;
}

// ---- TOML ---------------------------------------------------------------------------------

std::string toml_string(std::string_view text) {
  std::string out;
  const bool multiline = text.find('\n') != std::string_view::npos;
  out += multiline ? "\"\"\"\n" : "\"";
  for (const char c : text) {
    const auto u = static_cast<unsigned char>(c);
    if (c == '\\') out += "\\\\";
    else if (c == '"') out += "\\\"";
    else if (c == '\n' && multiline) out += '\n';
    else if (c == '\n') out += "\\n";
    else if (c == '\t') out += "\\t";
    else if (u < 0x20 || u == 0x7f) out += fmt::format("\\u{:04X}", u);
    else out += c;
  }
  out += multiline ? "\"\"\"" : "\"";
  return out;
}

std::string toml_number(double v) {
  // Shortest text that reads back the same; always a float, for the constants' types.
  std::string text = fmt::format("{}", v);
  if (text.find_first_of(".eEn") == std::string::npos) text += ".0";
  return text;
}

std::string toml_scalar(const MacroScalar& value) {
  if (const auto* i = std::get_if<long long>(&value)) return std::to_string(*i);
  if (const auto* d = std::get_if<double>(&value)) return toml_number(*d);
  if (const auto* s = std::get_if<std::string>(&value)) return toml_string(*s);
  return std::get<bool>(value) ? "true" : "false";
}

// Writes `key = value` lines section by section, in the order given.
class TomlWriter {
 public:
  void comment(std::string_view text) { out_ += fmt::format("# {}\n", text); }
  void section(std::string_view name) { out_ += fmt::format("\n[{}]\n", name); }
  void raw(std::string_view key, std::string_view value, std::string_view note = {}) {
    out_ += fmt::format("{} = {}{}\n", key, value, note.empty() ? "" : fmt::format("  # {}", note));
  }
  void text(std::string_view key, std::string_view value, std::string_view note = {}) {
    raw(key, toml_string(value), note);
  }
  void number(std::string_view key, double value, std::string_view note = {}) {
    raw(key, fmt::format("{}", std::round(value * 1e6) / 1e6), note);
  }
  void integer(std::string_view key, long long value, std::string_view note = {}) {
    raw(key, std::to_string(value), note);
  }
  void flag(std::string_view key, bool value) { raw(key, value ? "true" : "false"); }
  const std::string& str() const { return out_; }

 private:
  std::string out_;
};

// ---- the printer --------------------------------------------------------------------------

struct Bed {
  double x = 0, y = 0, origin_x = 0, origin_y = 0;
  bool round = false;
};

Bed bed_of(const Settings& s) {
  const auto points = prusa_points(s.raw("bed_shape"));
  if (!points || points->size() < 3) {
    throw Settings::Refused{fmt::format("bed_shape '{}' is not a list of points",
                                        std::string(s.raw("bed_shape")).substr(0, 40))};
  }
  double x0 = points->front().x, x1 = x0, y0 = points->front().y, y1 = y0;
  for (const PrusaPoint& p : *points) {
    x0 = std::min(x0, p.x); x1 = std::max(x1, p.x);
    y0 = std::min(y0, p.y); y1 = std::max(y1, p.y);
  }
  Bed bed{x1 - x0, y1 - y0, x0, y0, false};
  const auto corner = [&](const PrusaPoint& p) {
    return (std::abs(p.x - x0) < 1e-6 || std::abs(p.x - x1) < 1e-6) &&
           (std::abs(p.y - y0) < 1e-6 || std::abs(p.y - y1) < 1e-6);
  };
  if (points->size() == 4 && std::all_of(points->begin(), points->end(), corner)) return bed;
  // A circle: PrusaSlicer's round beds are many points at one distance from the centre.
  const double cx = (x0 + x1) / 2, cy = (y0 + y1) / 2, r = bed.x / 2;
  const bool round = points->size() >= 8 && std::abs(bed.x - bed.y) <= 0.01 * bed.x &&
                     std::all_of(points->begin(), points->end(), [&](const PrusaPoint& p) {
                       return std::abs(std::hypot(p.x - cx, p.y - cy) - r) <= 0.01 * r;
                     });
  if (!round) {
    throw Settings::Refused{fmt::format("bed_shape has {} points that make neither a rectangle "
                                        "nor a circle; mahost knows those two", points->size())};
  }
  bed.round = true;
  bed.y = bed.x;
  return bed;
}

// PrusaSlicer's gcode_flavor as the firmware mahost writes for, or a refusal.
std::string firmware_of(std::string_view flavor, std::string& note) {
  if (flavor == "marlin" || flavor == "marlin2") return "marlin";
  if (flavor == "repetier") return "repetier";
  if (flavor == "teacup") return "teacup";
  if (flavor == "klipper" || flavor == "smoothie" || flavor == "reprap" || flavor == "reprapfirmware") {
    note = fmt::format("PrusaSlicer's gcode_flavor {}: written as Marlin's G-code, which it takes", flavor);
    return "marlin";
  }
  throw Settings::Refused{fmt::format(
      "gcode_flavor {}: mahost writes G-code for Marlin (and Klipper, Smoothie, RepRapFirmware, "
      "Sprinter), Repetier and Teacup", flavor)};
}

// The identifiers a G-code template names, in [...] and {...} (with words of its strings and
// regular expressions: only those that are the printer's settings matter).
std::set<std::string> names_in(std::string_view gcode) {
  std::set<std::string> names;
  int braces = 0;
  bool bracket = false;
  const auto word_char = [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; };
  for (std::size_t i = 0; i < gcode.size(); ++i) {
    const char c = gcode[i];
    if (c == '{') ++braces;
    else if (c == '}') braces = std::max(0, braces - 1);
    else if (c == '[' && braces == 0) bracket = true;
    else if (c == ']' && braces == 0) bracket = false;
    if ((braces == 0 && !bracket) || !(std::isalpha(static_cast<unsigned char>(c)) || c == '_')) continue;
    if (i > 0 && word_char(gcode[i - 1])) continue;
    std::size_t end = i;
    while (end < gcode.size() && word_char(gcode[end])) ++end;
    names.emplace(gcode.substr(i, end - i));
    i = end - 1;
  }
  return names;
}

// What several of the printer profile's sections take from PrusaSlicer's settings, read in
// this order (a refusal names the first key at fault).
struct PrinterFigures {
  std::string firmware, flavor_note;
  Bed bed;
  double nozzle = 0;
  std::size_t extruders = 1;
  // The print's layers, within the printer's range (widened to take them, as PrusaSlicer
  // would print them); step 0.01 mm where they are all on that grid, else any thickness.
  double layer = 0, first_layer = 0, min_layer = 0, max_layer = 0, step = 0;
  double width = 0, first_width = 0;
  // Speeds, mm/s: 0 is PrusaSlicer's "auto", which its max_print_speed bounds.
  double auto_speed = 0, perimeter = 0, infill = 0, solid = 0, support = 0, travel_z = 0;

  double speed_or_auto(double v) const { return v > 0 ? v : auto_speed; }
};

PrinterFigures printer_figures(const Settings& s) {
  if (s.number("z_offset") != 0) {
    throw Settings::Refused{fmt::format("z_offset = {:g} mm: mahost moves Z as planned, with no offset",
                                        s.number("z_offset"))};
  }
  PrinterFigures f;
  f.firmware = firmware_of(s.text("gcode_flavor"), f.flavor_note);
  f.bed = bed_of(s);
  f.nozzle = s.number("nozzle_diameter");
  f.extruders = s.count("nozzle_diameter");

  f.layer = s.number("layer_height");
  f.first_layer = s.relative("first_layer_height", f.layer);
  f.min_layer = s.number("min_layer_height");
  f.max_layer = s.number("max_layer_height");
  if (!(f.max_layer > 0)) f.max_layer = 0.75 * f.nozzle;
  f.min_layer = std::min({f.min_layer, f.layer, f.first_layer});
  f.max_layer = std::max({f.max_layer, f.layer, f.first_layer});
  const auto on_grid = [](double v) { return std::abs(v * 100 - std::round(v * 100)) < 1e-6; };
  f.step = on_grid(f.min_layer) && on_grid(f.layer) && on_grid(f.first_layer) ? 0.01 : 0;

  f.width = s.relative("extrusion_width", f.layer);
  if (!(f.width > 0)) f.width = s.relative("perimeter_extrusion_width", f.layer);
  if (!(f.width > 0)) f.width = 1.125 * f.nozzle;
  f.first_width = s.relative("first_layer_extrusion_width", f.first_layer);
  if (!(f.first_width > 0)) f.first_width = f.width;

  f.auto_speed = s.number("max_print_speed");
  f.perimeter = f.speed_or_auto(s.number("perimeter_speed"));
  f.infill = f.speed_or_auto(s.number("infill_speed"));
  f.solid = f.speed_or_auto(s.relative("solid_infill_speed", f.infill));
  f.support = f.speed_or_auto(s.number("support_material_speed"));
  f.travel_z = s.number("travel_speed_z");
  if (!(f.travel_z > 0)) f.travel_z = s.number("machine_max_feedrate_z");
  return f;
}

// "bundle of Prusa Research" or "settings": where a profile was imported from.
std::string source_of(const PrusaIni& ini) {
  return ini.is_vendor ? "bundle of " + ini.vendor : std::string("settings");
}

// The header comments, name, material and firmware.
void write_identity(TomlWriter& t, const PrinterFigures& f, const std::string& file, const PrusaIni& ini,
                    const PrusaPreset& printer, const PrusaPreset* print, const PrusaPreset& filament) {
  t.comment(fmt::format("{} for mahost, imported from PrusaSlicer's {} ({})", printer.name,
                        source_of(ini), file));
  t.comment(fmt::format("with the print profile \"{}\" and the filament \"{}\". Import again to update;",
                        print ? print->name : "(PrusaSlicer's defaults)", filament.name));
  t.comment("keys as in mahost's own profiles (printer/profile.h). Units: mm, s, mm/s, mm/s^2.");
  t.text("name", printer.name);
  t.text("material", filament.name);
  t.text("firmware", f.firmware, f.flavor_note);
}

// [build_volume], [nozzle], [filament], [extrusion].
void write_machine(TomlWriter& t, const Settings& s, const PrinterFigures& f) {
  t.section("build_volume");
  t.number("x", f.bed.x);
  t.number("y", f.bed.y);
  t.number("z", s.number("max_print_height"));
  if (f.bed.origin_x != 0 || f.bed.origin_y != 0) {
    t.number("origin_x", f.bed.origin_x, "the G-code's X of the front left corner");
    t.number("origin_y", f.bed.origin_y);
  }
  if (f.bed.round) t.text("shape", "circle", "the bed is the circle of diameter x");

  t.section("nozzle");
  t.number("diameter", f.nozzle);
  if (f.extruders > 1) t.integer("count", static_cast<long long>(f.extruders), "mahost prints with the first");
  t.section("filament");
  t.number("diameter", s.number("filament_diameter"));
  t.section("extrusion");
  t.number("width", f.width);
  t.text("e_mode", s.flag("use_relative_e_distances") ? "relative" : "absolute");
}

// [layer], [first_layer].
void write_layers(TomlWriter& t, const Settings& s, const PrinterFigures& f) {
  t.section("layer");
  t.number("min", f.min_layer);
  t.number("max", f.max_layer);
  t.number("step", f.step, f.step > 0 ? "" : "any thickness in the range");
  t.number("default", f.layer);
  t.section("first_layer");
  t.number("height", f.first_layer,
           s.first("first_layer_height").percent
               ? fmt::format("PrusaSlicer's {}: as Slic3r took it, a percent of layer_height (PrusaSlicer 2.5 "
                             "reads it as mm and does not slice)", s.raw("first_layer_height"))
               : std::string());
  t.number("width", f.first_width);
  t.number("speed", s.relative("first_layer_speed", f.perimeter));
}

// [motion]: the machine's limits; a limit past what mahost takes (a vendor's 8000 mm/s
// extruder) is mahost's largest, which no move reaches either.
void write_motion(TomlWriter& t, const Settings& s) {
  t.section("motion");
  const auto limit = [&](const std::string& key, std::string_view from, double most) {
    const double v = s.number(from);
    if (v > most) {
      t.number(key, most, fmt::format("PrusaSlicer's {} is {:g}", from, v));
    } else {
      t.number(key, v);
    }
  };
  for (const char* axis : {"x", "y", "z", "e"}) {
    limit(fmt::format("max_speed_{}", axis), fmt::format("machine_max_feedrate_{}", axis), 2000);
  }
  for (const char* axis : {"x", "y", "z", "e"}) {
    limit(fmt::format("max_acceleration_{}", axis), fmt::format("machine_max_acceleration_{}", axis), 100000);
  }
  limit("print_acceleration", "machine_max_acceleration_extruding", 100000);
  limit("travel_acceleration", "machine_max_acceleration_travel", 100000);
  limit("retract_acceleration", "machine_max_acceleration_retracting", 100000);
  t.number("min_feedrate", s.number("machine_min_extruding_rate"));
}

// [speed], [retraction].
void write_speeds(TomlWriter& t, const Settings& s, const PrinterFigures& f) {
  t.section("speed");
  t.number("outer_wall", f.speed_or_auto(s.relative("external_perimeter_speed", f.perimeter)));
  t.number("inner_wall", f.perimeter);
  t.number("thin_wall", f.speed_or_auto(s.number("gap_fill_speed")));
  t.number("skirt", f.perimeter);
  t.number("top_skin", f.speed_or_auto(s.relative("top_solid_infill_speed", f.solid)));
  t.number("bottom_skin", f.solid);
  t.number("solid_infill", f.solid);
  t.number("sparse_infill", f.infill);
  t.number("support", f.support);
  t.number("support_interface", f.speed_or_auto(s.relative("support_material_interface_speed", f.support)));
  t.number("bridge", f.speed_or_auto(s.number("bridge_speed")));
  t.number("brim", f.perimeter);
  t.number("raft", f.support);
  t.number("travel", f.speed_or_auto(s.number("travel_speed")));
  t.number("z", f.travel_z);

  t.section("retraction");
  const double retract_speed = s.number("retract_speed");
  const double deretract = s.number("deretract_speed");
  t.number("length", s.number("retract_length"));
  t.number("speed", retract_speed);
  t.number("prime_speed", deretract > 0 ? deretract : retract_speed);
  t.number("min_travel", s.number("retract_before_travel"));
  t.number("z_hop", s.number("retract_lift"));
}

// [print]: walls, infill, skins, skirt, seam.
void write_print(TomlWriter& t, const Settings& s) {
  t.section("print");
  t.integer("perimeters", std::lround(s.number("perimeters")));
  t.number("infill_density", s.number("fill_density"));
  const std::string pattern = s.text("fill_pattern");
  const bool lines = pattern == "rectilinear" || pattern == "alignedrectilinear" || pattern == "line";
  t.text("infill_pattern", lines ? "rectilinear" : "grid",
         lines || pattern == "grid" ? "" : fmt::format("PrusaSlicer's {}: mahost lays grid or lines", pattern));
  t.integer("top_layers", std::lround(s.number("top_solid_layers")));
  t.integer("bottom_layers", std::lround(s.number("bottom_solid_layers")));
  t.number("top_thickness", s.number("top_solid_min_thickness"));
  t.number("bottom_thickness", s.number("bottom_solid_min_thickness"));
  t.integer("skirt_loops", std::lround(s.number("skirts")));
  t.number("skirt_distance", s.number("skirt_distance"));
  const std::string seam = s.text("seam_position");
  t.text("seam", seam == "nearest" || seam == "random" ? "nearest" : "aligned");
}

// [support], [brim], [raft].
void write_support(TomlWriter& t, const Settings& s, const PrinterFigures& f) {
  t.section("support");
  t.text("type", !s.flag("support_material") ? "none"
                 : s.flag("support_material_buildplate_only") ? "buildplate" : "everywhere");
  const double top_gap = s.number("support_material_contact_distance");
  const double bottom_gap = s.number("support_material_bottom_contact_distance");
  t.number("top_contact_distance", top_gap);
  t.number("bottom_contact_distance", bottom_gap > 0 ? bottom_gap : top_gap);
  t.number("xy_gap", s.relative("support_material_xy_spacing", f.width));
  t.number("interface_thickness", s.number("support_material_interface_layers") * f.layer);
  t.number("spacing", s.number("support_material_spacing"));
  t.number("angle", s.number("support_material_angle"));
  t.text("pattern", s.text("support_material_pattern") == "rectilinear-grid" ? "grid" : "lines");

  t.section("brim");
  t.number("width", s.number("brim_width"));
  t.section("raft");
  t.flag("enabled", s.number("raft_layers") > 0);
  t.number("layer_thickness", f.layer);
  t.number("base_thickness", f.first_layer);
  t.number("base_width", std::max(f.first_width, f.first_layer));
}

// [gcode]: the start and end G-code with PrusaSlicer's placeholders, and [gcode.constants]:
// the printer's own settings they name that mahost has no key of its own for.
void write_gcode(TomlWriter& t, const Settings& s, const PrusaPreset& printer, const PrusaPreset* print,
                 const MacroVariables& known) {
  t.section("gcode");
  t.number("resolution", s.number("gcode_resolution"));
  t.text("syntax", "prusaslicer");
  const std::string start = s.text("start_gcode"), end = s.text("end_gcode");
  t.text("start", start);
  t.text("end", end);
  for (const char* hook : {"before_layer_gcode", "layer_gcode", "toolchange_gcode"}) {
    if (const auto raw = printer.raw(hook); raw && !prusa_string(*raw).empty()) {
      t.comment(fmt::format("PrusaSlicer's {} is not used: mahost writes each layer's start itself", hook));
    }
  }
  std::vector<std::pair<std::string, MacroVariable>> constants;
  std::set<std::string> names = names_in(start);
  names.merge(names_in(end));
  for (const std::string& name : names) {
    if (known.count(name)) continue;
    if (const auto raw = printer.raw(name)) {
      constants.emplace_back(name, typed(name, *raw));
    } else if (name == "print_settings_id" && print) {
      constants.emplace_back(name, macro_scalar(print->name));
    } else if (name == "printer_preset") {
      constants.emplace_back(name, macro_scalar(printer.name));
    }
  }
  if (constants.empty()) return;
  t.section("gcode.constants");
  for (const auto& [name, v] : constants) {
    std::vector<std::string> items;
    for (const MacroScalar& x : v.values) items.push_back(toml_scalar(x));
    t.raw(name, v.is_vector ? fmt::format("[{}]", fmt::join(items, ", ")) : items.front());
  }
}

// The material profile: the filament profile's keys.
std::string material_profile(const PrusaPreset& filament, const PrusaIni& ini, const std::string& file) {
  const Settings f(filament, nullptr, nullptr);
  TomlWriter m;
  m.comment(fmt::format("{} for mahost, imported from PrusaSlicer's {} ({}).", filament.name,
                        source_of(ini), file));
  m.comment("Temperatures in degrees Celsius; fan in percent of full speed.");
  m.text("name", filament.name);
  m.text("type", f.text("filament_type"));
  m.number("flow", f.number("extrusion_multiplier"));
  if (f.number("filament_density") > 0) m.number("density", f.number("filament_density"));
  m.section("temperature");
  m.number("nozzle", f.number("temperature"));
  m.number("first_layer_nozzle", f.number("first_layer_temperature"));
  m.number("bed", f.number("bed_temperature"));
  m.number("first_layer_bed", f.number("first_layer_bed_temperature"));
  m.section("fan");
  m.number("speed", f.flag("fan_always_on") ? f.number("min_fan_speed") : 0,
           "PrusaSlicer's min_fan_speed when fan_always_on; more only for short layers");
  m.integer("start_layer", std::lround(f.number("disable_fan_first_layers")));
  // The print profile's bridge flow and overhang threshold stay out: a material serves every
  // printer whose default filament it is, each with a print profile of its own.
  m.section("bridge");
  m.number("fan", f.number("bridge_fan_speed"));
  return m.str();
}

struct Written {
  std::string printer, material;
};

Written write_profiles(const Settings& s, const std::string& file, const PrusaIni& ini,
                       const PrusaPreset* print, const PrusaPreset& filament,
                       const MacroVariables& known) {
  const PrinterFigures f = printer_figures(s);
  TomlWriter t;
  write_identity(t, f, file, ini, s.printer(), print, filament);
  write_machine(t, s, f);
  write_layers(t, s, f);
  write_motion(t, s);
  write_speeds(t, s, f);
  write_print(t, s);
  write_support(t, s, f);
  write_gcode(t, s, s.printer(), print, known);
  std::string material = material_profile(filament, ini, file);
  return {t.str(), std::move(material)};
}

// Names in `available` close to `wanted`: those containing it, ignoring case.
std::vector<std::string> close_names(const std::vector<std::string>& available, std::string_view wanted) {
  const auto lower = [](std::string_view s) {
    std::string out(s);
    for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return out;
  };
  const std::string w = lower(wanted);
  std::vector<std::string> close;
  for (const std::string& name : available) {
    if (lower(name).find(w) != std::string::npos) close.push_back(name);
  }
  return close;
}

// The name the profiles are checked under, taken off the messages of a refusal (which names the
// printer already): "<kChecked>:39: key ..." -> "key ...".
constexpr std::string_view kChecked = "imported profile";

std::string without_source(std::string_view message) {
  if (!message.starts_with(kChecked)) return std::string(message);
  message.remove_prefix(kChecked.size());
  while (!message.empty() && (message.front() == ':' || std::isdigit(static_cast<unsigned char>(message.front())))) {
    message.remove_prefix(1);
  }
  if (message.starts_with(" ")) message.remove_prefix(1);
  return std::string(message);
}

}  // namespace

PrusaImport import_prusa_ini(std::string_view text, const std::string& name,
                             const std::vector<std::string>& only) {
  const PrusaIni ini = read_prusa_ini(text, name);
  PrusaImport result;
  for (const PrusaPreset& p : ini.printers) result.available.push_back(p.name);
  for (const std::string& wanted : only) {
    if (std::find(result.available.begin(), result.available.end(), wanted) != result.available.end()) continue;
    const std::vector<std::string> close = close_names(result.available, wanted);
    throw ConfigError(fmt::format(
        "{} has no printer '{}'{}", name, wanted,
        close.empty() ? fmt::format(" (it has {}; mahost profiles import {} --all takes them all)",
                                    result.available.size(), name)
                      : fmt::format("; did you mean: {}", fmt::join(close.begin(), close.begin() +
                                                                   std::min<std::size_t>(close.size(), 12), "; "))));
  }
  // What the evaluation of the G-code will know, whatever the printer (mahost's values).
  const MacroVariables known = prusa_variables(Profiles{}, PlaceholderValues{});
  std::set<std::string> stems;
  for (const PrusaPreset& printer : ini.printers) {
    if (!only.empty() && std::find(only.begin(), only.end(), printer.name) == only.end()) continue;
    try {
      const MacroVariables conditions = condition_variables(printer);
      const PrusaPreset* print = nullptr;
      const PrusaPreset* filament = nullptr;
      const Settings bare(printer, nullptr, nullptr);
      if (bare.text("printer_technology") != "FFF") {
        throw Settings::Refused{fmt::format("printer_technology {}: mahost prints with filament (FFF) only",
                                            bare.text("printer_technology"))};
      }
      if (ini.is_bundle) {
        print = find_profile(ini.prints, {bare.text("default_print_profile")}, printer, conditions);
        if (!print) {
          throw Settings::Refused{fmt::format("no print profile: default_print_profile '{}' is not "
                                              "in the file and none of its print profiles fits it",
                                              bare.text("default_print_profile"))};
        }
        std::vector<std::string> wanted = prusa_strings(bare.raw("default_filament_profile"));
        filament = find_profile(ini.filaments, wanted, printer, conditions);
        if (!filament) throw Settings::Refused{"no filament profile fits it"};
      } else {
        print = &ini.prints.begin()->second;
        filament = &ini.filaments.begin()->second;
      }
      const Settings settings(printer, print, filament);
      const Written written = write_profiles(settings, name, ini, print, *filament, known);
      ImportedPrinter imported;
      imported.printer = {printer.name, profile_file_stem(printer.name), written.printer};
      imported.material = {filament->name, profile_file_stem(filament->name), written.material};
      imported.print_profile = print ? print->name : "";
      // Checked as `mahost slice` loads them: every key's range, and the start and end G-code
      // evaluated with this material.
      Profiles profiles;
      profiles.printer = parse_printer_profile(written.printer, std::string(kChecked));
      profiles.material = parse_material_profile(written.material, std::string(kChecked));
      expand_placeholders(profiles.printer.start_gcode, profiles, {}, "gcode.start");
      expand_placeholders(profiles.printer.end_gcode, profiles, {}, "gcode.end");
      if (imported.printer.stem.empty() || !stems.insert(imported.printer.stem).second) {
        throw Settings::Refused{fmt::format("its file name '{}.toml' is another printer's", imported.printer.stem)};
      }
      result.printers.push_back(std::move(imported));
    } catch (const Settings::Refused& e) {
      result.refused.push_back({printer.name, e.reason});
    } catch (const ConfigError& e) {
      result.refused.push_back({printer.name, without_source(e.what())});
    }
  }
  for (const auto& [printer, why] : ini.skipped_printers) {
    if (only.empty()) result.refused.push_back({printer, why});
  }
  return result;
}

PrusaImport import_prusa_ini_file(const std::string& path, const std::vector<std::string>& only) {
  return import_prusa_ini(geometry::read_file_bytes(path), path, only);
}

}  // namespace printer
