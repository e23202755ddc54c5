// The slice options on the command line; see slice_flags.h.
#include "host/slice_flags.h"

#include <cmath>
#include <functional>
#include <memory>
#include <mutex>

#include <fmt/core.h>

#include "host/progress.h"

namespace host {
namespace {

// Sets a checked value wherever the command keeps it.
using Apply = std::function<void(const app::SliceOption& option, const std::string& value)>;

// The validator's text in the help: "0-50", "> 0", "MM > 0", "m|mm|in".
std::string shown_range(const app::SliceOption& option) {
  if (option.kind == app::OptionKind::choice) {
    std::string list;
    for (const std::string& choice : option.choices) list += (list.empty() ? "" : "|") + choice;
    return list;
  }
  const std::string name = option.value_name.empty() ? "" : std::string(option.value_name) + " ";
  if (std::isinf(option.hi)) return fmt::format("{}{} {:g}", name, option.lo_excluded ? ">" : ">=", option.lo);
  return fmt::format("{}{:g}-{:g}", name, option.lo, option.hi);
}

CLI::Validator table_check(const app::SliceOption& option) {
  return CLI::Validator(
      [&option](std::string& text) { return app::check_slice_option(option, text); },
      shown_range(option));
}

// One option of the table as a flag (two for a toggle); returns what it added.
std::vector<CLI::Option*> add_table_option(CLI::App& command, const app::SliceOption& option,
                                           const Apply& apply) {
  const std::string flag(option.flag);
  const auto set = [&option, apply](const std::string& value) { apply(option, value); };
  using K = app::OptionKind;
  switch (option.kind) {
    case K::number:
    case K::whole:
      return {command.add_option_function<std::string>(flag, set, option.help)
                  ->type_name(option.kind == K::number ? "FLOAT" : "INT")
                  ->check(table_check(option))};
    case K::choice:
      return {command.add_option_function<std::string>(flag, set, option.help)
                  ->type_name("TEXT")
                  ->check(table_check(option))};
    case K::duration:
      return {command.add_option_function<std::string>(flag, set, option.help)
                  ->type_name("DURATION")
                  ->check(CLI::Validator(
                      [&option](std::string& text) { return app::check_slice_option(option, text); },
                      ""))};
    case K::text:
      return {command.add_option_function<std::string>(flag, set, option.help)->type_name("TEXT")};
    case K::texts:
      // One value per flag: a model path after it stays the model.
      return {command
                  .add_option_function<std::vector<std::string>>(
                      flag,
                      [set](const std::vector<std::string>& values) {
                        for (const std::string& value : values) set(value);
                      },
                      option.help)
                  ->type_name("TEXT")
                  ->allow_extra_args(false)};
    case K::flag:
      return {command.add_flag_callback(flag, [set] { set("true"); }, option.help)};
    case K::toggle: {
      CLI::Option* on = command.add_flag_callback(flag, [set] { set("true"); }, option.help);
      CLI::Option* off = command.add_flag_callback(std::string(option.off_flag),
                                                   [set] { set("false"); },
                                                   std::string(option.off_help));
      on->excludes(off);
      return {on, off};
    }
  }
  return {};
}

// The options, in the table's order, their exclusions among them, under `group`.
std::vector<CLI::Option*> add_table_options(CLI::App& command,
                                            const std::vector<const app::SliceOption*>& options,
                                            const Apply& apply, const std::string& group) {
  std::vector<CLI::Option*> added;
  for (const app::SliceOption* option : options) {
    for (CLI::Option* flag : add_table_option(command, *option, apply)) added.push_back(flag);
  }
  for (const app::SliceOption* option : options) {
    CLI::Option* flag = command.get_option_no_throw(std::string(option->flag));
    for (std::string_view excluded : option->excludes) {
      if (CLI::Option* other = command.get_option_no_throw(std::string(excluded))) flag->excludes(other);
    }
  }
  if (!group.empty()) {
    for (CLI::Option* flag : added) flag->group(group);
  }
  for (const app::SliceOption* option : options) {
    if (option->hidden) command.get_option(std::string(option->flag))->group("");
  }
  return added;
}

std::vector<const app::SliceOption*> whole_table() {
  std::vector<const app::SliceOption*> options;
  for (const app::SliceOption& option : app::slice_options()) options.push_back(&option);
  return options;
}

// Sets a value on a part of the slice options (the model's placement, the adaptive request)
// that a command keeps on its own.
template <class Part>
Apply apply_to_part(Part& part, Part app::SliceOptions::*member) {
  return [&part, member](const app::SliceOption& option, const std::string& value) {
    app::SliceOptions scratch;
    scratch.*member = part;
    option.set(scratch, value);
    part = std::move(scratch.*member);
  };
}

}  // namespace

void add_slice_options(CLI::App& command, app::SliceOptions& options, const std::string& group) {
  add_table_options(
      command, whole_table(),
      [&options](const app::SliceOption& option, const std::string& value) { option.set(options, value); },
      group);
}

void add_model_options(CLI::App& command, app::ModelOptions& options) {
  command.add_option("MODEL", options.path,
                     "the model: STL (ASCII or binary), 3MF (every object of its build, placed "
                     "together) or OBJ")
      ->required();
  add_placement_options(command, options);
}

void add_placement_options(CLI::App& command, app::ModelOptions& options, const std::string& group) {
  add_table_options(command, app::placement_options(), apply_to_part(options, &app::SliceOptions::model),
                    group);
}

std::vector<CLI::Option*> add_adaptive_options(CLI::App& command, app::AdaptiveRequest& request,
                                               const std::string& group, bool print_time) {
  return add_table_options(command, app::adaptive_options(print_time),
                           apply_to_part(request, &app::SliceOptions::adaptive), group);
}

geometry::Mesh load_model_noting(const app::ModelOptions& options) {
  app::LoadedModel model = app::load_model(options);
  for (const std::string& line : app::model_notes(options, model)) fmt::print(stderr, "mahost: {}\n", line);
  return std::move(model.mesh);
}

app::SliceEvents terminal_slice_events(const std::string& contour) {
  // One bar at a time: a stage's first call (done = 0, on the calling thread) replaces the
  // previous stage's bar, which clears its line.
  struct Bars {
    std::mutex mutex;
    std::unique_ptr<Progress> bar;
    app::SliceStage stage = app::SliceStage::contours;
  };
  auto bars = std::make_shared<Bars>();
  app::SliceEvents events;
  events.progress = [bars, contour](app::SliceStage stage, std::size_t done, std::size_t total) {
    std::lock_guard lock(bars->mutex);
    if (!bars->bar || stage != bars->stage) {
      bars->bar.reset();
      const std::string label = stage == app::SliceStage::contours
                                    ? fmt::format("contours ({})", contour)
                                    : std::string(app::stage_name(stage));
      bars->bar = std::make_unique<Progress>(label, total);
      bars->stage = stage;
    }
    // Planning has no total: the candidate layers measured so far.
    bars->bar->update(done, stage == app::SliceStage::planning
                                ? fmt::format("{} candidate layers measured", done)
                                : fmt::format("layer {}/{}", done, total));
    if (stage == app::SliceStage::writing && done == total && total > 0) bars->bar.reset();
  };
  events.warning = [](const std::string& line) { fmt::print(stderr, "mahost: {}\n", line); };
  return events;
}

}  // namespace host
