// Printer and material profiles (see profile.h): one table of rules per profile kind says, for
// every key, its type, its range and where it goes; the file's keys and the --set overrides go
// through the same rules, so a key is checked the same way wherever it comes from.
#include "printer/profile.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <optional>
#include <set>
#include <sstream>

#include <fmt/core.h>
#include <fmt/format.h>
#include <toml++/toml.h>

#include "base/text.h"
#include "printer/error.h"
#include "printer/prusa_variables.h"

namespace printer {

namespace {

using base::trim;

constexpr double kInf = std::numeric_limits<double>::infinity();

// `constant`: any TOML value (a string, number, boolean or a list of them), for PrusaSlicer's
// settings kept by name under a table (gcode.constants.NAME).
enum class Kind { number, integer, boolean, text, number_list, box_list, constant };

struct Value {
  double number = 0;
  long long integer = 0;
  bool flag = false;
  std::string text;
  std::vector<double> list;
  std::vector<SupportBoxMm> boxes;
  MacroVariable constant;
  std::string name;  // a constant's name: the key after its table's
};

template <class Target>
struct Rule {
  std::string_view key;
  Kind kind = Kind::number;
  double min = -kInf, max = kInf;  // numbers, integers and each list element
  std::string_view unit;
  std::vector<std::string_view> choices;  // text keys with a fixed set of values
  bool required = false;
  bool table = false;  // every key under `key.` (Kind::constant)
  std::function<void(Target&, const Value&)> apply;
};

template <class Target>
using Rules = std::vector<Rule<Target>>;

// What a rule accepts, for messages: "a number from 1 to 500 mm/s".
template <class Target>
std::string describe(const Rule<Target>& rule) {
  std::string range;
  if (rule.min > -kInf && rule.max < kInf) {
    range = fmt::format(" from {} to {}", rule.min, rule.max);
  } else if (rule.min > -kInf) {
    range = fmt::format(" of at least {}", rule.min);
  }
  const std::string unit = rule.unit.empty() ? "" : " " + std::string(rule.unit);
  switch (rule.kind) {
    case Kind::number: return "a number" + range + unit;
    case Kind::integer: return "a whole number" + range + unit;
    case Kind::boolean: return "true or false";
    case Kind::number_list: return "a list of numbers" + range + unit;
    case Kind::box_list:
      return "a list of boxes [x0, y0, z0, x1, y1, z1] in mm with x0 < x1, y0 < y1, z0 < z1 "
             "(on the command line: x0,y0,z0,x1,y1,z1;...)";
    case Kind::text:
      if (!rule.choices.empty()) {
        return fmt::format("one of {}", fmt::join(rule.choices, ", "));
      }
      return "a string";
    case Kind::constant: return "a string, a number, true, false or a list of them";
  }
  return "a value";
}

template <class Target>
void check_value(const Rule<Target>& rule, const Value& v, const std::string& where) {
  auto out_of_range = [&](double x) {
    return !std::isfinite(x) || x < rule.min || x > rule.max;
  };
  bool bad = false;
  std::string shown;
  switch (rule.kind) {
    case Kind::number: bad = out_of_range(v.number); shown = fmt::format("{}", v.number); break;
    case Kind::integer:
      bad = out_of_range(static_cast<double>(v.integer));
      shown = fmt::format("{}", v.integer);
      break;
    case Kind::number_list:
      bad = v.list.empty() || std::any_of(v.list.begin(), v.list.end(), out_of_range);
      shown = fmt::format("[{}]", fmt::join(v.list, ", "));
      break;
    case Kind::text:
      bad = !rule.choices.empty() &&
            std::find(rule.choices.begin(), rule.choices.end(), v.text) == rule.choices.end();
      shown = "\"" + v.text + "\"";
      break;
    case Kind::box_list: {
      std::vector<std::string> texts;
      for (const SupportBoxMm& b : v.boxes) {
        bad = bad || !std::all_of(b.begin(), b.end(), [](double x) { return std::isfinite(x); }) ||
              !(b[0] < b[3] && b[1] < b[4] && b[2] < b[5]);
        texts.push_back(fmt::format("[{}]", fmt::join(b, ", ")));
      }
      shown = fmt::format("[{}]", fmt::join(texts, ", "));
      break;
    }
    case Kind::constant:
      if (v.name.empty() || std::isdigit(static_cast<unsigned char>(v.name.front())) ||
          !std::all_of(v.name.begin(), v.name.end(), [](char c) {
            return std::isalnum(static_cast<unsigned char>(c)) || c == '_';
          })) {
        throw ConfigError(fmt::format("{}: key '{}' has a name '{}' that is not a placeholder's "
                                      "(letters, digits and _)", where, rule.key, v.name));
      }
      break;
    case Kind::boolean: break;
  }
  if (bad) {
    throw ConfigError(fmt::format("{}: key '{}' = {} is not allowed; it must be {}", where,
                                  rule.key, shown, describe(rule)));
  }
}

std::string_view node_type_name(const toml::node& node) {
  if (node.is_string()) return "a string";
  if (node.is_integer() || node.is_floating_point()) return "a number";
  if (node.is_boolean()) return "a boolean";
  if (node.is_array()) return "a list";
  if (node.is_table()) return "a table";
  return "a date or time";
}

// Converts a TOML node to the rule's kind, or throws naming the key and the expected type.
template <class Target>
Value value_from_node(const Rule<Target>& rule, const toml::node& node, const std::string& where) {
  Value v;
  auto wrong_type = [&]() {
    return ConfigError(fmt::format("{}: key '{}' must be {}, not {}", where, rule.key,
                                   describe(rule), node_type_name(node)));
  };
  auto as_number = [&](const toml::node& n, double& out) {
    if (auto i = n.value_exact<int64_t>()) { out = static_cast<double>(*i); return true; }
    if (auto d = n.value_exact<double>()) { out = *d; return true; }
    return false;
  };
  switch (rule.kind) {
    case Kind::number:
      if (!as_number(node, v.number)) throw wrong_type();
      break;
    case Kind::integer:
      if (auto i = node.value_exact<int64_t>()) v.integer = *i; else throw wrong_type();
      break;
    case Kind::boolean:
      if (auto b = node.value_exact<bool>()) v.flag = *b; else throw wrong_type();
      break;
    case Kind::text:
      if (auto s = node.value_exact<std::string>()) v.text = *s; else throw wrong_type();
      break;
    case Kind::number_list: {
      const toml::array* array = node.as_array();
      if (!array) throw wrong_type();
      for (const toml::node& element : *array) {
        double x = 0;
        if (!as_number(element, x)) throw wrong_type();
        v.list.push_back(x);
      }
      break;
    }
    case Kind::constant: {
      auto scalar = [&](const toml::node& n) -> MacroScalar {
        if (auto i = n.value_exact<int64_t>()) return static_cast<long long>(*i);
        if (auto d = n.value_exact<double>()) return *d;
        if (auto b = n.value_exact<bool>()) return *b;
        if (auto t = n.value_exact<std::string>()) return *t;
        throw wrong_type();
      };
      if (const toml::array* array = node.as_array()) {
        std::vector<MacroScalar> values;
        for (const toml::node& element : *array) values.push_back(scalar(element));
        if (values.empty()) throw wrong_type();
        v.constant = macro_vector(std::move(values));
      } else {
        v.constant = macro_scalar(scalar(node));
      }
      break;
    }
    case Kind::box_list: {
      const toml::array* array = node.as_array();
      if (!array) throw wrong_type();
      for (const toml::node& element : *array) {
        const toml::array* box = element.as_array();
        if (!box || box->size() != 6) throw wrong_type();
        SupportBoxMm b{};
        for (std::size_t i = 0; i < 6; ++i) {
          if (!as_number((*box)[i], b[i])) throw wrong_type();
        }
        v.boxes.push_back(b);
      }
      break;
    }
  }
  return v;
}

bool parse_double(std::string_view text, double& out) {
  const std::string s(text);
  if (s.empty()) return false;
  char* end = nullptr;
  out = std::strtod(s.c_str(), &end);
  return end == s.c_str() + s.size();
}

// A whole number, all of `text`.
std::optional<long long> whole_number(std::string_view text) {
  long long i = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), i);
  if (text.empty() || ec != std::errc() || end != text.data() + text.size()) return std::nullopt;
  return i;
}

// A placeholder's value typed on the command line: a number if it reads as one, else the text.
MacroVariable constant_from_text(std::string_view text) {
  double x = 0;
  if (const std::optional<long long> i = whole_number(text)) return macro_scalar(*i);
  if (parse_double(text, x)) return macro_scalar(x);
  return macro_scalar(std::string(text));
}

// "\n" typed on a command line means a line break in G-code.
std::string with_line_breaks(std::string_view text) {
  std::string s;
  for (std::size_t at = 0; at < text.size(); ++at) {
    if (text.substr(at, 2) == "\\n") {
      s += '\n';
      ++at;
    } else {
      s += text[at];
    }
  }
  return s;
}

// "a,b,c" or "[a,b,c]" (`text` trimmed), each a number; nothing when one is not. Empty text
// is an empty list.
std::optional<std::vector<double>> numbers_from_text(std::string_view text) {
  if (!text.empty() && text.front() == '[' && text.back() == ']') text = text.substr(1, text.size() - 2);
  std::vector<double> numbers;
  while (!text.empty()) {
    const std::size_t comma = text.find(',');
    double x = 0;
    if (!parse_double(trim(text.substr(0, comma)), x)) return std::nullopt;
    numbers.push_back(x);
    if (comma == std::string_view::npos) break;
    text.remove_prefix(comma + 1);
  }
  return numbers;
}

// "x0,y0,z0,x1,y1,z1;x0,..." (each box may be in brackets); an empty value or "none" is no
// boxes; nothing when a box is not six numbers.
std::optional<std::vector<SupportBoxMm>> boxes_from_text(std::string_view text) {
  if (text == "none") text = {};
  std::vector<SupportBoxMm> boxes;
  while (!text.empty()) {
    const std::size_t semicolon = text.find(';');
    const std::optional<std::vector<double>> numbers = numbers_from_text(trim(text.substr(0, semicolon)));
    if (!numbers || numbers->size() != 6) return std::nullopt;
    SupportBoxMm b{};
    std::copy(numbers->begin(), numbers->end(), b.begin());
    boxes.push_back(b);
    if (semicolon == std::string_view::npos) break;
    text.remove_prefix(semicolon + 1);
  }
  return boxes;
}

// Converts a --set value typed on the command line to the rule's kind.
template <class Target>
Value value_from_text(const Rule<Target>& rule, std::string_view text, const std::string& where) {
  Value v;
  auto wrong = [&]() {
    return ConfigError(fmt::format("{}: key '{}' must be {}", where, rule.key, describe(rule)));
  };
  text = trim(text);
  switch (rule.kind) {
    case Kind::number:
      if (!parse_double(text, v.number)) throw wrong();
      break;
    case Kind::integer: {
      const std::optional<long long> i = whole_number(text);
      if (!i) throw wrong();
      v.integer = *i;
      break;
    }
    case Kind::boolean:
      if (text == "true") v.flag = true;
      else if (text == "false") v.flag = false;
      else throw wrong();
      break;
    case Kind::constant: v.constant = constant_from_text(text); break;
    case Kind::text: v.text = with_line_breaks(text); break;
    case Kind::number_list: {
      std::optional<std::vector<double>> numbers = numbers_from_text(text);
      if (!numbers || numbers->empty()) throw wrong();
      v.list = std::move(*numbers);
      break;
    }
    case Kind::box_list: {
      std::optional<std::vector<SupportBoxMm>> boxes = boxes_from_text(text);
      if (!boxes) throw wrong();
      v.boxes = std::move(*boxes);
      break;
    }
  }
  return v;
}

// ---------------------------------------------------------------------------------------------
// The rules.

template <class Target>
Rule<Target> number(std::string_view key, double min, double max, std::string_view unit,
                    std::function<void(Target&, double)> set, bool required = false) {
  Rule<Target> r;
  r.key = key; r.kind = Kind::number; r.min = min; r.max = max; r.unit = unit;
  r.required = required;
  r.apply = [set](Target& t, const Value& v) { set(t, v.number); };
  return r;
}

template <class Target>
Rule<Target> integer(std::string_view key, double min, double max, std::string_view unit,
                     std::function<void(Target&, int)> set) {
  Rule<Target> r;
  r.key = key; r.kind = Kind::integer; r.min = min; r.max = max; r.unit = unit;
  r.apply = [set](Target& t, const Value& v) { set(t, static_cast<int>(v.integer)); };
  return r;
}

template <class Target>
Rule<Target> text(std::string_view key, std::vector<std::string_view> choices,
                  std::function<void(Target&, const std::string&)> set, bool required = false) {
  Rule<Target> r;
  r.key = key; r.kind = Kind::text; r.choices = std::move(choices); r.required = required;
  r.apply = [set](Target& t, const Value& v) { set(t, v.text); };
  return r;
}

template <class Target>
Rule<Target> boolean(std::string_view key, std::function<void(Target&, bool)> set) {
  Rule<Target> r;
  r.key = key; r.kind = Kind::boolean;
  r.apply = [set](Target& t, const Value& v) { set(t, v.flag); };
  return r;
}

template <class Target>
Rule<Target> boxes(std::string_view key, std::function<void(Target&, const std::vector<SupportBoxMm>&)> set) {
  Rule<Target> r;
  r.key = key; r.kind = Kind::box_list; r.unit = "mm";
  r.apply = [set](Target& t, const Value& v) { set(t, v.boxes); };
  return r;
}

using P = PrinterProfile;
using M = MaterialProfile;

const Rules<P>& printer_rules() {
  static const Rules<P> rules = [] {
    Rules<P> r;
    r.push_back(text<P>("name", {}, [](P& p, const std::string& s) { p.name = s; }, true));
    r.push_back(text<P>("material", {}, [](P& p, const std::string& s) { p.default_material = s; }));
    r.push_back(text<P>("firmware", {"marlin", "teacup", "repetier"},
                        [](P& p, const std::string& s) { p.firmware = *parse_firmware(s); }));
    r.push_back(number<P>("build_volume.x", 10, 2000, "mm", [](P& p, double v) { p.bed_x = v; }, true));
    r.push_back(number<P>("build_volume.y", 10, 2000, "mm", [](P& p, double v) { p.bed_y = v; }, true));
    r.push_back(number<P>("build_volume.z", 10, 2000, "mm", [](P& p, double v) { p.bed_z = v; }, true));
    r.push_back(number<P>("build_volume.origin_x", -2000, 2000, "mm (the G-code's X of the front left corner)",
                          [](P& p, double v) { p.bed_origin_x = v; }));
    r.push_back(number<P>("build_volume.origin_y", -2000, 2000, "mm (the G-code's Y of the front left corner)",
                          [](P& p, double v) { p.bed_origin_y = v; }));
    r.push_back(text<P>("build_volume.shape", {"rectangle", "circle"},
                        [](P& p, const std::string& s) { p.round_bed = s == "circle"; }));
    r.push_back(number<P>("nozzle.diameter", 0.1, 2.0, "mm",
                          [](P& p, double v) { p.nozzle_diameter = v; }, true));
    r.push_back(integer<P>("nozzle.count", 1, 16, "extruders (mahost prints with the first)",
                           [](P& p, int v) { p.extruders = v; }));
    r.push_back(number<P>("filament.diameter", 1.0, 3.5, "mm",
                          [](P& p, double v) { p.filament_diameter = v; }, true));
    r.push_back(number<P>("extrusion.width", 0.1, 3.0, "mm",
                          [](P& p, double v) { p.extrusion_width = v; }));
    r.push_back(text<P>("extrusion.e_mode", {"absolute", "relative"},
                        [](P& p, const std::string& s) { p.relative_e = s == "relative"; }));
    {
      Rule<P> list;
      list.key = "layer.allowed"; list.kind = Kind::number_list; list.min = 0.01; list.max = 2.0;
      list.unit = "mm";
      list.apply = [](P& p, const Value& v) {
        p.layer.allowed = v.list;
        std::sort(p.layer.allowed.begin(), p.layer.allowed.end());
      };
      r.push_back(list);
    }
    r.push_back(number<P>("layer.min", 0.01, 2.0, "mm", [](P& p, double v) { p.layer.min = v; }));
    r.push_back(number<P>("layer.max", 0.01, 2.0, "mm", [](P& p, double v) { p.layer.max = v; }));
    r.push_back(number<P>("layer.step", 0, 1.0, "mm (0: any)", [](P& p, double v) { p.layer.step = v; }));
    r.push_back(number<P>("layer.default", 0.01, 2.0, "mm",
                          [](P& p, double v) { p.layer.default_thickness = v; }));
    r.push_back(number<P>("first_layer.height", 0.01, 2.0, "mm",
                          [](P& p, double v) { p.first_layer_height = v; }));
    r.push_back(number<P>("first_layer.width", 0.1, 3.0, "mm",
                          [](P& p, double v) { p.first_layer_width = v; }));
    r.push_back(number<P>("first_layer.speed", 1, 300, "mm/s",
                          [](P& p, double v) { p.first_layer_speed = v; }));
    static const std::string speed_keys[] = {"motion.max_speed_x", "motion.max_speed_y",
                                             "motion.max_speed_z", "motion.max_speed_e"};
    static const std::string accel_keys[] = {"motion.max_acceleration_x", "motion.max_acceleration_y",
                                             "motion.max_acceleration_z", "motion.max_acceleration_e"};
    for (int axis = 0; axis < 4; ++axis) {
      r.push_back(number<P>(speed_keys[axis], 0.1, 2000, "mm/s",
                            [axis](P& p, double v) { p.motion.max_speed[axis] = v; }));
      r.push_back(number<P>(accel_keys[axis], 1, 100000, "mm/s^2",
                            [axis](P& p, double v) { p.motion.max_acceleration[axis] = v; }));
    }
    r.push_back(number<P>("motion.print_acceleration", 1, 100000, "mm/s^2",
                          [](P& p, double v) { p.motion.print_acceleration = v; }));
    r.push_back(number<P>("motion.travel_acceleration", 1, 100000, "mm/s^2",
                          [](P& p, double v) { p.motion.travel_acceleration = v; }));
    r.push_back(number<P>("motion.retract_acceleration", 1, 100000, "mm/s^2",
                          [](P& p, double v) { p.motion.retract_acceleration = v; }));
    r.push_back(number<P>("motion.junction_deviation", 0.001, 0.5, "mm",
                          [](P& p, double v) { p.motion.junction_deviation = v; }));
    r.push_back(number<P>("motion.min_feedrate", 0, 100, "mm/s",
                          [](P& p, double v) { p.motion.min_feedrate = v; }));
    struct SpeedKey { std::string_view key; double FeatureSpeeds::*field; };
    static const SpeedKey speeds[] = {
        {"speed.outer_wall", &FeatureSpeeds::outer_wall}, {"speed.inner_wall", &FeatureSpeeds::inner_wall},
        {"speed.thin_wall", &FeatureSpeeds::thin_wall}, {"speed.skirt", &FeatureSpeeds::skirt},
        {"speed.top_skin", &FeatureSpeeds::top_skin}, {"speed.bottom_skin", &FeatureSpeeds::bottom_skin},
        {"speed.solid_infill", &FeatureSpeeds::solid_infill},
        {"speed.sparse_infill", &FeatureSpeeds::sparse_infill},
        {"speed.support", &FeatureSpeeds::support},
        {"speed.support_interface", &FeatureSpeeds::support_interface},
        {"speed.bridge", &FeatureSpeeds::bridge}, {"speed.brim", &FeatureSpeeds::brim},
        {"speed.raft", &FeatureSpeeds::raft},
        {"speed.travel", &FeatureSpeeds::travel}, {"speed.z", &FeatureSpeeds::z}};
    for (const SpeedKey& s : speeds) {
      const auto field = s.field;
      r.push_back(number<P>(s.key, 1, 1000, "mm/s", [field](P& p, double v) { p.speed.*field = v; }));
    }
    r.push_back(number<P>("retraction.length", 0, 20, "mm", [](P& p, double v) { p.retraction.length = v; }));
    r.push_back(number<P>("retraction.speed", 1, 200, "mm/s", [](P& p, double v) { p.retraction.speed = v; }));
    r.push_back(number<P>("retraction.prime_speed", 1, 200, "mm/s",
                          [](P& p, double v) { p.retraction.prime_speed = v; }));
    r.push_back(number<P>("retraction.min_travel", 0, 100, "mm",
                          [](P& p, double v) { p.retraction.min_travel = v; }));
    r.push_back(number<P>("retraction.z_hop", 0, 10, "mm", [](P& p, double v) { p.retraction.z_hop = v; }));
    r.push_back(integer<P>("print.perimeters", 0, 50, "", [](P& p, int v) { p.print.perimeters = v; }));
    r.push_back(number<P>("print.infill_density", 0, 100, "%",
                          [](P& p, double v) { p.print.infill_density = v; }));
    r.push_back(text<P>("print.infill_pattern", {"grid", "rectilinear"},
                        [](P& p, const std::string& s) { p.print.infill_pattern = s; }));
    r.push_back(integer<P>("print.top_layers", 0, 100, "", [](P& p, int v) { p.print.top_layers = v; }));
    r.push_back(integer<P>("print.bottom_layers", 0, 100, "", [](P& p, int v) { p.print.bottom_layers = v; }));
    r.push_back(number<P>("print.top_thickness", 0, 20, "mm (0: no minimum)",
                          [](P& p, double v) { p.print.top_thickness = v; }));
    r.push_back(number<P>("print.bottom_thickness", 0, 20, "mm (0: no minimum)",
                          [](P& p, double v) { p.print.bottom_thickness = v; }));
    r.push_back(integer<P>("print.skirt_loops", 0, 20, "", [](P& p, int v) { p.print.skirt_loops = v; }));
    r.push_back(number<P>("print.skirt_distance", 0, 50, "mm",
                          [](P& p, double v) { p.print.skirt_distance = v; }));
    r.push_back(text<P>("print.seam", {"aligned", "nearest"},
                        [](P& p, const std::string& s) { p.print.seam = s; }));
    // Supports, brim and raft.
    r.push_back(text<P>("support.type", {"none", "buildplate", "everywhere"},
                        [](P& p, const std::string& s) { p.support.type = s; }));
    r.push_back(number<P>("support.xy_gap", 0, 10, "mm", [](P& p, double v) { p.support.xy_gap = v; }));
    r.push_back(number<P>("support.top_contact_distance", 0, 2, "mm",
                          [](P& p, double v) { p.support.top_contact_distance = v; }));
    r.push_back(number<P>("support.bottom_contact_distance", 0, 2, "mm",
                          [](P& p, double v) { p.support.bottom_contact_distance = v; }));
    r.push_back(number<P>("support.interface_thickness", 0, 5, "mm",
                          [](P& p, double v) { p.support.interface_thickness = v; }));
    r.push_back(number<P>("support.interface_density", 10, 100, "%",
                          [](P& p, double v) { p.support.interface_density = v; }));
    r.push_back(text<P>("support.pattern", {"lines", "grid"},
                        [](P& p, const std::string& s) { p.support.pattern = s; }));
    r.push_back(boolean<P>("support.sheath", [](P& p, bool v) { p.support.sheath = v; }));
    r.push_back(number<P>("support.spacing", 0.5, 20, "mm", [](P& p, double v) { p.support.spacing = v; }));
    r.push_back(number<P>("support.angle", -360, 360, "degrees", [](P& p, double v) { p.support.angle = v; }));
    r.push_back(number<P>("support.min_area", 0, 100, "mm^2", [](P& p, double v) { p.support.min_area = v; }));
    r.push_back(boxes<P>("support.enforcers", [](P& p, const std::vector<SupportBoxMm>& b) { p.support.enforcers = b; }));
    r.push_back(boxes<P>("support.blockers", [](P& p, const std::vector<SupportBoxMm>& b) { p.support.blockers = b; }));
    r.push_back(number<P>("brim.width", 0, 50, "mm", [](P& p, double v) { p.brim_width = v; }));
    r.push_back(boolean<P>("raft.enabled", [](P& p, bool v) { p.raft.enabled = v; }));
    r.push_back(number<P>("raft.margin", 0, 30, "mm", [](P& p, double v) { p.raft.margin = v; }));
    r.push_back(number<P>("raft.air_gap", 0, 1, "mm", [](P& p, double v) { p.raft.air_gap = v; }));
    r.push_back(number<P>("raft.base_thickness", 0.05, 2, "mm", [](P& p, double v) { p.raft.base_thickness = v; }));
    r.push_back(number<P>("raft.base_width", 0.1, 3, "mm", [](P& p, double v) { p.raft.base_width = v; }));
    r.push_back(number<P>("raft.base_spacing", 0.2, 10, "mm", [](P& p, double v) { p.raft.base_spacing = v; }));
    r.push_back(integer<P>("raft.interface_layers", 0, 10, "", [](P& p, int v) { p.raft.interface_layers = v; }));
    r.push_back(number<P>("raft.interface_spacing", 0.2, 10, "mm",
                          [](P& p, double v) { p.raft.interface_spacing = v; }));
    r.push_back(integer<P>("raft.surface_layers", 0, 10, "", [](P& p, int v) { p.raft.surface_layers = v; }));
    r.push_back(number<P>("raft.layer_thickness", 0.05, 2, "mm",
                          [](P& p, double v) { p.raft.layer_thickness = v; }));
    r.push_back(text<P>("gcode.start", {}, [](P& p, const std::string& s) { p.start_gcode = s; }));
    r.push_back(text<P>("gcode.end", {}, [](P& p, const std::string& s) { p.end_gcode = s; }));
    r.push_back(number<P>("gcode.resolution", 0, 0.1, "mm", [](P& p, double v) { p.resolution = v; }));
    r.push_back(text<P>("gcode.syntax", {"mahost", "prusaslicer"}, [](P& p, const std::string& s) {
      p.gcode_syntax = s == "prusaslicer" ? GcodeSyntax::prusaslicer : GcodeSyntax::mahost;
    }));
    {
      Rule<P> constants;
      constants.key = "gcode.constants"; constants.kind = Kind::constant; constants.table = true;
      constants.apply = [](P& p, const Value& v) { p.gcode_constants[v.name] = v.constant; };
      r.push_back(constants);
    }
    {
      Rule<P> baud;
      baud.key = "serial.baud"; baud.kind = Kind::integer; baud.min = 1200; baud.max = 4000000;
      baud.unit = "baud";
      baud.apply = [](P& p, const Value& v) { p.baud = static_cast<int>(v.integer); };
      r.push_back(baud);
    }
    return r;
  }();
  return rules;
}

const Rules<M>& material_rules() {
  static const Rules<M> rules = [] {
    Rules<M> r;
    r.push_back(text<M>("name", {}, [](M& m, const std::string& s) { m.name = s; }, true));
    r.push_back(text<M>("type", {}, [](M& m, const std::string& s) { m.type = s; }));
    r.push_back(number<M>("temperature.nozzle", 0, 350, "C",
                          [](M& m, double v) { m.nozzle_temperature = v; }, true));
    r.push_back(number<M>("temperature.first_layer_nozzle", 0, 350, "C",
                          [](M& m, double v) { m.first_layer_nozzle_temperature = v; }));
    r.push_back(number<M>("temperature.bed", 0, 150, "C",
                          [](M& m, double v) { m.bed_temperature = v; }, true));
    r.push_back(number<M>("temperature.first_layer_bed", 0, 150, "C",
                          [](M& m, double v) { m.first_layer_bed_temperature = v; }));
    r.push_back(number<M>("fan.speed", 0, 100, "%", [](M& m, double v) { m.fan_speed = v; }));
    r.push_back(integer<M>("fan.start_layer", 0, 1000, "", [](M& m, int v) { m.fan_start_layer = v; }));
    r.push_back(number<M>("flow", 0.5, 1.5, "", [](M& m, double v) { m.flow = v; }));
    r.push_back(number<M>("density", 0.5, 3.0, "g/cm^3", [](M& m, double v) { m.density = v; }));
    r.push_back(number<M>("support.overhang_angle", 0, 89, "degrees from vertical",
                          [](M& m, double v) { m.overhang_angle = v; }));
    r.push_back(number<M>("bridge.max_length", 0, 200, "mm", [](M& m, double v) { m.bridge_length = v; }));
    r.push_back(number<M>("bridge.flow", 0.5, 1.5, "", [](M& m, double v) { m.bridge_flow = v; }));
    r.push_back(number<M>("bridge.fan", 0, 100, "%", [](M& m, double v) { m.bridge_fan = v; }));
    return r;
  }();
  return rules;
}

template <class Target>
const Rule<Target>* find_rule(const Rules<Target>& rules, std::string_view key) {
  for (const Rule<Target>& rule : rules) {
    if (rule.key == key && !rule.table) return &rule;
    if (rule.table && key.size() > rule.key.size() + 1 && key.starts_with(rule.key) &&
        key[rule.key.size()] == '.') {
      return &rule;
    }
  }
  return nullptr;
}

// A table rule's value knows its own name: the key after the table's ("printer_model").
template <class Target>
void name_value(const Rule<Target>& rule, std::string_view key, Value& v) {
  if (rule.table) v.name = std::string(key.substr(rule.key.size() + 1));
}

// Keys an earlier mahost read and what took their place, for a profile written for it.
struct RenamedKey {
  std::string_view old_key, now;
};
constexpr RenamedKey kRenamedKeys[] = {
    {"support.interface_layers",
     "'support.interface_thickness', in mm (0.4 for the old 2 layers at 0.2 mm)"},
};

// "unknown key 'speed.outer_wal'; keys under 'speed': outer_wall, inner_wall, ..." so that a
// typo is one glance from its fix; a renamed key says what it is now.
template <class Target>
std::string unknown_key_message(const Rules<Target>& rules, std::string_view key,
                                const std::string& where) {
  for (const RenamedKey& renamed : kRenamedKeys) {
    if (key == renamed.old_key) {
      return fmt::format("{}: unknown key '{}': it is now {}", where, key, renamed.now);
    }
  }
  const std::size_t dot = key.rfind('.');
  const std::string_view section = dot == std::string_view::npos ? "" : key.substr(0, dot);
  std::vector<std::string_view> siblings;
  std::set<std::string_view> sections;
  for (const Rule<Target>& rule : rules) {
    const std::size_t rule_dot = rule.key.rfind('.');
    const std::string_view rule_section =
        rule_dot == std::string_view::npos ? "" : rule.key.substr(0, rule_dot);
    sections.insert(rule_section.empty() ? rule.key : rule_section);
    if (rule_section == section) siblings.push_back(rule.key.substr(rule_dot + 1));
  }
  if (!siblings.empty()) {
    return fmt::format("{}: unknown key '{}'; keys {}: {}", where, key,
                       section.empty() ? "at the top" : fmt::format("under '{}'", section),
                       fmt::join(siblings, ", "));
  }
  return fmt::format("{}: unknown key '{}'; known sections and keys: {}", where, key,
                     fmt::join(sections, ", "));
}

void flatten(const toml::table& table, const std::string& prefix,
             std::vector<std::pair<std::string, const toml::node*>>& leaves) {
  for (const auto& [name, node] : table) {
    const std::string key = prefix.empty() ? std::string(name.str())
                                           : prefix + "." + std::string(name.str());
    if (const toml::table* inner = node.as_table()) {
      flatten(*inner, key, leaves);
    } else {
      leaves.emplace_back(key, &node);
    }
  }
}

template <class Target>
void apply_table(Target& target, const Rules<Target>& rules, std::string_view toml_text,
                 const std::string& source) {
  toml::table table;
  try {
    table = toml::parse(toml_text, source);
  } catch (const toml::parse_error& e) {
    throw ConfigError(fmt::format("{}:{}:{}: not valid TOML: {}", source, e.source().begin.line,
                                  e.source().begin.column, e.description()));
  }
  std::vector<std::pair<std::string, const toml::node*>> leaves;
  flatten(table, "", leaves);
  std::set<std::string_view> seen;
  for (const auto& [key, node] : leaves) {
    const std::string where = fmt::format("{}:{}", source, node->source().begin.line);
    const Rule<Target>* rule = find_rule(rules, key);
    if (!rule) throw ConfigError(unknown_key_message(rules, key, where));
    Value v = value_from_node(*rule, *node, where);
    name_value(*rule, key, v);
    check_value(*rule, v, where);
    rule->apply(target, v);
    seen.insert(rule->key);
  }
  for (const Rule<Target>& rule : rules) {
    if (rule.required && !seen.count(rule.key)) {
      throw ConfigError(fmt::format("{}: key '{}' is missing; it must be {}", source, rule.key,
                                    describe(rule)));
    }
  }
}

std::string format_number(double v) { return fmt::format("{:g}", v); }

// Checks that only make sense for the profile as a whole.
void check_printer(const PrinterProfile& p) {
  const std::string& where = p.source;
  const LayerThicknesses& layer = p.layer;
  if (layer.allowed.empty()) {
    if (layer.min > layer.max) {
      throw ConfigError(fmt::format("{}: layer.min ({} mm) is above layer.max ({} mm)", where,
                                    layer.min, layer.max));
    }
  }
  if (!layer.allows(layer.default_thickness)) {
    throw ConfigError(fmt::format("{}: layer.default = {} mm is not a layer thickness this "
                                  "printer allows ({})", where, layer.default_thickness,
                                  layer.describe()));
  }
  if (!layer.allows(p.first_layer_height)) {
    throw ConfigError(fmt::format("{}: first_layer.height = {} mm is not a layer thickness this "
                                  "printer allows ({})", where, p.first_layer_height,
                                  layer.describe()));
  }
  // The bead model (bead_model.h) is a rounded rectangle: a bead at least as wide as it is tall.
  const double tallest = layer.allowed.empty() ? layer.max : layer.allowed.back();
  if (p.extrusion_width < tallest) {
    throw ConfigError(fmt::format("{}: extrusion.width = {} mm is narrower than the tallest layer "
                                  "({} mm); widen it or lower the layer limit", where,
                                  p.extrusion_width, tallest));
  }
  if (p.raft.enabled) {
    for (const auto& [key, thickness] : {std::pair{"raft.base_thickness", p.raft.base_thickness},
                                         std::pair{"raft.layer_thickness", p.raft.layer_thickness}}) {
      if (!layer.allows(thickness)) {
        throw ConfigError(fmt::format("{}: {} = {} mm is not a layer thickness this printer "
                                      "allows ({})", where, key, thickness, layer.describe()));
      }
    }
    if (p.raft.base_width < p.raft.base_thickness) {
      throw ConfigError(fmt::format("{}: raft.base_width = {} mm is narrower than "
                                    "raft.base_thickness = {} mm", where, p.raft.base_width,
                                    p.raft.base_thickness));
    }
  }
  if (p.round_bed && std::abs(p.bed_x - p.bed_y) > 1e-6) {
    throw ConfigError(fmt::format("{}: build_volume.shape = \"circle\" needs x = y (the circle's "
                                  "diameter), not {} and {} mm", where, p.bed_x, p.bed_y));
  }
  if (p.first_layer_width < p.first_layer_height) {
    throw ConfigError(fmt::format("{}: first_layer.width = {} mm is narrower than "
                                  "first_layer.height = {} mm", where, p.first_layer_width,
                                  p.first_layer_height));
  }
}

void check_gcode_placeholders(const Profiles& profiles) {
  expand_placeholders(profiles.printer.start_gcode, profiles, {}, "gcode.start");
  expand_placeholders(profiles.printer.end_gcode, profiles, {}, "gcode.end");
}

std::string read_text_file(const std::string& path, std::string_view what) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    throw ConfigError(fmt::format("cannot read {} profile '{}': {}", what, path,
                                  std::filesystem::exists(path) ? "permission denied"
                                                                : "no such file"));
  }
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// A profile given as a file rather than a name: a .toml, or an existing file's path.
bool looks_like_path(const std::string& s) {
  if (s.size() > 5 && s.compare(s.size() - 5, 5, ".toml") == 0) return true;
  std::error_code ec;
  return s.find('/') != std::string::npos && std::filesystem::is_regular_file(s, ec);
}

std::vector<std::string> split_search_path(const std::string& config_dir) {
  std::vector<std::string> dirs;
  std::string_view rest = config_dir;
  while (true) {
    const std::size_t colon = rest.find(':');
    const std::string_view dir = rest.substr(0, colon);
    if (!dir.empty()) dirs.emplace_back(dir);
    if (colon == std::string_view::npos) break;
    rest.remove_prefix(colon + 1);
  }
  return dirs;
}

std::string resolve_profile(const std::string& name_or_path, const std::string& config_dir,
                            std::string_view kind, std::string_view what) {
  if (looks_like_path(name_or_path)) return name_or_path;
  const std::vector<std::string> dirs = split_search_path(config_dir);
  for (const std::string& stem : {name_or_path, profile_file_stem(name_or_path)}) {
    for (const std::string& dir : dirs) {
      const std::string path = dir + "/" + std::string(kind) + "/" + stem + ".toml";
      std::error_code ec;
      if (std::filesystem::is_regular_file(path, ec)) return path;
    }
  }
  std::vector<std::string> folders;
  for (const std::string& dir : dirs) folders.push_back(dir + "/" + std::string(kind));
  const std::vector<std::string> names = available_profiles(config_dir, kind);
  throw ConfigError(fmt::format("{} profile '{}' not found in {} (available: {}); give one of these "
                                "names or a path to a .toml file", what, name_or_path,
                                fmt::join(folders, ", "),
                                names.empty() ? "none" : fmt::format("{}", fmt::join(names, ", "))));
}

template <class Target>
void apply_assignment(Target& target, const Rules<Target>& rules, std::string_view key,
                      std::string_view value, const std::string& where) {
  const Rule<Target>* rule = find_rule(rules, key);
  if (!rule) throw ConfigError(unknown_key_message(rules, key, where));
  Value v = value_from_text(*rule, value, where);
  name_value(*rule, key, v);
  check_value(*rule, v, where);
  rule->apply(target, v);
}

}  // namespace

// ---------------------------------------------------------------------------------------------

bool LayerThicknesses::allows(double thickness) const {
  constexpr double kTolerance = 1e-6;
  if (!std::isfinite(thickness)) return false;
  if (!allowed.empty()) {
    return std::any_of(allowed.begin(), allowed.end(),
                       [&](double a) { return std::abs(a - thickness) <= kTolerance; });
  }
  if (thickness < min - kTolerance || thickness > max + kTolerance) return false;
  if (step <= 0) return true;
  const double steps = (thickness - min) / step;
  return std::abs(steps - std::round(steps)) * step <= kTolerance;
}

std::string LayerThicknesses::describe() const {
  std::vector<std::string> values;
  if (!allowed.empty()) {
    for (double a : allowed) values.push_back(format_number(a));
  } else if (step > 0 && (max - min) / step <= 20) {
    for (int k = 0; min + k * step <= max + 1e-9; ++k) values.push_back(format_number(min + k * step));
  } else if (step > 0) {
    return fmt::format("{} to {} mm in steps of {} mm", format_number(min), format_number(max),
                       format_number(step));
  } else {
    return fmt::format("{} to {} mm", format_number(min), format_number(max));
  }
  return fmt::format("{} mm", fmt::join(values, ", "));
}

namespace {

// $NAME if it is set to an absolute path (the XDG base directory rules ignore relative ones).
std::optional<std::string> absolute_from_environment(const char* name) {
  const char* value = std::getenv(name);
  if (!value || value[0] != '/') return std::nullopt;
  return std::string(value);
}

}  // namespace

std::string user_config_directory() {
  if (const auto xdg = absolute_from_environment("XDG_CONFIG_HOME")) return *xdg + "/mahost";
  if (const auto home = absolute_from_environment("HOME")) return *home + "/.config/mahost";
  return ".config/mahost";
}

std::string config_directory(const std::string& installed) {
  if (const char* env = std::getenv("MAHOST_CONFIG_DIR"); env && *env) return env;
  std::vector<std::string> dirs{user_config_directory()};
  // $XDG_CONFIG_DIRS: the system's folders, most important first (default /etc/xdg).
  const char* system = std::getenv("XDG_CONFIG_DIRS");
  for (const std::string& dir : split_search_path(system && *system ? system : "/etc/xdg")) {
    if (dir.front() == '/') dirs.push_back(dir + "/mahost");
  }
  if (!installed.empty()) dirs.push_back(installed);
  return fmt::format("{}", fmt::join(dirs, ":"));
}

std::string profile_file_stem(std::string_view name) {
  std::string stem;
  for (const char c : name) {
    const auto u = static_cast<unsigned char>(c);
    if (std::isalnum(u) || c == '.' || c == '+' || c == '_' || u >= 0x80) {
      stem += static_cast<char>(std::tolower(u));
    } else if (!stem.empty() && stem.back() != '-') {
      stem += '-';
    }
  }
  while (!stem.empty() && (stem.back() == '-' || stem.back() == '.')) stem.pop_back();
  while (!stem.empty() && stem.front() == '.') stem.erase(stem.begin());
  return stem;
}

std::vector<ProfileFile> find_profiles(const std::string& config_dir, std::string_view kind) {
  std::vector<ProfileFile> found;
  std::set<std::string> seen;
  for (const std::string& dir : split_search_path(config_dir)) {
    std::vector<ProfileFile> here;
    std::error_code ec;
    for (const auto& entry :
         std::filesystem::directory_iterator(dir + "/" + std::string(kind), ec)) {
      if (entry.path().extension() != ".toml") continue;
      const std::string id = entry.path().stem().string();
      if (!seen.count(id)) here.push_back({id, entry.path().string()});
    }
    for (const ProfileFile& f : here) seen.insert(f.id);
    found.insert(found.end(), here.begin(), here.end());
  }
  std::sort(found.begin(), found.end(),
            [](const ProfileFile& a, const ProfileFile& b) { return a.id < b.id; });
  return found;
}

std::vector<std::string> available_profiles(const std::string& config_dir, std::string_view kind) {
  std::vector<std::string> names;
  for (const ProfileFile& f : find_profiles(config_dir, kind)) names.push_back(f.id);
  return names;
}

PrinterProfile parse_printer_profile(std::string_view toml_text, const std::string& source) {
  PrinterProfile p;
  p.source = source;
  apply_table(p, printer_rules(), toml_text, source);
  check_printer(p);
  Profiles both{p, MaterialProfile{}};
  check_gcode_placeholders(both);
  return p;
}

MaterialProfile parse_material_profile(std::string_view toml_text, const std::string& source) {
  MaterialProfile m;
  m.source = source;
  // First-layer temperatures default to the regular ones when a profile leaves them out.
  m.first_layer_nozzle_temperature = -1;
  m.first_layer_bed_temperature = -1;
  apply_table(m, material_rules(), toml_text, source);
  if (m.type.empty()) m.type = m.name;
  if (m.first_layer_nozzle_temperature < 0) m.first_layer_nozzle_temperature = m.nozzle_temperature;
  if (m.first_layer_bed_temperature < 0) m.first_layer_bed_temperature = m.bed_temperature;
  return m;
}

PrinterProfile load_printer_profile(const std::string& name_or_path, const std::string& config_dir) {
  const std::string path = resolve_profile(name_or_path, config_dir, "printers", "printer");
  return parse_printer_profile(read_text_file(path, "printer"), path);
}

MaterialProfile load_material_profile(const std::string& name_or_path, const std::string& config_dir) {
  const std::string path = resolve_profile(name_or_path, config_dir, "materials", "material");
  return parse_material_profile(read_text_file(path, "material"), path);
}

void apply_override(Profiles& profiles, std::string_view assignment) {
  const std::string where = fmt::format("--set {}", assignment);
  const std::size_t equals = assignment.find('=');
  if (equals == std::string_view::npos || equals == 0) {
    throw ConfigError(fmt::format("{}: expected key=value, e.g. --set retraction.length=1.5 or "
                                  "--set material.temperature.nozzle=245", where));
  }
  std::string_view key = trim(assignment.substr(0, equals));
  const std::string_view value = assignment.substr(equals + 1);
  if (key.starts_with("material.")) {
    key.remove_prefix(9);
    apply_assignment(profiles.material, material_rules(), key, value, where);
  } else {
    if (key.starts_with("printer.")) key.remove_prefix(8);
    apply_assignment(profiles.printer, printer_rules(), key, value, where);
  }
  try {
    check_printer(profiles.printer);
    check_gcode_placeholders(profiles);
  } catch (const ConfigError& e) {
    throw ConfigError(fmt::format("{} (after {})", e.what(), where));
  }
}

Profiles load_profiles(const ProfileRequest& request) {
  Profiles profiles;
  profiles.printer = load_printer_profile(request.printer, request.config_dir);
  const std::string material =
      request.material.empty() ? profiles.printer.default_material : request.material;
  profiles.material = load_material_profile(material, request.config_dir);
  for (const std::string& assignment : request.overrides) apply_override(profiles, assignment);
  check_gcode_placeholders(profiles);
  return profiles;
}

void check_layer_thickness(const PrinterProfile& printer, double thickness) {
  if (printer.layer.allows(thickness)) return;
  throw ConfigError(fmt::format("layer thickness {} mm is not allowed on the {} ({}); allowed: {}",
                                format_number(thickness), printer.name, printer.source,
                                printer.layer.describe()));
}

void check_layer_tops(const PrinterProfile& printer, std::span<const double> tops) {
  constexpr double kTolerance = 1e-6;
  double below = 0;
  for (std::size_t i = 0; i < tops.size(); ++i) {
    const double thickness = tops[i] - below;
    const bool first = i == 0;
    const bool fine = first ? std::abs(thickness - printer.first_layer_height) <= kTolerance
                            : printer.layer.allows(thickness);
    if (!fine) {
      throw ConfigError(fmt::format(
          "layer {} (z {:g} to {:g} mm) is {:g} mm thick, which the {} ({}) cannot print; "
          "allowed: {}",
          i + 1, below, tops[i], std::round(thickness * 1e6) / 1e6, printer.name, printer.source,
          first ? fmt::format("{:g} mm for the first layer (first_layer.height)",
                              printer.first_layer_height)
                : printer.layer.describe()));
    }
    below = tops[i];
  }
}

double bed_centre_x(const PrinterProfile& printer) { return printer.bed_origin_x + printer.bed_x / 2; }
double bed_centre_y(const PrinterProfile& printer) { return printer.bed_origin_y + printer.bed_y / 2; }

bool on_bed(const PrinterProfile& printer, double x, double y, double tolerance) {
  if (printer.round_bed) {
    const double dx = x - bed_centre_x(printer), dy = y - bed_centre_y(printer);
    return std::sqrt(dx * dx + dy * dy) <= printer.bed_x / 2 + tolerance;
  }
  return x >= printer.bed_origin_x - tolerance && x <= printer.bed_origin_x + printer.bed_x + tolerance &&
         y >= printer.bed_origin_y - tolerance && y <= printer.bed_origin_y + printer.bed_y + tolerance;
}

void check_part_fits(const PrinterProfile& printer, double size_x, double size_y, double size_z) {
  constexpr double kTolerance = 1e-6;
  if (size_x <= printer.bed_x + kTolerance && size_y <= printer.bed_y + kTolerance &&
      size_z <= printer.bed_z + kTolerance) {
    return;
  }
  throw ConfigError(fmt::format("the part is {:.1f} x {:.1f} x {:.1f} mm but the {} builds at most "
                                "{:g} x {:g} x {:g} mm; scale it down (--scale, --height) or "
                                "choose a bigger printer (--printer)", size_x, size_y, size_z,
                                printer.name, printer.bed_x, printer.bed_y, printer.bed_z));
}

double travel_lift(const PrinterProfile& printer) {
  return printer.retraction.length > 0 ? printer.retraction.z_hop : 0;
}

void check_layer_tops_fit(const PrinterProfile& printer, double part_z, double top_z,
                          double thickness, double raft) {
  constexpr double kTolerance = 1e-6;
  const double hop = travel_lift(printer);
  raft = std::max(raft, 0.0);
  if (top_z + raft + hop <= printer.bed_z + kTolerance) return;
  // A whole number of layers after the first, up to the build height less the hop.
  const double room = printer.bed_z - raft - hop - printer.first_layer_height;
  const double tallest =
      room >= 0 && thickness > 0
          ? printer.first_layer_height + std::floor(room / thickness + 1e-9) * thickness
          : 0;
  std::string lift;
  if (hop > 0) lift = fmt::format(" and travels lift {:g} mm more", hop);
  if (raft > 0) {
    throw ConfigError(fmt::format(
        "the part is {:.2f} mm tall, but on its {:.2f} mm raft its last layer of {:g} mm ends at "
        "{:.2f} mm{}, above the {}'s build height of {:g} mm; make the part at most {:.2f} mm "
        "tall (--height {:.2f}), print it without the raft (--no-raft), or choose a bigger "
        "printer (--printer)",
        part_z, raft, thickness, top_z + raft, lift, printer.name, printer.bed_z, tallest, tallest));
  }
  throw ConfigError(fmt::format(
      "the part is {:.2f} mm tall, but its last layer of {:g} mm ends at {:.2f} mm{}, above the "
      "{}'s build height of {:g} mm; make the part at most {:.2f} mm tall (--height {:.2f}), "
      "or choose a bigger printer (--printer)",
      part_z, thickness, top_z, lift, printer.name, printer.bed_z, tallest, tallest));
}

std::string expand_placeholders(std::string_view text, const Profiles& profiles,
                                const PlaceholderValues& values, std::string_view key) {
  const PrinterProfile& p = profiles.printer;
  if (p.gcode_syntax == GcodeSyntax::prusaslicer) {
    return expand_prusa_macro(text, prusa_variables(profiles, values), fmt::format("{}: {}", p.source, key),
                              "mahost evaluates PrusaSlicer's placeholders for the printer, the "
                              "material and the slice, and the printer's gcode.constants");
  }
  const MaterialProfile& m = profiles.material;
  struct Entry { std::string_view name; std::string value; };
  const Entry entries[] = {
      {"nozzle_temperature", format_number(m.nozzle_temperature)},
      {"first_layer_nozzle_temperature", format_number(m.first_layer_nozzle_temperature)},
      {"bed_temperature", format_number(m.bed_temperature)},
      {"first_layer_bed_temperature", format_number(m.first_layer_bed_temperature)},
      {"bed_x", format_number(p.bed_x)},
      {"bed_y", format_number(p.bed_y)},
      {"bed_z", format_number(p.bed_z)},
      {"nozzle_diameter", format_number(p.nozzle_diameter)},
      {"filament_diameter", format_number(p.filament_diameter)},
      {"layer_height", format_number(values.layer_height)},
      {"first_layer_height", format_number(p.first_layer_height)},
      {"fan_speed", fmt::format("{}", static_cast<int>(std::lround(m.fan_speed * 2.55)))},
      {"printer_name", p.name},
      {"material_name", m.name},
  };
  std::string out;
  out.reserve(text.size());
  for (std::size_t i = 0; i < text.size(); ++i) {
    if (text[i] != '{') {
      out += text[i];
      continue;
    }
    const std::size_t close = text.find('}', i);
    const std::string_view name =
        text.substr(i + 1, close == std::string_view::npos ? std::string_view::npos : close - i - 1);
    const Entry* found = nullptr;
    for (const Entry& e : entries) {
      if (close != std::string_view::npos && e.name == name) found = &e;
    }
    if (!found) {
      std::vector<std::string_view> names;
      for (const Entry& e : entries) names.push_back(e.name);
      throw ConfigError(fmt::format("{}: {}: unknown placeholder '{{{}}}'; known: {}", p.source, key,
                                    name, fmt::join(names, ", ")));
    }
    out += found->value;
    i = close;
  }
  return out;
}

}  // namespace printer
