// `mahost sim [--pty] [--baud B] [--dialect marlin|teacup|repetier] [--faults SPEC]
//  [--time-scale N|max] [--record OUT.json]
//  [--printed-stl PART.stl] [--queue N] [--advanced-ok] ...`: a simulated Marlin printer on a
// pseudo-terminal (sim/pty_server.h). The first line on stdout is the port to open
// (/dev/pts/N); then a line each time a host opens or closes it; it serves until SIGINT or
// SIGTERM (or a disconnect fault), then writes the record and prints a summary: lines,
// resends, faults injected, print time on the sim clock.
#include <signal.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <memory>
#include <optional>
#include <string>

#include <CLI/CLI.hpp>
#include <fmt/core.h>

#include "app/profile_paths.h"
#include "host/cli_checks.h"
#include "host/commands.h"
#include "host/job_setup.h"
#include "printer/error.h"
#include "printer/profile.h"
#include "sim/faults.h"
#include "sim/pty_server.h"
#include "sim/record.h"
#include "sim/unsupported_extrusion.h"

namespace host {
namespace {

struct SimOptions {
  bool pty = true;
  double baud = 0;
  std::string faults;
  std::string time_scale = "1";
  std::string record_path;
  std::string stl_path;
  std::string printer_profile;
  std::string dialect = "marlin";
  int queue = 4;
  int planner = 15;
  int rx_buffer = 128;
  bool advanced_ok = false;
  bool no_ok_after_resend = false;
  bool no_reset_on_open = false;
  bool no_emergency_parser = false;
  // From a reset (power-on, or a host opening the port: DTR) to `start`: an AVR board's
  // bootloader waits about a second for an upload before Marlin starts (optiboot, stk500v2).
  double boot_time = 1.0;
  bool require_linenumber = false;
  bool no_ack_line_number = false;
};

std::atomic<bool> stop_requested{false};

void request_stop(int) { stop_requested.store(true); }

// Fails now rather than after a long session when an output file cannot be written.
void check_writable(const std::string& path, std::string_view what) {
  if (path.empty()) return;
  std::FILE* file = std::fopen(path.c_str(), "w");
  if (!file) {
    throw printer::ConfigError(fmt::format("cannot write the {} {}: {}; check the folder exists and is writable",
                                           what, path, std::strerror(errno)));
  }
  std::fclose(file);
}

std::string_view state_text(sim::PrinterState state) {
  switch (state) {
    case sim::PrinterState::running: return "running";
    case sim::PrinterState::booting: return "booting";
    case sim::PrinterState::halted: return "halted";
    case sim::PrinterState::disconnected: return "disconnected";
  }
  return "running";
}

// The simulated printer's firmware and, with --printer, the profile's motion and filament, so
// the sim's clock matches the estimate the slicer wrote.
sim::Config sim_config(const SimOptions& options, const printer::PrinterProfile* profile) {
  sim::Config config;
  if (profile != nullptr) {
    config.motion = profile->motion;
    config.filament_diameter = profile->filament_diameter;
  }
  config.faults = sim::parse_fault_spec(options.faults);
  config.dialect = *sim::parse_dialect(options.dialect);
  config.queue_depth = options.queue;
  config.planner_depth = options.planner;
  config.rx_buffer_size = options.rx_buffer;
  config.advanced_ok = options.advanced_ok;
  config.ok_after_resend = !options.no_ok_after_resend;
  config.emergency_parser = !options.no_emergency_parser;
  config.boot_time = options.boot_time;
  config.teacup_require_linenumber = options.require_linenumber;
  config.repetier_ack_with_linenumber = !options.no_ack_line_number;
  return config;
}

// The unsupported-extrusion check of the summary: a 10 mm bridge, a 0.2 mm contact gap, or the
// profile's.
sim::SupportCheckOptions support_check(const printer::PrinterProfile* profile, const std::string& dir) {
  sim::SupportCheckOptions check;
  check.contact_gap = 0.2;
  if (profile != nullptr) {
    check.filament_diameter = profile->filament_diameter;
    check.contact_gap = std::max(profile->support.top_contact_distance, profile->support.bottom_contact_distance);
    check.bridge_length = printer::load_material_profile(profile->default_material, dir).bridge_length;
  }
  return check;
}

sim::PtyOptions pty_options(const SimOptions& options) {
  sim::PtyOptions pty;
  pty.time_scale = parse_time_scale(options.time_scale);
  pty.baud = options.baud;
  pty.reset_on_open = !options.no_reset_on_open;
  // One line per session, so whoever watches the terminal sees the host come and go.
  pty.on_session = [reset = pty.reset_on_open](bool opened) {
    fmt::print("{}\n", opened ? (reset ? "host opened the port: the board resets"
                                       : "host opened the port")
                              : "host closed the port");
    std::fflush(stdout);
  };
  return pty;
}

// SIGINT and SIGTERM end the serving (request_stop).
void install_stop_handlers() {
  struct sigaction action {};
  action.sa_handler = request_stop;
  sigemptyset(&action.sa_mask);
  action.sa_flags = 0;  // no SA_RESTART: a signal ends the wait at once
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
}

// What the session did, on stdout, a line per subject.
void print_sim_summary(const sim::PtyServer& server, const SimOptions& options, const sim::Config& config,
                       const sim::SupportCheckOptions& check) {
  const sim::Printer& printer = server.printer();
  const sim::Counters& n = printer.counters();
  // A disconnect's reason says so itself; a halt's says why.
  std::string state(state_text(printer.state()));
  if (printer.state() == sim::PrinterState::disconnected) state = printer.stop_reason();
  if (printer.state() == sim::PrinterState::halted) state += ": " + printer.stop_reason();
  fmt::print("printer     {}, port opened {} time{}\n", state, server.opens(),
             server.opens() == 1 ? "" : "s");
  fmt::print("lines       {} accepted, {} commands executed, {} unknown\n", n.lines, n.commands,
             n.unknown_commands);
  fmt::print("resends     {} ({} line errors)\n", n.resends, n.errors);
  fmt::print("faults      {} injected{}\n", n.faults_injected,
             options.faults.empty() ? "" : " (" + sim::to_string(config.faults) + ")");
  fmt::print("overflows   {} ({} bytes lost)\n", n.overflows, n.overflow_bytes);
  fmt::print("print time  {:.1f} s on the sim clock, {:.1f} s of motion, {:.1f} mm of filament\n",
             printer.now(), printer.motion_time(), printer.deposition().filament_used());
  fmt::print("deposited   {}\n",
             sim::unsupported_summary(sim::check_unsupported_extrusion(printer.deposition(), check), check));
  if (!options.record_path.empty()) fmt::print("record      {}\n", options.record_path);
  if (!options.stl_path.empty()) fmt::print("printed     {}\n", options.stl_path);
}

void run_sim(const SimOptions& options) {
  const std::string dir = app::profile_search_path();
  std::optional<printer::PrinterProfile> profile;
  if (!options.printer_profile.empty()) profile = printer::load_printer_profile(options.printer_profile, dir);
  const printer::PrinterProfile* machine = profile ? &*profile : nullptr;
  const sim::SupportCheckOptions check = support_check(machine, dir);
  const sim::Config config = sim_config(options, machine);
  const sim::PtyOptions pty = pty_options(options);
  check_writable(options.record_path, "record");
  check_writable(options.stl_path, "printed part");

  sim::PtyServer server(config, pty);
  // Handlers first: whoever reads the port may signal at once.
  install_stop_handlers();
  fmt::print("{}\n", server.path());
  std::fflush(stdout);
  server.serve(stop_requested);

  if (!options.record_path.empty()) sim::write_record_json(server.printer(), options.record_path);
  if (!options.stl_path.empty()) sim::write_printed_stl(server.printer(), options.stl_path);
  print_sim_summary(server, options, config, check);
}

}  // namespace

void add_sim_command(CLI::App& app) {
  auto options = std::make_shared<SimOptions>();
  CLI::App* sim = app.add_subcommand(
      "sim",
      "Run a simulated Marlin printer on a pseudo-terminal: prints the port (/dev/pts/N) "
      "first, then a line as each host opens and closes it, serves until Ctrl-C, then prints "
      "lines, resends, faults and print time.");
  sim->add_flag("--pty", options->pty, "serve on a pseudo-terminal (the default and only mode)");
  sim->add_option("--baud", options->baud,
                  "pace bytes like a UART at this rate, 10 bits a byte: one of " +
                      printer::standard_baud_rates_text() + " (default: no pacing)")
      ->check(standard_baud_rate());
  sim->add_option("--dialect", options->dialect,
                  "the firmware it speaks as: " + sim::dialect_names() +
                      " (replies, resend requests, errors and commands as that firmware's own; "
                      "default: marlin)")
      ->check(CLI::IsMember({"marlin", "teacup", "repetier"}))
      ->capture_default_str();
  sim->add_option("--faults", options->faults,
                  "faults to inject, e.g. corrupt=0.01,drop-ok=0.01,resend=0.01,delay=50ms,"
                  "disconnect-at-line=5000,halt-at-line=N,freeze-at-line=N,runaway-at-line=N,seed=42");
  sim->add_option("--time-scale", options->time_scale,
                  "sim time per wall time: 1 = real time, N = N times faster, max = no waiting")
      ->capture_default_str();
  sim->add_option("--record", options->record_path,
                  "write the executed commands, counters and deposition record as JSON on exit");
  sim->add_option("--printed-stl", options->stl_path, "write the printed part as STL on exit");
  sim->add_option("--printer", options->printer_profile,
                  "printer profile (name or .toml) for motion limits and filament diameter, "
                  "and with its material for the unsupported-extrusion check's bridge length "
                  "and contact gap (default: Marlin's stock limits, 1.75 mm filament, 10 mm "
                  "bridges, 0.2 mm gap)");
  sim->add_option("--queue", options->queue, "command queue depth (Marlin's BUFSIZE)")
      ->check(whole_number_in(1, 64))
      ->capture_default_str();
  sim->add_option("--planner", options->planner, "moves the planner holds (Marlin's BLOCK_BUFFER_SIZE less the one it keeps free)")
      ->check(whole_number_in(1, 256))
      ->capture_default_str();
  sim->add_option("--rx-buffer", options->rx_buffer, "serial receive buffer, bytes")
      ->check(whole_number_in(16, 65536))
      ->capture_default_str();
  sim->add_flag("--advanced-ok", options->advanced_ok, "answer ok N<line> P<planner> B<queue>");
  sim->add_flag("--no-ok-after-resend", options->no_ok_after_resend,
                "send no ok after Resend: (as Marlin 2.0.9 did; 2.1 sends it)");
  sim->add_option("--boot-time", options->boot_time,
                  "seconds from a reset (power-on, or a host opening the port) to 'start', on the "
                  "sim clock; what arrives meanwhile is lost (a bootloader's wait)")
      ->check(number_in(0.0, 60.0))
      ->capture_default_str();
  sim->add_flag("--require-linenumber", options->require_linenumber,
                "teacup: built with REQUIRE_LINENUMBER, so lines need a number from the expected "
                "one up (default: off, numbers ignored, as Teacup ships)");
  sim->add_flag("--no-ack-line-number", options->no_ack_line_number,
                "repetier: built without ACK_WITH_LINENUMBER, a plain ok (default: ok <n>)");
  sim->add_flag("--no-reset-on-open", options->no_reset_on_open,
                "keep state when a host opens the port (a board that ignores DTR)");
  sim->add_flag("--no-emergency-parser", options->no_emergency_parser,
                "M112/M108/M410 wait in the queue like other commands");
  sim->callback([options] { run_sim(*options); });
}

}  // namespace host
