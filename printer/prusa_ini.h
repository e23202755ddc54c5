// PrusaSlicer's .ini files as PrusaSlicer reads them: a vendor bundle (/usr/share/PrusaSlicer/
// profiles/*.ini) or a user's exported bundle, with [printer:NAME], [print:NAME] and
// [filament:NAME] sections inheriting from others, or an exported config.ini (one flat set of
// keys: a printer, a print and a filament together).
//
// Inheritance as PrusaSlicer's PresetBundle flattens it (src/libslic3r/PresetBundle.cpp,
// flatten_configbundle_hierarchy): `inherits = A; B` takes every key of A and B not set in the
// section itself, B's over A's (the last parent wins), each parent flattened first; names in
// asterisks (*common*) are abstract, never offered themselves. A vendor bundle's printer is
// concrete only with a printer_model its [printer_model:...] sections list. Values are
// PrusaSlicer's serialized text: strings C-escaped (\n, \", \\), optionally in quotes; vectors
// comma separated (floats, ints) or as quoted strings separated by ';'; percents with '%';
// bed shapes as XxY points.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace printer {

// One preset's keys after inheritance, with the preset's name.
struct PrusaPreset {
  std::string name;
  std::map<std::string, std::string, std::less<>> keys;  // raw values, as in the file

  // The raw value, or nullopt when the preset does not set the key.
  std::optional<std::string_view> raw(std::string_view key) const;
};

struct PrusaIni {
  bool is_bundle = false;        // sections; false: a flat config.ini
  bool is_vendor = false;        // has a [vendor] section: a vendor's bundle
  std::string vendor;            // [vendor] name
  std::vector<PrusaPreset> printers;  // concrete, flattened, in file order
  std::map<std::string, PrusaPreset, std::less<>> prints, filaments;  // concrete, flattened
  // Printer sections left out, with why: abstract ones are not listed.
  std::vector<std::pair<std::string, std::string>> skipped_printers;
};

// Parses and flattens. `name` names the file in errors (ConfigError: a line that is neither a
// section, a key = value nor a comment; an inheritance cycle).
PrusaIni read_prusa_ini(std::string_view text, const std::string& name);

// ---- values -------------------------------------------------------------------------------

// A string value: quotes taken off, C escapes undone (PrusaSlicer's unescape_string_cstyle).
std::string prusa_string(std::string_view raw);

// A vector of strings ("a";"b", or a;b): each unescaped.
std::vector<std::string> prusa_strings(std::string_view raw);

// Numbers: one, or a comma separated vector (each optionally ending in '%'). nullopt when the
// text is not numbers.
struct PrusaNumber {
  double value = 0;
  bool percent = false;
};
std::optional<std::vector<PrusaNumber>> prusa_numbers(std::string_view raw);

// A bed shape or another list of points: "0x0,250x0,250x210,0x210".
struct PrusaPoint {
  double x = 0, y = 0;
};
std::optional<std::vector<PrusaPoint>> prusa_points(std::string_view raw);

}  // namespace printer
