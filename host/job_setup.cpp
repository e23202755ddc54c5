#include "host/job_setup.h"

#include <signal.h>
#include <unistd.h>

#include <charconv>
#include <ctime>
#include <filesystem>
#include <thread>

#include <fmt/core.h>

#include "host/cli_checks.h"
#include "host/local_time.h"
#include "printer/error.h"
#include "printer/serial_link.h"
#include "sim/dialect.h"
#include "sim/faults.h"

namespace host {

namespace fs = std::filesystem;

void add_link_options(CLI::App& command, LinkOptions& link, const std::string& baud_default,
                      const std::string& dry_run_help) {
  auto* port = command.add_option("--port", link.port,
                                  "the printer's serial port, e.g. /dev/ttyUSB0 or /dev/pts/N "
                                  "(see mahost ports; no default: give --port or --dry-run)")
                   ->group(kLinkGroup);
  auto* dry = command.add_flag("--dry-run", link.dry_run, dry_run_help)->group(kLinkGroup);
  port->excludes(dry);
  command.add_option("--baud", link.baud,
                     "serial speed, bit/s: one of " + printer::standard_baud_rates_text() +
                         " (default: " + baud_default + ")")
      ->check(standard_baud_rate())
      ->group(kLinkGroup);
  command.add_option("--window", link.window,
                     "lines in flight; more than 1 only when the firmware reports ADVANCED_OK "
                     "(default: 1)")
      ->check(whole_number_in(1, 32))
      ->group(kLinkGroup);
  command.add_option("--timeout", link.probe_after,
                     "silence before the host probes the printer with M105, s (default: 3)")
      ->check(number_in(0.1, 600.0))
      ->group(kLinkGroup);
  command.add_option("--faults", link.faults,
                     "faults of the simulated printer, e.g. corrupt=0.01,drop-ok=0.01,seed=3 "
                     "(see mahost sim --help; default: none)")
      // Checked as the command line is read, before a model is sliced for it.
      ->check(CLI::Validator(
          [](std::string& spec) -> std::string {
            try {
              sim::parse_fault_spec(spec);
            } catch (const printer::ConfigError& e) {
              return e.what();
            }
            return {};
          },
          "SPEC"))
      ->group(kDryRunGroup);
  command.add_flag("--advanced-ok", link.advanced_ok,
                   "the simulated firmware reports its buffer space (ADVANCED_OK), so --window "
                   "takes effect (default: off)")
      ->group(kDryRunGroup);
  command.add_option("--dialect", link.dialect,
                     "the firmware the simulated printer speaks as: " + sim::dialect_names() +
                         " (default: the printer profile's firmware)")
      ->check(CLI::IsMember({"marlin", "teacup", "repetier"}))
      ->group(kDryRunGroup);
  command.add_flag("--force", link.force,
                   "leave out the file's lines that are not G-code, and say how many, instead "
                   "of refusing the file (default: off)")
      ->group(kJobGroup);
  command.add_option("--park", link.park, "where a pause parks the nozzle: X,Y, mm (default: 5,5)")
      ->delimiter(',')
      ->expected(2)
      ->group(kJobGroup);
  command.add_option("--lift", link.lift, "how far a pause lifts the nozzle, mm (default: 5)")
      ->check(number_in(0.0, 100.0))
      ->group(kJobGroup);
  command.add_option("--retract", link.retract, "filament a pause retracts, mm (default: 1)")
      ->check(number_in(0.0, 20.0))
      ->group(kJobGroup);
}

void check_link_choice(const LinkOptions& link, const char* command) {
  if (link.dry_run == !link.port.empty()) {
    throw printer::ConfigError(fmt::format("{}: give either --port PORT or --dry-run", command));
  }
}

double parse_time_scale(const std::string& text, const std::string& flag) {
  if (text == "max") return 0;
  double value = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (ec != std::errc() || end != text.data() + text.size() || !(value > 0) || value > 1e6) {
    throw printer::ConfigError(fmt::format(
        "{} {}: give a speed-up factor above 0 (1 = real time, 10 = ten times "
        "faster) or max",
        flag, text));
  }
  return value;
}

OpenLink open_link(const LinkOptions& options, const printer::PrinterProfile& machine, int baud) {
  OpenLink open;
  if (options.dry_run) {
    sim::Config config;
    config.faults = sim::parse_fault_spec(options.faults);
    config.advanced_ok = options.advanced_ok;
    config.motion = machine.motion;
    config.filament_diameter = machine.filament_diameter;
    config.time_scale = options.time_scale;
    // The firmware the printer profile names (`--set firmware=teacup`), unless --dialect says.
    const std::string_view dialect =
        !options.dialect.empty() ? std::string_view(options.dialect) : printer::dialect_of(machine.firmware).name;
    if (const auto d = sim::parse_dialect(dialect)) config.dialect = *d;
    auto link = std::make_unique<sim::SimLink>(config);
    open.sim = link.get();
    open.link = std::move(link);
  } else {
    if (!options.faults.empty()) {
      throw printer::ConfigError("--faults: only a --dry-run printer can be given faults");
    }
    if (options.advanced_ok) {
      throw printer::ConfigError(
          "--advanced-ok: only a --dry-run printer can be told to report ADVANCED_OK; a real "
          "one says so itself");
    }
    if (!options.dialect.empty()) {
      throw printer::ConfigError(
          "--dialect: only a --dry-run printer can be told which firmware to speak as; a real "
          "one says so itself in reply to M115");
    }
    open.link = std::make_unique<printer::SerialLink>(options.port, baud);
  }
  return open;
}

printer::ProtocolOptions protocol_options(const LinkOptions& options, const printer::PrinterProfile& machine) {
  printer::ProtocolOptions p;
  p.window = options.window;
  p.probe_after = std::chrono::milliseconds(static_cast<long>(options.probe_after * 1000));
  p.assumed_firmware = machine.firmware;
  return p;
}

printer::GcodeFile read_job_gcode(const std::string& path, const LinkOptions& options) {
  printer::GcodeFile file = printer::read_gcode_file(path, printer::GcodeReading{options.force});
  if (file.skipped_lines > 0) {
    std::string lines;
    for (const std::size_t n : file.skipped_line_numbers) lines += (lines.empty() ? "" : ", ") + std::to_string(n);
    fmt::print(stderr, "note: --force: left out {} line{} that {} not G-code (line{} {}{})\n",
               file.skipped_lines, file.skipped_lines == 1 ? "" : "s",
               file.skipped_lines == 1 ? "is" : "are", file.skipped_line_numbers.size() == 1 ? "" : "s",
               lines, file.skipped_lines > file.skipped_line_numbers.size() ? ", ..." : "");
  }
  return file;
}

printer::PauseOptions pause_options(const LinkOptions& options, const printer::PrinterProfile& machine) {
  printer::PauseOptions p;
  if (options.park.size() == 2) {
    p.park_x = options.park[0];
    p.park_y = options.park[1];
  }
  p.lift = options.lift;
  p.retract = options.retract;
  p.max_z = machine.bed_z;
  return p;
}

void connect(printer::LineProtocol& protocol, const OpenLink& link) {
  protocol.connect(link.sim != nullptr ? std::chrono::milliseconds(500) : std::chrono::milliseconds(3000));
}

std::chrono::milliseconds wait_real_time() {
  const auto before = std::chrono::steady_clock::now();
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  return std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::steady_clock::now() - before);
}

std::string job_name(const std::string& stem) {
  return fmt::format("{}-{}-{}", stem.empty() ? "job" : stem, local_time("%Y%m%d-%H%M%S"), ::getpid());
}

printer::JobOptions job_options_for(const printer::GcodeFile& file, const std::string& gcode_path,
                                    const printer::PrinterProfile& machine,
                                    const LinkOptions& link, int baud, const std::string& journal) {
  printer::JobOptions job;
  job.pause = pause_options(link, machine);
  job.motion = machine.motion;
  job.journal_path = journal;
  job.journal_durable = !link.dry_run;
  job.journal.job = fs::path(journal).stem().string();
  job.journal.gcode_path = fs::absolute(gcode_path).string();
  job.journal.gcode_hash = file.hash;
  job.journal.printer = fs::absolute(machine.source).string();
  job.journal.firmware = std::string(printer::dialect_of(machine.firmware).name);
  job.journal.port = link.dry_run ? "" : link.port;
  job.journal.baud = link.dry_run ? 0 : baud;
  return job;
}

bool other_mahost_running(int pid) {
  if (pid <= 0 || pid == ::getpid() || ::kill(pid, 0) != 0) return false;
  std::error_code a, b;
  const fs::path theirs = fs::read_symlink(fmt::format("/proc/{}/exe", pid), a);
  const fs::path mine = fs::read_symlink("/proc/self/exe", b);
  return !a && !b && theirs == mine;
}

void remove_files(const std::vector<std::string>& paths) {
  for (const std::string& path : paths) {
    std::error_code ignored;
    fs::remove(path, ignored);
    fs::remove(path + ".tmp", ignored);  // a journal write cut short
  }
}

}  // namespace host
