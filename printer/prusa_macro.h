// PrusaSlicer's G-code macro language, for the start and end G-code of printers imported from
// PrusaSlicer (prusa_import.h): what its PlaceholderParser (src/libslic3r/PlaceholderParser.cpp)
// accepts in custom G-code, evaluated the same way.
//
// The text is copied as it is but for:
//  - [name], [name_N], [name[index_name]]: the legacy placeholders: a value, a vector's element
//    for the current extruder (0), its N-th, or the one an integer variable names;
//  - {expression; ...}: expressions, their values written (numbers as C++ streams print them:
//    6 significant digits, no trailing zeros; booleans true / false);
//  - {if c}text{elsif c}text{else}text{endif}: the text of the first true condition;
//  - a '}' that closes nothing is dropped, as PrusaSlicer drops it.
// Expressions: integers, reals (with a '.' or an exponent), "strings" (\" \\ \n \r escapes),
// true, false; variables, vectors indexed v[i] (an index past the end is element 0, as in
// PrusaSlicer); + - * / % (integer division on two integers; + joins when either side is a
// string); == != <> < > <= >= (reals equal within 1e-8); =~ /regex/ and !~ /regex/ (the
// whole string must match); and or not && || !; c ? a : b; min(a, b), max(a, b), int(x),
// round(x), digits(x, n[, d]), zdigits(x, n[, d]), one_of(s, "a", /re/, ...), empty(v),
// size(v). Variables are only read where evaluated: a branch not taken may name anything.
// Not supported, with an error naming them: assignments, local and global variables,
// `if ... then` blocks, random(), interpolate_table(), is_nil().
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <map>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

namespace printer {

// One value: an integer, a real, a string or a boolean (PrusaSlicer's int, float, string, bool;
// its percents and enums arrive as reals and strings).
using MacroScalar = std::variant<long long, double, std::string, bool>;

struct MacroVariable {
  std::vector<MacroScalar> values;  // a scalar has one
  bool is_vector = false;
  // Elements from this index on exist but are not known (the materials of a printer's other
  // extruders): naming one is an error saying `unknown_why`.
  std::size_t known = std::numeric_limits<std::size_t>::max();
  std::string unknown_why;
};

using MacroVariables = std::map<std::string, MacroVariable, std::less<>>;

// Builders for the variable table.
MacroVariable macro_scalar(MacroScalar value);
MacroVariable macro_vector(std::vector<MacroScalar> values);

// Evaluates `text`. A name not in `variables` where it is evaluated, a syntax error, a type
// error or an unsupported construct throws ConfigError: "<where>: line L: <the placeholder or
// expression>: <what is wrong>". `unknown_hint` ends the message for an unknown name.
std::string expand_prusa_macro(std::string_view text, const MacroVariables& variables,
                               std::string_view where, std::string_view unknown_hint = {});

// PrusaSlicer's text of a value: integers in decimal, reals as C++ streams print them.
std::string macro_text(const MacroScalar& value);

}  // namespace printer
