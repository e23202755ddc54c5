// The slice options and their table; see slice_options.h.
#include "app/slice_options.h"

#include <algorithm>
#include <charconv>
#include <cmath>

#include <fmt/format.h>

#include "app/profile_paths.h"
#include "app/value_check.h"
#include "geometry/contour/contour_strategy.h"
#include "geometry/support/support_plan.h"
#include "printer/error.h"

namespace app {
namespace {

double number(const std::string& value) {
  double v = 0;
  std::from_chars(value.data(), value.data() + value.size(), v);
  return v;
}

std::string shown(double value) { return fmt::format("{:g}", value); }

// The table's entries by kind; `set` and `profile_default` are filled in by each entry.
SliceOption number_option(std::string_view flag, std::string_view field, std::string_view unit,
                          double lo, double hi, std::string_view profile_key, std::string help) {
  SliceOption o;
  o.flag = flag;
  o.field = field;
  o.kind = OptionKind::number;
  o.unit = unit;
  o.lo = lo;
  o.hi = hi;
  o.profile_key = profile_key;
  o.help = std::move(help);
  return o;
}

SliceOption choice_option(std::string_view flag, std::string_view field, std::string noun,
                          std::vector<std::string> choices, std::string help) {
  SliceOption o;
  o.flag = flag;
  o.field = field;
  o.kind = OptionKind::choice;
  o.noun = std::move(noun);
  o.choices = std::move(choices);
  o.help = std::move(help);
  return o;
}

SliceOption other_option(std::string_view flag, std::string_view field, OptionKind kind,
                         std::string help) {
  SliceOption o;
  o.flag = flag;
  o.field = field;
  o.kind = kind;
  o.help = std::move(help);
  return o;
}

std::vector<SliceOption> make_table() {
  std::vector<SliceOption> t;
  using K = OptionKind;
  // The model's placement.
  t.push_back(choice_option("--units", "units", "a unit", {"m", "mm", "in"},
                            "unit of the file's coordinates, which STL and OBJ do not record "
                            "(3MF does) (default: mm)"));
  t.back().set = [](SliceOptions& o, const std::string& v) { o.model.units = v; };
  t.push_back(number_option("--scale", "scale", "", 0, INFINITY, "",
                            "scale factor, applied after --units (default: 1)"));
  t.back().lo_excluded = true;
  t.back().value_name = "F";
  t.back().excludes = {"--height"};
  t.back().set = [](SliceOptions& o, const std::string& v) { o.model.scale = number(v); };
  t.push_back(number_option("--height", "height", "mm", 0, INFINITY, "",
                            "scale uniformly so the part is MM tall, mm (default: the file's "
                            "size)"));
  t.back().lo_excluded = true;
  t.back().value_name = "MM";
  t.back().excludes = {"--scale"};
  t.back().set = [](SliceOptions& o, const std::string& v) { o.model.height = number(v); };
  t.push_back(choice_option("--up", "up", "an axis", {"x", "y", "z"},
                            "the model's axis that points up on the bed (default: z)"));
  t.back().set = [](SliceOptions& o, const std::string& v) { o.model.up = v; };
  t.push_back(other_option("--rotate", "", K::texts,
                           "turn the model by DEGREES about an AXIS (x, y, z or a vector a,b,c) "
                           "after --up, e.g. --rotate x:90 or --rotate 1,1,0:30; repeatable, "
                           "applied in order (default: none)"));
  t.back().set = [](SliceOptions& o, const std::string& v) { o.model.rotate.push_back(v); };
  t.push_back(choice_option("--orient", "orient", "an orientation", {"none", "auto"},
                            "auto: rest the model on the face of its convex hull that needs the "
                            "least support (then the lowest), after --up and --rotate (default: "
                            "none, as given)"));
  t.back().set = [](SliceOptions& o, const std::string& v) { o.model.orient = v; };
  // Accepted, and not listed, for the scripts of earlier versions, which refused an STL whose
  // stored normals disagreed with its vertex order unless given this: stored normals are
  // never used now (geometry/mesh/stl_io.h).
  t.push_back(other_option("--ignore-normals", "", K::flag,
                           "accepted and unused: the vertex order and the repair decide, "
                           "never an STL's stored normals"));
  t.back().hidden = true;
  t.back().set = [](SliceOptions& o, const std::string& v) { o.model.ignore_normals = v == "true"; };

  // The profiles.
  t.push_back(other_option("--printer", "", K::text,
                           fmt::format("printer profile: a name in the config directory "
                                       "(up-plus-2, generic-marlin) or a path to a .toml file "
                                       "(default: {})",
                                       printer::kDefaultPrinter)));
  t.back().set = [](SliceOptions& o, const std::string& v) { o.printer = v; };
  t.push_back(other_option("--material", "", K::text,
                           "material profile: a name (abs, pla) or a path to a .toml file "
                           "(default: the printer profile's material)"));
  t.back().profile_key = "material";
  t.back().set = [](SliceOptions& o, const std::string& v) { o.material = v; };

  // The layers.
  t.push_back(number_option("--layer", "layer", "mm", 0, INFINITY, "layer.default",
                            "layer thickness, mm; one the printer allows (default: the printer "
                            "profile's layer.default)"));
  t.back().lo_excluded = true;
  t.back().excludes = {"--boundaries", "--adaptive", "--tolerance", "--max-layers", "--max-time"};
  t.back().set = [](SliceOptions& o, const std::string& v) { o.layer = number(v); };
  t.push_back(other_option("--boundaries", "", K::text,
                           "explicit layer tops instead of --layer: a comma list in mm "
                           "(0.3,0.5,0.7,...), a file with one top per line (# comments), or a "
                           "G-code file of CuraEngine, PrusaSlicer, Slic3r or mahost, whose layer "
                           "heights are used; the first layer must be the printer's "
                           "first_layer.height, every other one a thickness it allows (default: "
                           "none)"));
  t.back().excludes = {"--layer", "--adaptive", "--tolerance", "--max-layers", "--max-time"};
  t.back().set = [](SliceOptions& o, const std::string& v) { o.boundaries = v; };
  t.push_back(other_option(
      "--adaptive", "adaptive", K::flag,
      fmt::format("vary the layer thickness: the fewest layers whose distance error D (as "
                  "analyze reports it, of the contour printed) stays within --tolerance "
                  "(default {:g} mm), thinner where the surface flattens, thicker where it "
                  "stands; flat tops and floors on layer boundaries",
                  kDefaultTolerance)));
  t.back().excludes = {"--layer", "--boundaries"};
  t.back().set = [](SliceOptions& o, const std::string& v) { o.adaptive.adaptive = v == "true"; };
  t.push_back(number_option("--tolerance", "tolerance", "mm", 0, INFINITY, "",
                            fmt::format("with --adaptive: the largest D a layer may have, mm "
                                        "(implies --adaptive); layers where even the thinnest "
                                        "thickness exceeds it are printed thinnest and counted "
                                        "(default: {:g} with --adaptive, none without)",
                                        kDefaultTolerance)));
  t.back().lo_excluded = true;
  t.back().excludes = {"--layer", "--boundaries", "--max-layers", "--max-time"};
  t.back().set = [](SliceOptions& o, const std::string& v) { o.adaptive.tolerance = number(v); };
  t.push_back(other_option("--max-layers", "maxLayers", K::whole,
                           "with --adaptive: at most this many layers, with the least tolerance "
                           "that allows it (implies --adaptive; default: none)"));
  t.back().lo = 1;
  t.back().hi = 100000;
  t.back().excludes = {"--layer", "--boundaries", "--tolerance", "--max-time"};
  t.back().set = [](SliceOptions& o, const std::string& v) {
    o.adaptive.max_layers = static_cast<std::size_t>(number(v));
  };
  t.push_back(other_option("--max-time", "maxTime", K::duration,
                           "with --adaptive: an estimated print time the plan must fit, as "
                           "1h30m, 90m or 5400s: the --max-layers plan of the most layers "
                           "whose estimate (mid sections, the profile's supports and raft) is "
                           "within it, in fewer layers while the G-code's own estimate is over it "
                           "(implies --adaptive; default: none)"));
  t.back().unit = "s";
  t.back().excludes = {"--layer", "--boundaries", "--tolerance", "--max-layers"};
  t.back().set = [](SliceOptions& o, const std::string& v) {
    o.adaptive.max_seconds = parse_duration(v).value_or(0);
  };

  // The contour, walls and infill, any profile key.
  t.push_back(choice_option("--contour", "contour", "a contour strategy", contour_strategy_names(),
                            fmt::format("the region each layer extrudes: {} (default: best)",
                                        contour_strategies_help())));
  t.back().set = [](SliceOptions& o, const std::string& v) { o.contour = v; };
  t.push_back(other_option("--perimeters", "perimeters", K::whole,
                           "wall loops (default: the printer profile's print.perimeters)"));
  t.back().hi = 50;
  t.back().profile_key = "print.perimeters";
  t.back().set = [](SliceOptions& o, const std::string& v) { o.perimeters = static_cast<int>(number(v)); };
  t.back().profile_default = [](const printer::Profiles& p) {
    return std::to_string(p.printer.print.perimeters);
  };
  t.push_back(number_option("--infill", "infill", "%", 0, 100, "print.infill_density",
                            "sparse infill density, percent (default: the printer profile's "
                            "print.infill_density)"));
  t.back().set = [](SliceOptions& o, const std::string& v) { o.infill = number(v); };
  t.back().profile_default = [](const printer::Profiles& p) { return shown(p.printer.print.infill_density); };
  t.push_back(other_option("--set", "", K::texts,
                           "override a profile key, e.g. --set retraction.length=1.5 or --set "
                           "material.temperature.nozzle=250 (repeatable; default: none)"));
  t.back().set = [](SliceOptions& o, const std::string& v) { o.overrides.push_back(v); };

  // Supports, bridges, brim and raft.
  t.push_back(choice_option("--support", "support", "a support placement", support_placement_names(),
                            "supports under overhangs: none, buildplate (columns from the bed "
                            "only) or everywhere (also from the part's top surfaces); bridges are "
                            "laid with supports only (default: the printer profile's "
                            "support.type)"));
  t.back().profile_key = "support.type";
  t.back().set = [](SliceOptions& o, const std::string& v) { o.support.placement = v; };
  t.back().profile_default = [](const printer::Profiles& p) { return p.printer.support.type; };
  t.push_back(number_option("--overhang-angle", "", "deg", 0, 89, "material.support.overhang_angle",
                            "degrees from vertical a wall may lean without support (default: the "
                            "material's support.overhang_angle)"));
  t.back().set = [](SliceOptions& o, const std::string& v) { o.support.overhang_angle = number(v); };
  t.back().profile_default = [](const printer::Profiles& p) { return shown(p.material.overhang_angle); };
  t.push_back(number_option("--support-xy-gap", "", "mm", 0, 10, "support.xy_gap",
                            "mm between support and the part beside it (default: support.xy_gap)"));
  t.back().set = [](SliceOptions& o, const std::string& v) { o.support.xy_gap = number(v); };
  t.back().profile_default = [](const printer::Profiles& p) { return shown(p.printer.support.xy_gap); };
  t.push_back(number_option("--support-top-distance", "", "mm", 0, 2, "support.top_contact_distance",
                            "mm of air between the support's top and the part over it, rounded "
                            "up to the layers' own tops (default: support.top_contact_distance)"));
  t.back().set = [](SliceOptions& o, const std::string& v) { o.support.top_distance = number(v); };
  t.back().profile_default = [](const printer::Profiles& p) {
    return shown(p.printer.support.top_contact_distance);
  };
  t.push_back(number_option("--support-bottom-distance", "", "mm", 0, 2,
                            "support.bottom_contact_distance",
                            "mm of air between the part and support standing on it (default: "
                            "support.bottom_contact_distance)"));
  t.back().set = [](SliceOptions& o, const std::string& v) { o.support.bottom_distance = number(v); };
  t.back().profile_default = [](const printer::Profiles& p) {
    return shown(p.printer.support.bottom_contact_distance);
  };
  t.push_back(number_option("--support-interface-thickness", "", "mm", 0, 5,
                            "support.interface_thickness",
                            "mm of dense layers at the top of the support at least, rounded up to "
                            "the layers' own tops; 0 for none (default: "
                            "support.interface_thickness)"));
  t.back().set = [](SliceOptions& o, const std::string& v) { o.support.interface_thickness = number(v); };
  t.back().profile_default = [](const printer::Profiles& p) {
    return shown(p.printer.support.interface_thickness);
  };
  t.push_back(choice_option("--support-pattern", "", "a support pattern", {"lines", "grid"},
                            "the support's sparse body: lines or grid (default: support.pattern)"));
  t.back().profile_key = "support.pattern";
  t.back().set = [](SliceOptions& o, const std::string& v) { o.support.pattern = v; };
  t.back().profile_default = [](const printer::Profiles& p) { return p.printer.support.pattern; };
  t.push_back(number_option("--support-spacing", "", "mm", 0.5, 20, "support.spacing",
                            "mm between the support body's lines (default: support.spacing)"));
  t.back().set = [](SliceOptions& o, const std::string& v) { o.support.spacing = number(v); };
  t.back().profile_default = [](const printer::Profiles& p) { return shown(p.printer.support.spacing); };
  t.push_back(other_option("--support-enforcer", "", K::texts,
                           "support every overhang inside the box x0,y0,z0,x1,y1,z1 (mm; X, Y on "
                           "the bed as in the G-code, Z from the bed up), however gentle "
                           "(repeatable; default: support.enforcers)"));
  t.back().profile_key = "support.enforcers";
  t.back().set = [](SliceOptions& o, const std::string& v) { o.support.enforcers.push_back(v); };
  t.push_back(other_option("--support-blocker", "", K::texts,
                           "support no overhang inside the box x0,y0,z0,x1,y1,z1 (repeatable; "
                           "default: support.blockers)"));
  t.back().profile_key = "support.blockers";
  t.back().set = [](SliceOptions& o, const std::string& v) { o.support.blockers.push_back(v); };
  t.push_back(number_option("--bridge-length", "", "mm", 0, 200, "material.bridge.max_length",
                            "mm a bridge may span, held at both ends, before it is supported "
                            "instead; 0 bridges nothing (default: the material's "
                            "bridge.max_length)"));
  t.back().set = [](SliceOptions& o, const std::string& v) { o.support.bridge_length = number(v); };
  t.back().profile_default = [](const printer::Profiles& p) { return shown(p.material.bridge_length); };
  t.push_back(number_option("--brim", "brim", "mm", 0, 50, "brim.width",
                            "brim width round the first layer, mm; 0 for none (default: the "
                            "printer profile's brim.width)"));
  t.back().set = [](SliceOptions& o, const std::string& v) { o.support.brim = number(v); };
  t.back().profile_default = [](const printer::Profiles& p) { return shown(p.printer.brim_width); };
  t.push_back(other_option("--raft", "raft", K::toggle,
                           "print the part on a raft (default: the printer profile's "
                           "raft.enabled)"));
  t.back().off_flag = "--no-raft";
  t.back().off_help =
      "print the part without a raft, on the bed (default: the printer profile's raft.enabled)";
  t.back().profile_key = "raft.enabled";
  t.back().set = [](SliceOptions& o, const std::string& v) { o.support.raft = v == "true"; };
  t.back().profile_default = [](const printer::Profiles& p) {
    return std::string(p.printer.raft.enabled ? "true" : "false");
  };
  return t;
}

// "x0,y0,z0,x1,y1,z1" as a box, or ConfigError naming the option.
printer::SupportBoxMm parse_box(const std::string& text, std::string_view option) {
  printer::SupportBoxMm box{};
  std::string_view rest = text;
  std::size_t count = 0;
  bool ok = true;
  while (ok && !rest.empty()) {
    const std::size_t comma = rest.find(',');
    std::string_view field = rest.substr(0, comma);
    while (!field.empty() && field.front() == ' ') field.remove_prefix(1);
    while (!field.empty() && field.back() == ' ') field.remove_suffix(1);
    double v = 0;
    const auto [end, error] = std::from_chars(field.data(), field.data() + field.size(), v);
    ok = count < 6 && error == std::errc() && end == field.data() + field.size() && std::isfinite(v);
    if (ok) box[count++] = v;
    if (comma == std::string_view::npos) break;
    rest.remove_prefix(comma + 1);
  }
  if (!ok || count != 6 || !(box[0] < box[3] && box[1] < box[4] && box[2] < box[5])) {
    throw printer::ConfigError(fmt::format(
        "{} '{}': needs six numbers x0,y0,z0,x1,y1,z1 (mm; X and Y on the bed as in the G-code, "
        "Z from the bed up to the part) with x0 < x1, y0 < y1 and z0 < z1",
        option, text));
  }
  return box;
}

void apply_support_choices(const SupportChoices& choices, printer::Profiles& profiles) {
  printer::PrinterProfile& machine = profiles.printer;
  printer::SupportSettings& s = machine.support;
  if (!choices.placement.empty()) s.type = choices.placement;
  if (choices.overhang_angle) profiles.material.overhang_angle = *choices.overhang_angle;
  if (choices.xy_gap) s.xy_gap = *choices.xy_gap;
  if (choices.top_distance) s.top_contact_distance = *choices.top_distance;
  if (choices.bottom_distance) s.bottom_contact_distance = *choices.bottom_distance;
  if (choices.interface_thickness) s.interface_thickness = *choices.interface_thickness;
  if (!choices.pattern.empty()) s.pattern = choices.pattern;
  if (choices.spacing) s.spacing = *choices.spacing;
  for (const std::string& box : choices.enforcers) s.enforcers.push_back(parse_box(box, "--support-enforcer"));
  for (const std::string& box : choices.blockers) s.blockers.push_back(parse_box(box, "--support-blocker"));
  if (choices.bridge_length) profiles.material.bridge_length = *choices.bridge_length;
  if (choices.brim) machine.brim_width = *choices.brim;
  if (choices.raft) machine.raft.enabled = *choices.raft;
  if (machine.raft.enabled) {
    for (const auto& [key, thickness] : {std::pair{"raft.base_thickness", machine.raft.base_thickness},
                                         std::pair{"raft.layer_thickness", machine.raft.layer_thickness}}) {
      if (!machine.layer.allows(thickness)) {
        throw printer::ConfigError(fmt::format(
            "--raft: {} = {:g} mm is not a layer thickness the {} allows ({}); set another "
            "with --set {}=...", key, thickness, machine.name, machine.layer.describe(), key));
      }
    }
  }
}

std::vector<const SliceOption*> by_flags(std::initializer_list<std::string_view> flags) {
  std::vector<const SliceOption*> options;
  for (std::string_view flag : flags) options.push_back(find_slice_option_flag(flag));
  return options;
}

}  // namespace

const std::vector<SliceOption>& slice_options() {
  static const std::vector<SliceOption> table = make_table();
  return table;
}

const SliceOption* find_slice_option_flag(std::string_view flag) {
  for (const SliceOption& option : slice_options()) {
    if (option.flag == flag || (!option.off_flag.empty() && option.off_flag == flag)) return &option;
  }
  return nullptr;
}

const SliceOption* find_slice_option_field(std::string_view field) {
  if (field.empty()) return nullptr;
  for (const SliceOption& option : slice_options()) {
    if (option.field == field) return &option;
  }
  return nullptr;
}

std::vector<const SliceOption*> placement_options() {
  return by_flags({"--units", "--scale", "--height", "--up", "--rotate", "--orient", "--ignore-normals"});
}

std::vector<const SliceOption*> adaptive_options(bool print_time) {
  if (print_time) return by_flags({"--adaptive", "--tolerance", "--max-layers", "--max-time"});
  return by_flags({"--adaptive", "--tolerance", "--max-layers"});
}

std::string check_slice_option(const SliceOption& option, const std::string& value) {
  switch (option.kind) {
    case OptionKind::number:
      return number_problem(value, option.lo, option.hi, option.lo_excluded, false);
    case OptionKind::whole:
      return number_problem(value, option.lo, option.hi, option.lo_excluded, true);
    case OptionKind::choice:
      return choice_problem(value, option.choices, option.noun);
    case OptionKind::duration: {
      const std::optional<double> seconds = parse_duration(value);
      if (seconds && *seconds > 0) return {};
      return fmt::format("'{}' is not a duration: give hours, minutes and seconds, as 1h30m, 90m "
                         "or 5400s",
                         value);
    }
    case OptionKind::flag:
    case OptionKind::toggle:
      return value == "true" || value == "false" ? std::string()
                                                 : fmt::format("'{}' is not true or false", value);
    case OptionKind::text:
    case OptionKind::texts:
      return {};
  }
  return {};
}

void set_slice_option(SliceOptions& options, const SliceOption& option, const std::string& value,
                      std::string_view name) {
  if (const std::string problem = check_slice_option(option, value); !problem.empty()) {
    throw OptionError(fmt::format("{}: {}", name, problem));
  }
  option.set(options, value);
}

void check_exclusions(const std::vector<const SliceOption*>& given,
                      std::string (*name_of)(const SliceOption&)) {
  for (std::size_t i = 0; i < given.size(); ++i) {
    for (std::size_t j = i + 1; j < given.size(); ++j) {
      const auto& excluded = given[i]->excludes;
      if (std::find(excluded.begin(), excluded.end(), given[j]->flag) != excluded.end()) {
        throw OptionError(fmt::format("{} and {}: give one of them, not two", name_of(*given[i]),
                                      name_of(*given[j])));
      }
    }
  }
}

std::vector<std::string> model_only_slice_flags() {
  std::vector<std::string> flags;
  for (const SliceOption& option : slice_options()) {
    // The printer and its keys also say how a G-code file is printed.
    if (option.flag == "--printer" || option.flag == "--set") continue;
    flags.emplace_back(option.flag);
    if (!option.off_flag.empty()) flags.emplace_back(option.off_flag);
  }
  return flags;
}

std::vector<std::string> support_placement_names() {
  std::vector<std::string> names;
  for (const geometry::SupportPlacement placement : geometry::kSupportPlacements) {
    names.emplace_back(geometry::support_placement_name(placement));
  }
  return names;
}

std::vector<std::string> contour_strategy_names() {
  std::vector<std::string> names;
  for (const geometry::ContourStrategy& strategy : geometry::contour_strategies()) {
    names.emplace_back(strategy.name);
  }
  return names;
}

std::string contour_strategies_help() {
  std::string text;
  for (const geometry::ContourStrategy& strategy : geometry::contour_strategies()) {
    if (!text.empty()) text += ", ";
    text += fmt::format("{} ({})", strategy.name, strategy.description);
  }
  return text;
}

printer::Profiles load_slice_profiles(const SliceOptions& options) {
  printer::ProfileRequest request;
  request.printer = options.printer;
  request.material = options.material;
  request.config_dir = profile_search_path();
  request.overrides = options.overrides;
  printer::Profiles profiles = printer::load_profiles(request);
  if (options.perimeters) profiles.printer.print.perimeters = *options.perimeters;
  if (options.infill) profiles.printer.print.infill_density = *options.infill;
  apply_support_choices(options.support, profiles);
  return profiles;
}

double uniform_thickness(const SliceOptions& options, const printer::PrinterProfile& machine) {
  return options.layer ? *options.layer : machine.layer.default_thickness;
}

}  // namespace app
