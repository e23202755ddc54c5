// `mahost help [COMMAND ...] [--all]`: the text `mahost --help` and `mahost COMMAND --help`
// print, under one command (the man page is made from `mahost help --all`, so it says the same).
#include <algorithm>
#include <memory>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <fmt/core.h>

#include "host/commands.h"

namespace host {
namespace {

struct HelpOptions {
  std::vector<std::string> command;  // a command and its subcommands: {"profiles", "import"}
  bool all = false;
};

std::string root_help(const CLI::App& app) {
  return app.get_formatter()->make_help(&app, app.get_name(), CLI::AppFormatMode::Normal);
}

// `app`'s commands and theirs, depth first, in the order --help lists them ("help" left out).
void collect(const CLI::App& app, const std::string& prefix,
             std::vector<std::pair<std::string, const CLI::App*>>& out) {
  for (const CLI::App* sub : app.get_subcommands([](const CLI::App* a) { return !a->get_name().empty(); })) {
    if (prefix.empty() && sub->get_name() == "help") continue;
    const std::string path = prefix + sub->get_name();
    out.emplace_back(path, sub);
    collect(*sub, path + " ", out);
  }
}

void run_help(const CLI::App& app, const HelpOptions& options) {
  if (options.all) {
    fmt::print("{}", root_help(app));
    std::vector<std::pair<std::string, const CLI::App*>> commands;
    collect(app, "", commands);
    for (const auto& [path, sub] : commands) {
      const std::size_t space = path.rfind(' ');
      const std::string parents = space == std::string::npos ? "" : " " + path.substr(0, space);
      // "mahost info:" heads the command's help, its summary and usage indented under it (so
      // that help2man makes the heading a section of the man page, the rest its text).
      std::string text = sub->help(app.get_name() + parents);
      const std::size_t head_end = std::min(text.find("\n\n"), text.size());
      std::string head;
      for (std::size_t at = 0; at < head_end;) {
        const std::size_t end = std::min(text.find('\n', at), head_end);
        head += "  " + text.substr(at, end - at) + "\n";
        at = end + 1;
      }
      fmt::print("\n{} {}:\n{}{}", app.get_name(), path, head, text.substr(head_end));
    }
    return;
  }
  const CLI::App* command = &app;
  std::string prefix = app.get_name();
  for (const std::string& word : options.command) {
    const CLI::App* sub = nullptr;
    try {
      sub = command->get_subcommand(word);
    } catch (const CLI::OptionNotFound&) {
    }
    if (!sub || word == "help") {
      throw CommandExit{kExitBadInput,
                        fmt::format("help: '{}' is not a command of {} (see {} --help)", word, prefix, prefix)};
    }
    if (command != &app) prefix += " " + command->get_name();
    command = sub;
  }
  fmt::print("{}", command == &app ? root_help(app) : command->help(prefix));
}

}  // namespace

void add_help_command(CLI::App& app) {
  auto options = std::make_shared<HelpOptions>();
  CLI::App* help = app.add_subcommand("help", "Show the help of mahost or of one command");
  help->footer("`mahost help slice` prints what `mahost slice --help` does; --all prints every "
               "command's help, as the man page (man mahost) has it.");
  help->add_option("COMMAND", options->command,
                   "the command, and its subcommand if it has any (default: none, mahost's own help)");
  help->add_flag("--all", options->all, "every command's help, one after another (default: off)");
  help->callback([&app, options] { run_help(app, *options); });
}

}  // namespace host
