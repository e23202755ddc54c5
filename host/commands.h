// The mahost subcommands. Each lives in its own cmd_<name>.cpp and registers itself on the
// app with one call from main.cpp; its callback runs the command and throws typed errors
// (geometry::InputError, printer::ConfigError, ...) that main.cpp turns into one line and an
// exit code.
#pragma once

#include <CLI/CLI.hpp>

namespace host {

// Exit codes, documented in docs/guide.md ("Good to know").
inline constexpr int kExitOk = 0;
inline constexpr int kExitInternal = 1;    // a bug: please report it
inline constexpr int kExitBadInput = 2;    // a flag, file, profile or value that cannot be used
inline constexpr int kExitPrinter = 3;     // the printer or its link failed
inline constexpr int kExitCancelled = 4;   // the user cancelled or stopped the job
inline constexpr int kExitInterrupted = 130;

// A command that wants to end the process with a given code and a message (e.g. a job the
// user cancelled) throws this; main.cpp prints the message, if any, and exits with the code.
struct CommandExit {
  int code = kExitOk;
  std::string message;
};

// `mahost info`: host/cmd_info.cpp.
void add_info_command(CLI::App& app);
// `mahost slice`: host/cmd_slice.cpp.
void add_slice_command(CLI::App& app);

// `mahost sim`: host/cmd_sim.cpp.
void add_sim_command(CLI::App& app);
// `mahost print` and `mahost resume`: host/cmd_print.cpp.
void add_print_command(CLI::App& app);
// `mahost serve`: host/cmd_serve.cpp and host/serve/.
void add_serve_command(CLI::App& app);
// `mahost ctl`: host/cmd_ctl.cpp.
void add_ctl_command(CLI::App& app);
// `mahost ports`: host/cmd_ports.cpp.
void add_ports_command(CLI::App& app);
void add_analyze_command(CLI::App& app);  // `mahost analyze` and `mahost advise`: host/cmd_analyze.cpp
// `mahost profiles list` and `mahost profiles import`: host/cmd_profiles.cpp.
void add_profiles_command(CLI::App& app);
// `mahost help`: host/cmd_help.cpp.
void add_help_command(CLI::App& app);

}  // namespace host
