// mahost: a 3D model to a printed part. Parses the command line, runs one subcommand, and turns
// every error into one line on stderr and an exit code (host/commands.h).
#include <charconv>
#include <cstdio>
#include <exception>
#include <new>

#include <CLI/CLI.hpp>
#include <fmt/core.h>

#include "app/error.h"
#include "host/commands.h"
#include "printer/error.h"

namespace {

// One line per command, in the order a user meets them; see host/commands.h.
void add_commands(CLI::App& app) {
  host::add_info_command(app);
  host::add_slice_command(app);
  host::add_print_command(app);
  host::add_serve_command(app);
  host::add_ctl_command(app);
  host::add_ports_command(app);
  host::add_sim_command(app);
  host::add_analyze_command(app);
  host::add_profiles_command(app);
  host::add_help_command(app);
}

// "mahost --bogus" or "mahost bogus": the unknown word is the news, not the missing subcommand
// CLI11 reports first.
int missing_subcommand_exit(CLI::App& app, const CLI::RequiredError& e) {
  const std::vector<std::string> unknown = app.remaining(true);
  if (!unknown.empty()) {
    fmt::print(stderr, "mahost: unknown {} '{}' (see mahost --help)\n",
               unknown.front().rfind("-", 0) == 0 ? "option" : "command", unknown.front());
  } else {
    fmt::print(stderr, "mahost: {} (see mahost --help)\n", e.what());
  }
  return host::kExitBadInput;
}

// CLI11 says "Could not convert: --pause-at-layer = abc"; what the user gave first.
int conversion_error_exit(const CLI::ConversionError& e) {
  const std::string what = e.what();
  const std::string prefix = "Could not convert: ";
  const auto equals = what.find(" = ");
  if (what.rfind(prefix, 0) == 0 && equals != std::string::npos) {
    const std::string value = what.substr(equals + 3);
    double number = 0;
    const auto [end, ec] = std::from_chars(value.data(), value.data() + value.size(), number);
    const bool a_number = ec == std::errc() && end == value.data() + value.size();
    fmt::print(stderr, "mahost: {}: '{}' is not {} (see mahost --help)\n",
               what.substr(prefix.size(), equals - prefix.size()), value,
               a_number ? "a whole number" : "a number");
  } else {
    fmt::print(stderr, "mahost: {} (see mahost --help)\n", what);
  }
  return host::kExitBadInput;
}

// The one line on stderr for an error, and the exit code that goes with it.
int error_exit(const char* message, int code) {
  fmt::print(stderr, "mahost: {}\n", message);
  return code;
}

}  // namespace

int main(int argc, char** argv) {
  // Named, not taken from argv[0]: the usage lines say "mahost" wherever it was run from (and
  // the man page, which help2man makes by running the built binary, names no build folder).
  CLI::App app{"mahost: slice 3D models (STL, 3MF, OBJ) with medial-axis contours and print "
               "them on a Marlin-style printer",
               "mahost"};
  app.set_version_flag("--version", "mahost " MAHOST_VERSION);
  app.require_subcommand(1);
  app.fallthrough(false);
  add_commands(app);

  try {
    app.parse(argc, argv);
    return host::kExitOk;
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::RequiredError& e) {
    return missing_subcommand_exit(app, e);
  } catch (const CLI::ConversionError& e) {
    return conversion_error_exit(e);
  } catch (const CLI::ParseError& e) {
    fmt::print(stderr, "mahost: {} (see mahost --help)\n", e.what());
    return host::kExitBadInput;
  } catch (const host::CommandExit& e) {
    if (!e.message.empty()) fmt::print(stderr, "mahost: {}\n", e.message);
    return e.code;
  } catch (const app::InputError& e) {
    return error_exit(e.what(), host::kExitBadInput);
  } catch (const printer::ConfigError& e) {
    return error_exit(e.what(), host::kExitBadInput);
  } catch (const printer::LinkError& e) {
    return error_exit(e.what(), host::kExitPrinter);
  } catch (const printer::PrinterError& e) {
    return error_exit(e.what(), host::kExitPrinter);
  } catch (const std::bad_alloc&) {
    return error_exit("out of memory", host::kExitInternal);
  } catch (const std::exception& e) {
    fmt::print(stderr, "mahost: internal error: {} (please report this)\n", e.what());
    return host::kExitInternal;
  }
}
