// What a slice is asked for besides the model file, and the one table of those options: each
// option's command-line flag, HTTP field, kind of value, unit, range, profile key its default
// comes from, and help. `mahost slice` and `mahost print` make their flags from the table
// (host/slice_flags.h), `mahost serve` its slice fields (host/serve/http_api.cpp); both check
// a value with check_slice_option and set it with set_slice_option, so a range or a name is
// written once.
#pragma once

#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "app/layer_choice.h"
#include "app/model.h"
#include "printer/profile.h"

namespace app {

// Supports, bridges, brim and raft; each one left unset is the profile's.
struct SupportChoices {
  std::string placement;                          // none, buildplate, everywhere; "": support.type
  std::optional<double> overhang_angle;           // degrees from vertical; material's support.overhang_angle
  std::optional<double> xy_gap;                   // mm; support.xy_gap
  std::optional<double> top_distance;             // mm; support.top_contact_distance
  std::optional<double> bottom_distance;          // mm; support.bottom_contact_distance
  std::optional<double> interface_thickness;      // mm; support.interface_thickness
  std::string pattern;                            // lines, grid; "": support.pattern
  std::optional<double> spacing;                  // mm; support.spacing
  std::vector<std::string> enforcers, blockers;   // "x0,y0,z0,x1,y1,z1", added to the profile's
  std::optional<double> bridge_length;            // mm; the material's bridge.max_length
  std::optional<double> brim;                     // mm; brim.width
  std::optional<bool> raft;                       // raft.enabled
};

struct SliceOptions {
  ModelOptions model;
  std::string printer = printer::kDefaultPrinter;  // a profile name or a path to one
  std::string material;                            // "": the printer's
  std::optional<double> layer;                     // mm; the printer's layer.default
  std::string boundaries;                          // FILE|z1,z2,...: explicit layer tops instead
  AdaptiveRequest adaptive;
  std::string contour = "best";
  std::optional<int> perimeters;                   // print.perimeters
  std::optional<double> infill;                    // percent; print.infill_density
  std::vector<std::string> overrides;              // "key=value", one per --set
  SupportChoices support;
};

// What an option's value is.
enum class OptionKind {
  number,    // a finite number in [lo, hi] (above lo where lo_excluded)
  whole,     // a whole number in [lo, hi]
  choice,    // one of choices()
  text,      // any text (a path, a list of numbers the setter checks)
  duration,  // "1h30m", "90m", "5400s" (parse_duration)
  flag,      // present or not (HTTP: true or false)
  toggle,    // on, off or the profile's: --raft / --no-raft (HTTP: true or false)
  texts,     // repeatable text, each value kept in order (--set, --support-enforcer)
};

struct SliceOption {
  std::string_view flag;   // "--brim"
  std::string_view field;  // the HTTP field ("brim", "maxLayers"); "" for the command line only
  OptionKind kind = OptionKind::text;
  std::string_view unit;   // "mm", "%", "deg", "s"; "" for none
  double lo = 0, hi = 0;   // number, whole
  bool lo_excluded = false;
  std::string_view value_name;       // number: the help's name for the value ("MM" in "MM > 0")
  std::vector<std::string> choices;  // choice
  std::string noun;                  // choice: what a value is ("a unit"), for the refusal
  std::string_view off_flag;         // toggle: "--no-raft"
  std::string_view off_help;         // toggle: the off flag's help
  // Where the default comes from: a profile key ("brim.width", "material.bridge.max_length"),
  // or "" where the default is the help's own.
  std::string_view profile_key;
  std::string help;
  bool hidden = false;  // taken on the command line, not listed in its help
  // Options that cannot be given with this one (their flags).
  std::vector<std::string_view> excludes;
  // Sets a value check_slice_option accepted ("true" or "false" for a flag or toggle).
  void (*set)(SliceOptions& options, const std::string& value) = nullptr;
  // The profiles' value of what the option sets, as text: what a slice takes when the option
  // is not given, and, once given, what load_slice_profiles makes of it (null for an option
  // that does not set a profile key: --layer picks among the printer's thicknesses).
  std::string (*profile_default)(const printer::Profiles& profiles) = nullptr;
};

// Every slice option, in the order help lists them: the model's placement, the profiles,
// the layers, the contour, walls and infill, --set, then supports, bridges, brim and raft.
const std::vector<SliceOption>& slice_options();

// The option with this flag ("--brim") or HTTP field ("maxLayers"); nullptr if none.
const SliceOption* find_slice_option_flag(std::string_view flag);
const SliceOption* find_slice_option_field(std::string_view field);

// The placement options (--units ... --orient, --ignore-normals) and the adaptive ones
// (--adaptive, --tolerance, --max-layers, and --max-time when `print_time`), as the commands
// that take only those list them.
std::vector<const SliceOption*> placement_options();
std::vector<const SliceOption*> adaptive_options(bool print_time);

// What is wrong with `value` for the option ("" when nothing): "needs a number from 0 to 50,
// not '-3'", "'sometimes' is not one of none|buildplate|everywhere".
std::string check_slice_option(const SliceOption& option, const std::string& value);

// A value refused, by the option's name as the caller gave it (flag or field).
struct OptionError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Checks and sets one value; OptionError "brim: needs a number from 0 to 50, not '-3'" (the
// option named by `name`, the flag or field as given).
void set_slice_option(SliceOptions& options, const SliceOption& option, const std::string& value,
                      std::string_view name);

// The options given together that exclude each other (by flag), as "--layer and --adaptive";
// OptionError naming both by `name_of` (flag or field) if two were given.
void check_exclusions(const std::vector<const SliceOption*>& given,
                      std::string (*name_of)(const SliceOption&));

// The flags that only mean something for a model to slice (all but --printer and --set): for
// `print` to refuse them with a G-code file.
std::vector<std::string> model_only_slice_flags();

// "none", "buildplate", "everywhere": --support's values; the contour strategies' names and
// their "name (description), ..." help.
std::vector<std::string> support_placement_names();
std::vector<std::string> contour_strategy_names();
std::string contour_strategies_help();

// The printer and material profiles the options name, with
// --perimeters, --infill and the support options applied. Throws printer::ConfigError
// naming the profile, key or value that is wrong.
printer::Profiles load_slice_profiles(const SliceOptions& options);

// The layer thickness of uniform slicing: --layer, else the printer's layer.default.
double uniform_thickness(const SliceOptions& options, const printer::PrinterProfile& machine);

}  // namespace app
