// The one table of slice options (app/slice_options.h): what the command line and the HTTP
// form are made from, checked in-process.
#include <algorithm>
#include <cmath>
#include <set>
#include <string>

#include <doctest/doctest.h>
#include <fmt/core.h>

#include "app/slice_options.h"
#include "printer/error.h"

namespace slice_options_test {

using app::OptionKind;
using app::SliceOption;

// A value inside the option's range, and one outside it ("" when every text is taken).
std::pair<std::string, std::string> good_and_bad(const SliceOption& o) {
  switch (o.kind) {
    case OptionKind::number: return {o.lo_excluded ? "0.5" : fmt::format("{:g}", o.lo), fmt::format("{:g}", o.lo - 1)};
    case OptionKind::whole: return {fmt::format("{:g}", o.lo), "1.5"};
    case OptionKind::choice: return {o.choices.back(), "no-such-choice"};
    case OptionKind::duration: return {"1h30m", "90"};
    case OptionKind::flag:
    case OptionKind::toggle: return {"true", "maybe"};
    case OptionKind::text:
    case OptionKind::texts: return {"anything", ""};
  }
  return {};
}

TEST_CASE("every_slice_option_has_a_flag_a_setter_and_help_saying_its_default") {
  std::set<std::string_view> flags, fields;
  for (const SliceOption& o : app::slice_options()) {
    CAPTURE(o.flag);
    CHECK(o.flag.starts_with("--"));
    CHECK(flags.insert(o.flag).second);
    if (!o.field.empty()) CHECK(fields.insert(o.field).second);
    CHECK(static_cast<bool>(o.set));
    // A hidden option (taken, not listed) has no help to show and no HTTP field.
    if (o.hidden) {
      CHECK(o.field.empty());
    } else {
      CHECK(o.help.find("default") != std::string::npos);
    }
    // A default from the profiles names its key in the help ("the material's bridge.max_length").
    if (!o.profile_key.empty()) {
      const std::string_view key =
          o.profile_key.starts_with("material.") ? o.profile_key.substr(9) : o.profile_key;
      CHECK(o.help.find(key) != std::string::npos);
    }
    for (std::string_view excluded : o.excludes) {
      CAPTURE(excluded);
      const SliceOption* other = app::find_slice_option_flag(excluded);
      REQUIRE(other != nullptr);
      // Exclusion goes both ways, as the help lists it on both.
      CHECK(std::find(other->excludes.begin(), other->excludes.end(), o.flag) != other->excludes.end());
    }
  }
  CHECK(app::find_slice_option_field("maxLayers") == app::find_slice_option_flag("--max-layers"));
  CHECK(app::find_slice_option_flag("--no-raft") == app::find_slice_option_flag("--raft"));
}

TEST_CASE("one_check_for_a_flag_and_a_field_says_the_range") {
  const SliceOption& brim = *app::find_slice_option_field("brim");
  CHECK(app::check_slice_option(brim, "50") == "");
  CHECK(app::check_slice_option(brim, "-3") == "needs a number from 0 to 50, not '-3'");
  CHECK(app::check_slice_option(brim, "wide") == "needs a number from 0 to 50, not 'wide'");
  CHECK(app::check_slice_option(brim, "inf") == "needs a number from 0 to 50, not 'inf'");
  const SliceOption& layers = *app::find_slice_option_flag("--max-layers");
  CHECK(app::check_slice_option(layers, "2.5") == "needs a whole number from 1 to 100000, not '2.5'");
  CHECK(app::check_slice_option(*app::find_slice_option_flag("--tolerance"), "0") ==
        "needs a number greater than 0, not '0'");
  CHECK(app::check_slice_option(*app::find_slice_option_flag("--units"), "cm") ==
        "'cm' is not a unit; use one of m|mm|in");
  CHECK(app::check_slice_option(*app::find_slice_option_field("maxTime"), "90").find("not a duration") !=
        std::string::npos);

  // Every option refuses a value out of its kind or range and takes one inside it.
  for (const SliceOption& o : app::slice_options()) {
    CAPTURE(o.flag);
    const auto [good, bad] = good_and_bad(o);
    app::SliceOptions options;
    CHECK_NOTHROW(app::set_slice_option(options, o, good, o.flag));
    if (bad.empty()) continue;
    CHECK_FALSE(app::check_slice_option(o, bad).empty());
    try {
      app::set_slice_option(options, o, bad, o.field.empty() ? o.flag : o.field);
      FAIL("taken: " << bad);
    } catch (const app::OptionError& e) {
      // One line naming the option as the caller named it.
      const std::string what = e.what();
      CHECK(what.starts_with(std::string(o.field.empty() ? o.flag : o.field) + ": "));
      CHECK(what.find('\n') == std::string::npos);
    }
  }
}

// What an option sets is what the profiles then hold, and the table reads it back from them:
// the default a slice takes is the profile's, and a value given replaces it.
TEST_CASE("an_option_given_becomes_the_profile_value_its_default_is_read_from") {
  const printer::Profiles stock = app::load_slice_profiles({});
  for (const SliceOption& o : app::slice_options()) {
    if (!o.profile_default) continue;
    CAPTURE(o.flag);
    const std::string before = o.profile_default(stock);
    // A value inside the range that differs from the profile's.
    std::string value;
    if (o.kind == OptionKind::choice) {
      for (const std::string& c : o.choices) {
        if (c != before) value = c;
      }
    } else if (o.kind == OptionKind::toggle) {
      value = before == "true" ? "false" : "true";
    } else {
      for (const double v : {(o.lo + o.hi) / 2, o.lo, o.hi}) {
        const std::string text = fmt::format("{:g}", o.kind == OptionKind::whole ? std::floor(v) : v);
        if (text != before && value.empty()) value = text;
      }
    }
    REQUIRE(value != before);
    app::SliceOptions options;
    options.support.placement = "buildplate";  // a raft and supports may need each other's keys
    app::set_slice_option(options, o, value, o.flag);
    try {
      CHECK(o.profile_default(app::load_slice_profiles(options)) == value);
    } catch (const printer::ConfigError& e) {
      FAIL(e.what());
    }
  }
}

TEST_CASE("options_that_exclude_each_other_are_refused_by_the_names_given") {
  const auto field = [](const SliceOption& o) { return std::string(o.field); };
  const std::vector<const SliceOption*> layer_and_adaptive{app::find_slice_option_field("layer"),
                                                           app::find_slice_option_field("adaptive")};
  CHECK_THROWS_WITH_AS(app::check_exclusions(layer_and_adaptive, field),
                       "layer and adaptive: give one of them, not two", app::OptionError);
  const std::vector<const SliceOption*> budgets{app::find_slice_option_field("tolerance"),
                                                app::find_slice_option_field("maxTime")};
  CHECK_THROWS_AS(app::check_exclusions(budgets, field), app::OptionError);
  const std::vector<const SliceOption*> fine{app::find_slice_option_field("brim"),
                                             app::find_slice_option_field("adaptive"),
                                             app::find_slice_option_field("tolerance")};
  CHECK_NOTHROW(app::check_exclusions(fine, field));
}

TEST_CASE("the_default_printer_is_a_profile_that_loads") {
  const app::SliceOptions options;
  CHECK(options.printer == printer::kDefaultPrinter);
  const printer::Profiles profiles = app::load_slice_profiles(options);
  CHECK(profiles.printer.source.find(printer::kDefaultPrinter) != std::string::npos);
}

}  // namespace slice_options_test
