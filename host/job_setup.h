// What `mahost print`, `mahost resume` and `mahost serve` share to start a print job: the
// printer link and its options (a serial port or the in-process simulated printer), the
// protocol and pause options built from them, the job's name and journal path, and the
// journal fields and options of a job that streams a G-code file (DESIGN.md §4).
//
// A dry run simulates the printer the job is for: its motion limits and filament diameter,
// at the speed the options give (as fast as possible unless said otherwise).
#pragma once

#include <chrono>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "printer/gcode_file.h"
#include "printer/job.h"
#include "printer/line_protocol.h"
#include "printer/link.h"
#include "printer/pause.h"
#include "printer/profile.h"
#include "sim/sim_link.h"
#include "sim/unsupported_extrusion.h"

namespace host {

inline constexpr const char* kLinkGroup = "Printer link";
inline constexpr const char* kDryRunGroup = "Dry run (the in-process simulated printer)";
inline constexpr const char* kJobGroup = "Job";

struct LinkOptions {
  std::string port;
  int baud = 0;                // bit/s; 0: the printer profile's (print) or the journal's (resume)
  bool dry_run = false;
  std::string faults;          // dry run only: the simulated printer's faults
  bool advanced_ok = false;    // dry run only: the simulated firmware reports buffer space
  double time_scale = 0;       // dry run only: sim time per wall time (0: as fast as possible)
  std::string dialect;         // dry run only: the simulated firmware's dialect ("": the profile's)
  bool force = false;          // leave out lines that are not G-code instead of refusing
  std::size_t window = 1;
  double probe_after = 3;      // s
  std::vector<double> park;    // X,Y
  double lift = 5, retract = 1;
};

// Adds --port, --dry-run, --baud, --window, --timeout, --faults, --advanced-ok, --dialect,
// --force, --park, --lift and --retract. `dry_run_help` says what --dry-run does for this command.
void add_link_options(CLI::App& command, LinkOptions& link, const std::string& baud_default,
                      const std::string& dry_run_help);

// Throws ConfigError unless exactly one of --port and --dry-run was given.
void check_link_choice(const LinkOptions& link, const char* command);

// "1" -> 1, "20" -> 20, "max" -> 0 (as fast as possible): --time-scale's value. Throws
// ConfigError naming the flag for anything else.
double parse_time_scale(const std::string& text, const std::string& flag = "--time-scale");

struct OpenLink {
  std::unique_ptr<printer::Link> link;
  sim::SimLink* sim = nullptr;  // set for a dry run
  // A dry run of a whole print is checked for unsupported extrusion with these; set by the
  // command after opening.
  std::optional<sim::SupportCheckOptions> check;
};

// Opens the link: the simulated `machine` for a dry run (speaking the firmware its profile
// names unless --dialect says), else the serial port at `baud`.
// Throws ConfigError for dry-run options given with a port, LinkError for a port that
// cannot be opened.
OpenLink open_link(const LinkOptions& options, const printer::PrinterProfile& machine, int baud);

// `machine`: the firmware its profile names is assumed where the firmware does not say.
printer::ProtocolOptions protocol_options(const LinkOptions& options, const printer::PrinterProfile& machine);

// Reads the job's G-code, checked line by line before anything is sent (throws GcodeError
// naming the first bad line); with --force the lines that are not G-code are left out, and
// said so on stderr.
printer::GcodeFile read_job_gcode(const std::string& path, const LinkOptions& options);
printer::PauseOptions pause_options(const LinkOptions& options, const printer::PrinterProfile& machine);

// Starts the protocol on the link: the simulated board answers at once, a real one may take
// seconds to boot after its port opens.
void connect(printer::LineProtocol& protocol, const OpenLink& link);

// A dry run's wait while paused at full speed: real time, and the simulated clock runs no
// longer than that (see printer::JobOptions::paused_wait).
std::chrono::milliseconds wait_real_time();

// "<stem>-<date>-<time>-<pid>", the name of a job (its journal, socket and sliced G-code
// share it); "job-..." for an empty stem.
std::string job_name(const std::string& stem);

// The options of a job that prints `file` (at `gcode_path`) for `machine` with its journal at
// `journal` (absolute; "" keeps none): pauses, motion limits, the journal's fields (port and
// baud left empty for a dry run, its records not fsync'ed). resume_command is left unset.
printer::JobOptions job_options_for(const printer::GcodeFile& file, const std::string& gcode_path,
                                    const printer::PrinterProfile& machine,
                                    const LinkOptions& link, int baud, const std::string& journal);

// True when `pid` is another live process of this very mahost binary (a journal's writer
// still printing), false for this process, a dead one or another program.
bool other_mahost_running(int pid);

// Removes the files, and a journal write cut short beside each; missing ones are fine.
void remove_files(const std::vector<std::string>& paths);

}  // namespace host
