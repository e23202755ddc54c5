// PrusaSlicer's G-code macro language; see prusa_macro.h. A recursive descent parser that
// evaluates as it reads, as PrusaSlicer's does: in a branch not taken it only parses.
#include "printer/prusa_macro.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <optional>
#include <regex>
#include <sstream>

#include <fmt/core.h>

#include "printer/error.h"

namespace printer {

MacroVariable macro_scalar(MacroScalar value) {
  MacroVariable v;
  v.values.push_back(std::move(value));
  return v;
}

MacroVariable macro_vector(std::vector<MacroScalar> values) {
  MacroVariable v;
  v.values = std::move(values);
  v.is_vector = true;
  return v;
}

std::string macro_text(const MacroScalar& value) {
  if (const auto* i = std::get_if<long long>(&value)) return std::to_string(*i);
  if (const auto* d = std::get_if<double>(&value)) {
    std::ostringstream out;  // precision 6, no trailing zeros: PrusaSlicer's to_string
    out << *d;
    return out.str();
  }
  if (const auto* s = std::get_if<std::string>(&value)) return *s;
  return std::get<bool>(value) ? "true" : "false";
}

namespace {

// The error of one placeholder; the evaluator adds where it is.
struct MacroError {
  std::string what;
};

[[noreturn]] void error(std::string what) { throw MacroError{std::move(what)}; }

// A value as an expression has it; empty in a branch not taken.
struct Value {
  std::optional<MacroScalar> v;

  bool empty() const { return !v.has_value(); }
  bool is_int() const { return v && std::holds_alternative<long long>(*v); }
  bool is_real() const { return v && std::holds_alternative<double>(*v); }
  bool is_number() const { return is_int() || is_real(); }
  bool is_string() const { return v && std::holds_alternative<std::string>(*v); }
  bool is_bool() const { return v && std::holds_alternative<bool>(*v); }
  long long i() const { return std::get<long long>(*v); }
  double d() const { return is_int() ? static_cast<double>(i()) : std::get<double>(*v); }
  const std::string& s() const { return std::get<std::string>(*v); }
  bool b() const { return std::get<bool>(*v); }
  std::string text() const { return v ? macro_text(*v) : std::string(); }
};

std::string_view type_name(const Value& v) {
  if (v.is_int()) return "an integer";
  if (v.is_real()) return "a real number";
  if (v.is_string()) return "a string";
  return "a boolean";
}

// PrusaSlicer matches with Boost's perl syntax, where '.' also matches a line break (printer_notes
// has several lines); ECMAScript's does not, so each '.' outside a [class] becomes [\s\S].
std::string dot_matches_all(std::string_view pattern) {
  std::string out;
  bool in_class = false;
  for (std::size_t i = 0; i < pattern.size(); ++i) {
    const char c = pattern[i];
    if (c == '\\' && i + 1 < pattern.size()) {
      out += c;
      out += pattern[++i];
    } else if (in_class) {
      out += c;
      if (c == ']') in_class = false;
    } else if (c == '[') {
      out += c;
      in_class = true;
      if (i + 1 < pattern.size() && pattern[i + 1] == ']') out += pattern[++i];
    } else {
      out += c == '.' ? std::string("[\\s\\S]") : std::string(1, c);
    }
  }
  return out;
}

bool is_identifier_start(char c) { return std::isalpha(static_cast<unsigned char>(c)) || c == '_'; }
bool is_identifier_char(char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; }

constexpr std::string_view kKeywords[] = {
    "and", "digits", "zdigits", "empty", "if", "int", "is_nil", "local", "else", "elsif", "endif",
    "false", "global", "interpolate_table", "min", "max", "random", "repeat", "round", "not",
    "one_of", "or", "size", "true"};

bool is_keyword(std::string_view word) {
  return std::find(std::begin(kKeywords), std::end(kKeywords), word) != std::end(kKeywords);
}

class Evaluator {
 public:
  Evaluator(std::string_view text, const MacroVariables& variables)
      : text_(text), variables_(variables) {}

  std::string run() {
    std::string out = text_block(false);
    if (pos_ < text_.size()) {
      // text_block(false) stops only at an {elsif}, {else} or {endif} of no {if}.
      start_ = pos_;
      error("an {elsif}, {else} or {endif} without an {if}");
    }
    return out;
  }

  std::size_t placeholder_start() const { return start_; }

 private:
  // ---- text ---------------------------------------------------------------------------------

  // Text, placeholders and macros up to the end, or (nested) to the '{' of an elsif, else or
  // endif of the {if} it is the branch of.
  std::string text_block(bool nested) {
    std::string out;
    while (pos_ < text_.size()) {
      const char c = text_[pos_];
      if (c == '{') {
        if (closes_branch()) {
          if (!nested) return out;
          return out;
        }
        start_ = pos_;
        ++pos_;
        out += macros();
      } else if (c == '[') {
        start_ = pos_;
        ++pos_;
        out += legacy();
      } else if (c == '}') {
        ++pos_;  // a brace that closes nothing: PrusaSlicer's grammar drops it
      } else {
        const std::size_t stop = text_.find_first_of("[{}", pos_);
        const std::size_t end = stop == std::string_view::npos ? text_.size() : stop;
        if (!skipping()) out.append(text_.substr(pos_, end - pos_));
        pos_ = end;
      }
    }
    return out;
  }

  // At a '{' followed by elsif, else or endif?
  bool closes_branch() const {
    std::size_t at = pos_ + 1;
    while (at < text_.size() && is_space(text_[at])) ++at;
    const std::size_t from = at;
    while (at < text_.size() && is_identifier_char(text_[at])) ++at;
    const std::string_view word = text_.substr(from, at - from);
    return word == "elsif" || word == "else" || word == "endif";
  }

  // [name], [name_N] or [name[index_name]], after the '['.
  std::string legacy() {
    const std::string_view name = identifier_or_fail("a variable name after '['");
    std::string out;
    if (peek() == '[') {
      ++pos_;
      const std::string_view index_name = identifier_or_fail("an integer variable inside [name[...]]");
      expect(']');
      expect(']');
      if (skipping()) return out;
      const MacroVariable& vector = variable(name);
      if (!vector.is_vector) error(fmt::format("'{}' is not a vector, so it cannot be indexed", name));
      const Value index = scalar_of(index_name, variable(index_name), std::nullopt);
      if (!index.is_int()) error(fmt::format("the index '{}' is not an integer", index_name));
      if (index.i() < 0) error(fmt::format("the index '{}' is negative", index_name));
      return element(name, vector, static_cast<std::size_t>(index.i())).text();
    }
    expect(']');
    if (skipping()) return out;
    if (const auto found = variables_.find(name); found != variables_.end()) {
      const MacroVariable& v = found->second;
      return (v.is_vector ? element(name, v, 0) : scalar_of(name, v, std::nullopt)).text();
    }
    // [name_N]: element N of the vector `name`.
    const std::size_t underscore = name.rfind('_');
    if (underscore != std::string_view::npos && underscore + 1 < name.size()) {
      const std::string_view base = name.substr(0, underscore);
      const std::string_view digits = name.substr(underscore + 1);
      std::size_t index = 0;
      const auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), index);
      const auto found = variables_.find(base);
      if (found != variables_.end() && ec == std::errc() && end == digits.data() + digits.size()) {
        if (!found->second.is_vector) error(fmt::format("'{}' is not a vector, so it has no element {}", base, index));
        return element(base, found->second, index).text();
      }
    }
    unknown(name);
  }

  // ---- macros -------------------------------------------------------------------------------

  // Statements and blocks after a '{', to its closing '}'.
  std::string macros() {
    std::string out;
    bool any = false;
    for (;;) {
      skip_space();
      if (pos_ >= text_.size()) error("the '{' is never closed with '}'");
      const char c = text_[pos_];
      if (c == '}') {
        if (!any) error("'{}' holds nothing");
        ++pos_;
        return out;
      }
      if (c == ';') {
        ++pos_;
        any = true;
        continue;
      }
      const std::size_t at = pos_;
      const std::string_view word = peek_identifier();
      if (word == "if") {
        pos_ = at + word.size();
        out += if_block();
        any = true;
        continue;
      }
      if (word == "local" || word == "global") {
        error(fmt::format("'{}' variables are not supported by mahost", word));
      }
      const Value value = conditional();
      skip_space();
      if (peek() == '=' && peek(1) != '=' && peek(1) != '~') {
        error("assignments are not supported by mahost");
      }
      if (pos_ >= text_.size()) error("the '{' is never closed with '}'");
      if (peek() != ';' && peek() != '}') {
        error(fmt::format("expected ';' or '}}' after an expression, found '{}'", rest_of_line()));
      }
      if (!skipping()) out += value.text();
      any = true;
    }
  }

  // {if c}text{elsif c}text{else}text{endif}, after the "if".
  std::string if_block() {
    std::string out;
    bool done = false;  // a branch was taken
    bool condition = condition_value();
    for (;;) {
      skip_space();
      if (peek_identifier() == "then") error("'if ... then' blocks are not supported by mahost");
      expect('}');
      const bool take = !done && condition;
      enter(take);
      std::string branch = text_block(true);
      leave(take);
      if (take && !skipping()) out = std::move(branch);
      done = done || take;
      if (pos_ >= text_.size()) error("an {if} without {endif}");
      ++pos_;  // the '{' closes_branch() stopped at
      skip_space();
      const std::string_view word = peek_identifier();
      pos_ += word.size();
      if (word == "endif") return out;
      if (word == "elsif") {
        enter(!done);
        condition = condition_value();
        leave(!done);
        continue;
      }
      // else
      skip_space();
      expect('}');
      enter(!done);
      std::string last = text_block(true);
      leave(!done);
      if (!done && !skipping()) out = std::move(last);
      if (pos_ >= text_.size()) error("an {if} without {endif}");
      ++pos_;
      skip_space();
      const std::string_view end = peek_identifier();
      if (end != "endif") error(fmt::format("expected {{endif}} after {{else}}, found {{{}}}", end));
      pos_ += end.size();
      return out;
    }
  }

  bool condition_value() {
    const Value c = conditional();
    if (skipping()) return false;
    if (!c.is_bool()) error(fmt::format("the condition is {}, not a boolean", type_name(c)));
    return c.b();
  }

  // ---- expressions --------------------------------------------------------------------------

  Value conditional() {
    Value v = logical_or();
    skip_space();
    if (peek() != '?') return v;
    ++pos_;
    const bool skip = skipping();
    if (!skip && !v.is_bool()) error(fmt::format("'?' needs a boolean, not {}", type_name(v)));
    const bool first = !skip && v.b();
    enter(first);
    Value a = conditional();
    leave(first);
    skip_space();
    expect(':');
    enter(!skip && !first);
    Value b = conditional();
    leave(!skip && !first);
    if (skip) return {};
    return first ? a : b;
  }

  Value logical_or() {
    Value v = logical_and();
    for (;;) {
      skip_space();
      if (!take_keyword("or") && !take("||")) return v;
      Value rhs = logical_and();
      v = logic(v, rhs, true);
    }
  }

  Value logical_and() {
    Value v = equality();
    for (;;) {
      skip_space();
      if (!take_keyword("and") && !take("&&")) return v;
      Value rhs = equality();
      v = logic(v, rhs, false);
    }
  }

  Value logic(const Value& a, const Value& b, bool is_or) {
    if (skipping()) return {};
    if (!a.is_bool() || !b.is_bool()) error(fmt::format("'{}' needs booleans", is_or ? "or" : "and"));
    return {is_or ? (a.b() || b.b()) : (a.b() && b.b())};
  }

  Value equality() {
    Value v = relational();
    for (;;) {
      skip_space();
      if (take("==")) {
        v = compare(v, relational(), '=', false);
      } else if (take("!=") || take("<>")) {
        v = compare(v, relational(), '=', true);
      } else if (take("=~")) {
        v = regex_match(v, regular_expression(), false);
      } else if (take("!~")) {
        v = regex_match(v, regular_expression(), true);
      } else {
        return v;
      }
    }
  }

  Value relational() {
    Value v = additive();
    for (;;) {
      skip_space();
      if (take("<=")) {
        v = compare(v, additive(), '>', true);
      } else if (take(">=")) {
        v = compare(v, additive(), '<', true);
      } else if (peek() == '<' && peek(1) != '>') {
        ++pos_;
        v = compare(v, additive(), '<', false);
      } else if (peek() == '>') {
        ++pos_;
        v = compare(v, additive(), '>', false);
      } else {
        return v;
      }
    }
  }

  Value compare(const Value& a, const Value& b, char op, bool invert) {
    if (skipping()) return {};
    bool result = false;
    if (a.is_number() && b.is_number()) {
      const bool real = a.is_real() || b.is_real();
      switch (op) {
        case '=': result = real ? std::abs(a.d() - b.d()) < 1e-8 : a.i() == b.i(); break;
        case '<': result = real ? a.d() < b.d() : a.i() < b.i(); break;
        default: result = real ? a.d() > b.d() : a.i() > b.i(); break;
      }
    } else if (a.is_bool() && b.is_bool() && op == '=') {
      result = a.b() == b.b();
    } else if (a.is_string() || b.is_string()) {
      const std::string x = a.text(), y = b.text();
      result = op == '=' ? x == y : op == '<' ? x < y : x > y;
    } else {
      error(fmt::format("cannot compare {} with {}", type_name(a), type_name(b)));
    }
    return {invert ? !result : result};
  }

  Value regex_match(const Value& subject, std::string_view pattern, bool invert) {
    if (skipping()) return {};
    if (!subject.is_string()) error("the left side of =~ and !~ must be a string");
    try {
      const bool matched = std::regex_match(subject.s(), std::regex(dot_matches_all(pattern)));
      return {invert ? !matched : matched};
    } catch (const std::regex_error& e) {
      error(fmt::format("the regular expression /{}/ does not compile: {}", pattern, e.what()));
    }
  }

  // /.../ with \/ and \\ kept for the regex engine, after skipping spaces.
  std::string_view regular_expression() {
    skip_space();
    expect('/');
    const std::size_t from = pos_;
    while (pos_ < text_.size() && text_[pos_] != '/') {
      if (text_[pos_] == '\\') ++pos_;
      ++pos_;
    }
    if (pos_ >= text_.size()) error("the regular expression is not closed with '/'");
    return text_.substr(from, pos_++ - from);
  }

  Value additive() {
    Value v = multiplicative();
    for (;;) {
      skip_space();
      const char c = peek();
      if (c != '+' && c != '-') return v;
      ++pos_;
      Value rhs = multiplicative();
      if (skipping()) continue;
      if (c == '+' && (v.is_string() || rhs.is_string())) {
        v = {v.text() + rhs.text()};
        continue;
      }
      v = arithmetic(v, rhs, c);
    }
  }

  Value multiplicative() {
    Value v = unary();
    for (;;) {
      skip_space();
      const char c = peek();
      if (c != '*' && c != '/' && c != '%') return v;
      ++pos_;
      Value rhs = unary();
      if (!skipping()) v = arithmetic(v, rhs, c);
    }
  }

  Value arithmetic(const Value& a, const Value& b, char op) {
    if (!a.is_number() || !b.is_number()) {
      error(fmt::format("'{}' needs numbers, not {} and {}", op, type_name(a), type_name(b)));
    }
    if ((op == '/' || op == '%') && (b.is_int() ? b.i() == 0 : b.d() == 0)) error("division by zero");
    if (a.is_real() || b.is_real()) {
      switch (op) {
        case '+': return {a.d() + b.d()};
        case '-': return {a.d() - b.d()};
        case '*': return {a.d() * b.d()};
        case '/': return {a.d() / b.d()};
        default: return {std::fmod(a.d(), b.d())};
      }
    }
    switch (op) {
      case '+': return {a.i() + b.i()};
      case '-': return {a.i() - b.i()};
      case '*': return {a.i() * b.i()};
      case '/': return {a.i() / b.i()};
      default: return {a.i() % b.i()};
    }
  }

  Value unary() {
    skip_space();
    const char c = peek();
    if (c == '(') {
      ++pos_;
      Value v = conditional();
      skip_space();
      expect(')');
      return v;
    }
    if (c == '-') {
      ++pos_;
      Value v = unary();
      if (skipping()) return {};
      if (v.is_int()) return {-v.i()};
      if (v.is_real()) return {-v.d()};
      error(fmt::format("cannot negate {}", type_name(v)));
    }
    if (c == '+') {
      ++pos_;
      return unary();
    }
    if (c == '!' && peek(1) != '=' && peek(1) != '~') {
      ++pos_;
      return negation(unary());
    }
    if (c == '"') return string_literal();
    if (std::isdigit(static_cast<unsigned char>(c)) || (c == '.' && std::isdigit(static_cast<unsigned char>(peek(1))))) {
      return number();
    }
    const std::string_view word = peek_identifier();
    if (word.empty()) {
      if (pos_ >= text_.size()) error("the expression ends early");
      error(fmt::format("expected a value, found '{}'", rest_of_line()));
    }
    if (word == "not") {
      pos_ += word.size();
      return negation(unary());
    }
    if (word == "true" || word == "false") {
      pos_ += word.size();
      return skipping() ? Value{} : Value{word == "true"};
    }
    if (word == "min" || word == "max") return min_max(word);
    if (word == "int" || word == "round") return rounding(word);
    if (word == "digits" || word == "zdigits") return digits(word);
    if (word == "one_of") return one_of();
    if (word == "empty" || word == "size") return vector_test(word);
    if (word == "random" || word == "interpolate_table" || word == "is_nil" || word == "repeat") {
      error(fmt::format("{}() is not supported by mahost", word));
    }
    if (is_keyword(word)) error(fmt::format("'{}' cannot start a value", word));
    pos_ += word.size();
    return variable_value(word);
  }

  Value negation(const Value& v) {
    if (skipping()) return {};
    if (!v.is_bool()) error(fmt::format("'not' needs a boolean, not {}", type_name(v)));
    return {!v.b()};
  }

  Value string_literal() {
    ++pos_;  // "
    std::string s;
    while (pos_ < text_.size() && text_[pos_] != '"') {
      char c = text_[pos_++];
      if (c == '\\') {
        if (pos_ >= text_.size()) break;
        c = text_[pos_++];
        if (c == 'n') c = '\n';
        else if (c == 'r') c = '\r';
        else if (c != '"' && c != '\\') error(fmt::format("'\\{}' is not an escape of a string", c));
      }
      s += c;
    }
    if (pos_ >= text_.size()) error("the string is not closed with '\"'");
    ++pos_;
    return skipping() ? Value{} : Value{std::move(s)};
  }

  // An integer, or a real when it has a '.' or an exponent (PrusaSlicer's strict reals).
  Value number() {
    std::size_t end = pos_;
    while (end < text_.size() && std::isdigit(static_cast<unsigned char>(text_[end]))) ++end;
    bool real = false;
    if (end < text_.size() && text_[end] == '.') {
      real = true;
      ++end;
      while (end < text_.size() && std::isdigit(static_cast<unsigned char>(text_[end]))) ++end;
    }
    if (end < text_.size() && (text_[end] == 'e' || text_[end] == 'E')) {
      std::size_t at = end + 1;
      if (at < text_.size() && (text_[at] == '+' || text_[at] == '-')) ++at;
      if (at < text_.size() && std::isdigit(static_cast<unsigned char>(text_[at]))) {
        real = true;
        end = at;
        while (end < text_.size() && std::isdigit(static_cast<unsigned char>(text_[end]))) ++end;
      }
    }
    const std::string_view digits = text_.substr(pos_, end - pos_);
    pos_ = end;
    if (real) {
      double d = 0;
      std::from_chars(digits.data(), digits.data() + digits.size(), d);
      return skipping() ? Value{} : Value{d};
    }
    long long i = 0;
    const auto [stop, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), i);
    if (ec != std::errc()) error(fmt::format("the integer {} is too large", digits));
    return skipping() ? Value{} : Value{i};
  }

  // word ( a , b )
  std::vector<Value> arguments(std::string_view word, std::size_t least, std::size_t most) {
    pos_ += word.size();
    skip_space();
    expect('(');
    std::vector<Value> args;
    skip_space();
    if (peek() != ')') {
      for (;;) {
        args.push_back(conditional());
        skip_space();
        if (peek() != ',') break;
        ++pos_;
      }
    }
    skip_space();
    expect(')');
    if (args.size() < least || args.size() > most) {
      error(fmt::format("{}() takes {} arguments, not {}", word,
                        least == most ? fmt::format("{}", least) : fmt::format("{} to {}", least, most),
                        args.size()));
    }
    return args;
  }

  Value min_max(std::string_view word) {
    const std::vector<Value> a = arguments(word, 2, 2);
    if (skipping()) return {};
    if (!a[0].is_number() || !a[1].is_number()) error(fmt::format("{}() needs numbers", word));
    const bool is_min = word == "min";
    if (a[0].is_real() || a[1].is_real()) return {is_min ? std::min(a[0].d(), a[1].d()) : std::max(a[0].d(), a[1].d())};
    return {is_min ? std::min(a[0].i(), a[1].i()) : std::max(a[0].i(), a[1].i())};
  }

  Value rounding(std::string_view word) {
    const std::vector<Value> a = arguments(word, 1, 1);
    if (skipping()) return {};
    if (!a[0].is_number()) error(fmt::format("{}() needs a number", word));
    if (a[0].is_int()) return a[0];
    return {static_cast<long long>(word == "int" ? a[0].d() : std::round(a[0].d()))};
  }

  // digits(x, width[, decimals]): x padded with spaces (zdigits: zeros) to `width`.
  Value digits(std::string_view word) {
    const std::vector<Value> a = arguments(word, 2, 3);
    if (skipping()) return {};
    if (!a[0].is_number()) error(fmt::format("{}() needs a number", word));
    if (!a[1].is_int() || (a.size() == 3 && !a[2].is_int())) {
      error(fmt::format("{}(): the width and the decimals must be integers", word));
    }
    const int width = static_cast<int>(std::clamp<long long>(a[1].i(), 0, 64));
    const bool zeros = word == "zdigits";
    if (a.size() == 3) {
      const int decimals = static_cast<int>(std::clamp<long long>(a[2].i(), 0, 64));
      return {zeros ? fmt::format("{:0{}.{}f}", a[0].d(), width, decimals)
                    : fmt::format("{:{}.{}f}", a[0].d(), width, decimals)};
    }
    const long long whole = a[0].is_int() ? a[0].i() : std::llround(a[0].d());
    return {zeros ? fmt::format("{:0{}d}", whole, width) : fmt::format("{:{}d}", whole, width)};
  }

  // one_of(s, "a", /re/, ~"re", ...): s equals a string or matches a regular expression.
  Value one_of() {
    pos_ += 6;
    skip_space();
    expect('(');
    const Value subject = unary();
    bool matched = false;
    for (;;) {
      skip_space();
      if (peek() == ')') break;
      expect(',');
      skip_space();
      if (peek() == ')') break;
      if (peek() == '/') {
        const std::string_view pattern = regular_expression();
        if (!skipping() && !matched) matched = regex_match(string_subject(subject), pattern, false).b();
        continue;
      }
      const bool is_regex = peek() == '~';
      if (is_regex) ++pos_;
      const Value pattern = unary();
      if (skipping() || matched) continue;
      if (!pattern.is_string()) error("one_of(): the patterns must be strings");
      matched = is_regex ? regex_match(string_subject(subject), pattern.s(), false).b()
                         : string_subject(subject).s() == pattern.s();
    }
    expect(')');
    return skipping() ? Value{} : Value{matched};
  }

  const Value& string_subject(const Value& v) {
    if (!v.is_string()) error("one_of(): the first argument must be a string");
    return v;
  }

  Value vector_test(std::string_view word) {
    pos_ += word.size();
    skip_space();
    expect('(');
    skip_space();
    const std::string_view name = identifier_or_fail("a variable name");
    skip_space();
    expect(')');
    if (skipping()) return {};
    const MacroVariable& v = variable(name);
    if (!v.is_vector) error(fmt::format("{}(): '{}' is not a vector", word, name));
    if (word == "empty") return {v.values.empty()};
    return {static_cast<long long>(v.values.size())};
  }

  // name or name[index]
  Value variable_value(std::string_view name) {
    skip_space();
    std::optional<Value> index;
    if (peek() == '[') {
      ++pos_;
      index = additive();
      skip_space();
      expect(']');
    }
    if (skipping()) return {};
    const MacroVariable& v = variable(name);
    return scalar_of(name, v, index);
  }

  Value scalar_of(std::string_view name, const MacroVariable& v, const std::optional<Value>& index) {
    if (!v.is_vector) {
      if (index) error(fmt::format("'{}' is not a vector, so it cannot be indexed", name));
      return {v.values.front()};
    }
    if (!index) error(fmt::format("'{}' is a vector: name one element, {}[0]", name, name));
    if (!index->is_int()) error(fmt::format("the index of '{}' must be an integer", name));
    if (index->i() < 0) error(fmt::format("the index of '{}' is negative", name));
    return element(name, v, static_cast<std::size_t>(index->i()));
  }

  Value element(std::string_view name, const MacroVariable& v, std::size_t index) {
    if (v.values.empty()) error(fmt::format("'{}' is an empty vector", name));
    if (index >= v.known && index < v.values.size()) {
      error(fmt::format("{}[{}]: {}", name, index, v.unknown_why));
    }
    return {v.values[index < v.values.size() ? index : 0]};
  }

  const MacroVariable& variable(std::string_view name) {
    const auto found = variables_.find(name);
    if (found == variables_.end()) unknown(name);
    return found->second;
  }

  [[noreturn]] void unknown(std::string_view name) { throw UnknownName{std::string(name)}; }

  // ---- lexing -------------------------------------------------------------------------------

  static bool is_space(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r'; }

  void skip_space() {
    while (pos_ < text_.size() && is_space(text_[pos_])) ++pos_;
  }

  char peek(std::size_t ahead = 0) const {
    return pos_ + ahead < text_.size() ? text_[pos_ + ahead] : '\0';
  }

  bool take(std::string_view token) {
    if (text_.substr(pos_, token.size()) != token) return false;
    pos_ += token.size();
    return true;
  }

  bool take_keyword(std::string_view word) {
    if (peek_identifier() != word) return false;
    pos_ += word.size();
    return true;
  }

  std::string_view peek_identifier() const {
    if (pos_ >= text_.size() || !is_identifier_start(text_[pos_])) return {};
    std::size_t end = pos_ + 1;
    while (end < text_.size() && is_identifier_char(text_[end])) ++end;
    return text_.substr(pos_, end - pos_);
  }

  std::string_view identifier_or_fail(std::string_view what) {
    const std::string_view word = peek_identifier();
    if (word.empty() || is_keyword(word)) {
      error(fmt::format("expected {}, found '{}'", what, rest_of_line()));
    }
    pos_ += word.size();
    return word;
  }

  void expect(char c) {
    if (peek() == c) {
      ++pos_;
      return;
    }
    if (pos_ >= text_.size()) error(fmt::format("expected '{}', found the end of the text", c));
    error(fmt::format("expected '{}', found '{}'", c, rest_of_line()));
  }

  std::string rest_of_line() const {
    const std::size_t end = std::min(text_.find('\n', pos_), pos_ + 20);
    return std::string(text_.substr(pos_, std::min(end, text_.size()) - pos_));
  }

  // ---- branches -----------------------------------------------------------------------------

  bool skipping() const { return skip_ > 0; }
  void enter(bool taken) {
    if (!taken) ++skip_;
  }
  void leave(bool taken) {
    if (!taken) --skip_;
  }

 public:
  struct UnknownName {
    std::string name;
  };

 private:
  std::string_view text_;
  const MacroVariables& variables_;
  std::size_t pos_ = 0;
  std::size_t start_ = 0;  // where the placeholder being read starts
  int skip_ = 0;           // depth of branches not taken around here
};

// The placeholder that starts at `start`: "[name]" or "{...}" (cut short), for messages.
std::string placeholder_at(std::string_view text, std::size_t start) {
  if (start >= text.size()) return {};
  const char close = text[start] == '[' ? ']' : '}';
  std::size_t end = text.find(close, start);
  const std::size_t line_end = text.find('\n', start);
  end = std::min(end == std::string_view::npos ? text.size() : end + 1,
                 line_end == std::string_view::npos ? text.size() : line_end);
  std::string shown(text.substr(start, std::min<std::size_t>(end - start, 60)));
  if (end - start > 60) shown += "...";
  return shown;
}

}  // namespace

std::string expand_prusa_macro(std::string_view text, const MacroVariables& variables,
                               std::string_view where, std::string_view unknown_hint) {
  Evaluator evaluator(text, variables);
  auto located = [&](const std::string& what) {
    const std::size_t at = evaluator.placeholder_start();
    const auto line = 1 + std::count(text.begin(), text.begin() + std::min(at, text.size()), '\n');
    return ConfigError(fmt::format("{}: line {}: {}: {}", where, line, placeholder_at(text, at), what));
  };
  try {
    return evaluator.run();
  } catch (const MacroError& e) {
    throw located(e.what);
  } catch (const Evaluator::UnknownName& e) {
    throw located(fmt::format("'{}' is not a value mahost knows{}{}", e.name,
                              unknown_hint.empty() ? "" : "; ", unknown_hint));
  }
}

}  // namespace printer
