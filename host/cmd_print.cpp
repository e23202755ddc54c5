// `mahost print MODEL.stl|FILE.gcode (--port P [--baud B] | --dry-run) ...` and
// `mahost resume JOURNAL (--port P | --dry-run)`: a print job from the command line, with
// the terminal UI, the control socket for `mahost ctl`, and the journal for `mahost resume`.
// An STL is sliced first by `mahost slice` with the slice options given here.
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <ctime>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <fmt/core.h>

#include "host/commands.h"
#include "host/control_socket.h"
#include "host/print_ui.h"
#include "printer/error.h"
#include "printer/gcode_file.h"
#include "printer/job.h"
#include "printer/journal.h"
#include "printer/line_protocol.h"
#include "printer/serial_link.h"
#include "sim/faults.h"
#include "sim/sim_link.h"

extern char** environ;

namespace host {
namespace {

namespace fs = std::filesystem;

struct LinkOptions {
  std::string port;
  int baud = 115200;
  bool dry_run = false;
  std::string faults;          // dry run only: the simulated printer's faults
  bool advanced_ok = false;    // dry run only: the simulated firmware reports buffer space
  std::size_t window = 1;
  double probe_after = 3;      // s
  std::vector<double> park;    // X,Y
  double lift = 5, retract = 1;
};

struct PrintOptions {
  std::string input;
  LinkOptions link;
  std::vector<int> pause_at;
  std::string journal;
  // Passed to `mahost slice` for an STL.
  std::vector<std::pair<std::string, std::string>> slice_args;
};

struct OpenLink {
  std::unique_ptr<printer::Link> link;
  sim::SimLink* sim = nullptr;  // set for a dry run
};

OpenLink open_link(const LinkOptions& options) {
  OpenLink open;
  if (options.dry_run) {
    sim::Config config;
    config.faults = sim::parse_fault_spec(options.faults);
    config.advanced_ok = options.advanced_ok;
    auto link = std::make_unique<sim::SimLink>(config);
    open.sim = link.get();
    open.link = std::move(link);
  } else {
    if (!options.faults.empty()) {
      throw printer::ConfigError("--faults: only a --dry-run printer can be given faults");
    }
    open.link = std::make_unique<printer::SerialLink>(options.port, options.baud);
  }
  return open;
}

printer::ProtocolOptions protocol_options(const LinkOptions& options) {
  printer::ProtocolOptions p;
  p.window = options.window;
  p.probe_after = std::chrono::milliseconds(static_cast<long>(options.probe_after * 1000));
  return p;
}

printer::PauseOptions pause_options(const LinkOptions& options) {
  printer::PauseOptions p;
  if (options.park.size() == 2) {
    p.park_x = options.park[0];
    p.park_y = options.park[1];
  }
  p.lift = options.lift;
  p.retract = options.retract;
  return p;
}

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
  return s;
}

std::string timestamp() {
  const std::time_t t = std::time(nullptr);
  std::tm tm{};
  localtime_r(&t, &tm);
  char text[32];
  std::strftime(text, sizeof text, "%Y%m%d-%H%M%S", &tm);
  return text;
}

// Runs `mahost slice` (this same binary) so that slicing for a print is exactly `mahost slice`.
void slice_model(const PrintOptions& options, const std::string& gcode_path) {
  std::vector<std::string> argv{"/proc/self/exe", "slice", options.input, "-o", gcode_path};
  for (const auto& [flag, value] : options.slice_args) {
    argv.push_back(flag);
    argv.push_back(value);
  }
  std::vector<char*> args;
  for (std::string& a : argv) args.push_back(a.data());
  args.push_back(nullptr);
  pid_t pid = 0;
  if (posix_spawn(&pid, "/proc/self/exe", nullptr, nullptr, args.data(), environ) != 0) {
    throw std::runtime_error("cannot run mahost slice");
  }
  int status = 0;
  while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    // `mahost slice` already said why on stderr.
    throw CommandExit{WIFEXITED(status) ? WEXITSTATUS(status) : kExitInternal, ""};
  }
}

bool is_stl(const std::string& path) { return lower(fs::path(path).extension().string()) == ".stl"; }

void print_summary(const printer::JobResult& result, const printer::GcodeFile& file,
                   const OpenLink& link, const printer::LineProtocol& protocol,
                   std::chrono::steady_clock::duration wall) {
  const auto& stats = protocol.stats();
  const double wall_s = std::chrono::duration<double>(wall).count();
  std::string where;
  double seconds = std::chrono::duration<double>(result.elapsed).count();
  if (link.sim != nullptr) {
    link.sim->printer().finish();
    seconds = std::max(seconds, link.sim->printer().motion_end_time());
    where = fmt::format("dry run on the simulated printer ({:.1f} s of wall time)", wall_s);
  } else {
    where = fmt::format("on {}", link.link->name());
  }
  fmt::print("{}: {} {} of {} commands, {} layers; print time {} ({}), filament {:.2f} m\n",
             printer::to_string(result.state), where, result.commands_done, file.size(),
             file.layers.size(), clock_text(std::chrono::nanoseconds(static_cast<long long>(seconds * 1e9))),
             link.sim != nullptr ? "on the simulated printer's clock" : "wall clock",
             result.filament_mm / 1000.0);
  fmt::print("link: {} lines sent, {} resent after {} resend requests ({} stale ignored), {} "
             "timeouts probed with M105, {} duplicate oks, {} firmware errors; {} pauses\n",
             stats.lines_sent, stats.lines_resent, stats.resend_requests, stats.stale_resends,
             stats.probes, stats.duplicate_oks, stats.recoverable_errors, result.pauses);
}

void run_job(printer::LineProtocol& protocol, const printer::GcodeFile& file, OpenLink& link,
             printer::JobOptions job_options, const std::string& socket_path) {
  const auto wall_start = std::chrono::steady_clock::now();
  install_print_signals();
  PrintUi ui;
  ControlSocket control(socket_path);
  printer::Job job(protocol, file, std::move(job_options));
  job.on_event = [&](const std::string& line) { ui.event(line); };
  job.on_tick = [&](printer::Job& j) {
    ui.tick(j);
    control.serve(j);
  };
  ui.event(fmt::format("journal: {} (mahost resume it if the print is interrupted)", job.journal_path()));
  ui.event(fmt::format("control: {}: p pause, r resume, c cancel, ! stop{}", 
                       ui.keys() ? "keys" : "mahost ctl pause|resume|cancel|stop|status",
                       ui.keys() ? ", or mahost ctl from another terminal" : ""));
  const printer::JobResult result = job.run();
  ui.finish();
  print_summary(result, file, link, protocol, std::chrono::steady_clock::now() - wall_start);
  if (result.state == printer::JobState::cancelled || result.state == printer::JobState::stopped) {
    throw CommandExit{kExitCancelled, result.reason};
  }
}

void connect(printer::LineProtocol& protocol, const OpenLink& link) {
  protocol.connect(link.sim != nullptr ? std::chrono::milliseconds(500) : std::chrono::milliseconds(3000));
}

void run_print(const PrintOptions& options) {
  if (options.link.dry_run == !options.link.port.empty()) {
    throw printer::ConfigError("print: give either --port PORT or --dry-run");
  }
  for (int layer : options.pause_at) {
    if (layer < 1) throw printer::ConfigError(fmt::format("--pause-at-layer {}: layers count from 1", layer));
  }
  const std::string stem = fs::path(options.input).stem().string();
  const std::string name = fmt::format("{}-{}-{}", stem.empty() ? "job" : stem, timestamp(), ::getpid());
  std::string journal = options.journal;
  if (journal.empty()) journal = (fs::path(printer::job_directory()) / (name + ".journal")).string();
  journal = fs::absolute(journal).string();
  const std::string base = fs::path(journal).replace_extension().string();

  std::string gcode_path = options.input;
  if (is_stl(options.input)) {
    gcode_path = base + ".gcode";
    slice_model(options, gcode_path);
  }
  const printer::GcodeFile file = printer::read_gcode_file(gcode_path);
  for (int layer : options.pause_at) {
    if (static_cast<std::size_t>(layer) > file.layers.size()) {
      throw printer::ConfigError(fmt::format("--pause-at-layer {}: {} has {} layers", layer,
                                             gcode_path, file.layers.size()));
    }
  }
  OpenLink link = open_link(options.link);
  printer::LineProtocol protocol(*link.link, protocol_options(options.link));
  connect(protocol, link);
  if (options.link.window > 1 && !protocol.advanced_ok()) {
    fmt::print(stderr,
               "note: the firmware does not report its buffer space (ADVANCED_OK): --window {} "
               "falls back to one line at a time\n",
               options.link.window);
  }

  printer::JobOptions job_options;
  job_options.pause_at_layers = options.pause_at;
  job_options.pause = pause_options(options.link);
  job_options.journal_path = journal;
  job_options.journal_durable = !options.link.dry_run;
  job_options.journal.job = fs::path(base).filename().string();
  job_options.journal.gcode_path = fs::absolute(gcode_path).string();
  job_options.journal.gcode_hash = file.hash;
  job_options.journal.port = options.link.dry_run ? "" : options.link.port;
  job_options.journal.baud = options.link.dry_run ? 0 : options.link.baud;
  run_job(protocol, file, link, std::move(job_options), base + ".sock");
}

struct ResumeOptions {
  std::string journal;
  LinkOptions link;
};

bool process_is_mahost(int pid) {
  if (pid <= 0 || pid == ::getpid() || ::kill(pid, 0) != 0) return false;
  std::error_code a, b;
  const fs::path theirs = fs::read_symlink(fmt::format("/proc/{}/exe", pid), a);
  const fs::path mine = fs::read_symlink("/proc/self/exe", b);
  return !a && !b && theirs == mine;
}

void run_resume(const ResumeOptions& options) {
  if (options.link.dry_run == !options.link.port.empty()) {
    throw printer::ConfigError("resume: give either --port PORT or --dry-run");
  }
  const std::string journal = fs::absolute(options.journal).string();
  const printer::JournalRecord record = printer::read_journal(journal);
  if (record.state == "completed") {
    throw printer::ConfigError(fmt::format("{}: the job completed; there is nothing to resume", journal));
  }
  if (process_is_mahost(record.pid)) {
    throw printer::ConfigError(fmt::format(
        "{}: the job is still running (process {}); steer it with mahost ctl", journal, record.pid));
  }
  const printer::GcodeFile file = printer::read_gcode_file(record.gcode_path);
  if (file.hash != record.gcode_hash || file.size() != record.commands) {
    throw printer::ConfigError(fmt::format(
        "{}: the file changed since the job started ({} then, {} now): resuming would print a "
        "different part",
        record.gcode_path, record.gcode_hash, file.hash));
  }
  OpenLink link = open_link(options.link);
  printer::LineProtocol protocol(*link.link, protocol_options(options.link));
  connect(protocol, link);

  printer::JobOptions job_options;
  job_options.pause = pause_options(options.link);
  job_options.journal_path = journal;
  job_options.journal_durable = !options.link.dry_run;
  job_options.journal = record;
  job_options.journal.port = options.link.dry_run ? "" : options.link.port;
  job_options.journal.baud = options.link.dry_run ? 0 : options.link.baud;
  job_options.journal.pid = 0;
  job_options.first_command = record.resume_command;
  if (record.layer_index >= 0) {
    job_options.recover_from = record.state_at_resume;
    job_options.printer_restarted = protocol.restart_seen() || link.sim != nullptr;
  }
  const std::string base = fs::path(journal).replace_extension().string();
  run_job(protocol, file, link, std::move(job_options), base + ".sock");
}

void add_link_options(CLI::App& command, LinkOptions& link) {
  auto* port = command.add_option("--port", link.port, "the printer's serial port (/dev/ttyUSB0, /dev/pts/N)");
  auto* dry = command.add_flag("--dry-run", link.dry_run,
                               "print on the in-process simulated printer, at full speed");
  port->excludes(dry);
  command.add_option("--baud", link.baud, "serial speed (default 115200)")->check(CLI::PositiveNumber);
  command.add_option("--window", link.window,
                     "lines in flight (default 1; more only when the firmware reports ADVANCED_OK)")
      ->check(CLI::Range(1, 32));
  command.add_option("--timeout", link.probe_after, "seconds of silence before probing with M105 (default 3)")
      ->check(CLI::Range(0.1, 600.0));
  command.add_option("--faults", link.faults, "dry run: faults of the simulated printer (see mahost sim)");
  command.add_flag("--advanced-ok", link.advanced_ok, "dry run: the simulated firmware reports ADVANCED_OK");
  command.add_option("--park", link.park, "where a pause parks the nozzle: X,Y in mm (default 5,5)")
      ->delimiter(',')
      ->expected(2);
  command.add_option("--lift", link.lift, "how far a pause lifts the nozzle, mm (default 5)")->check(CLI::Range(0.0, 100.0));
  command.add_option("--retract", link.retract, "filament a pause retracts, mm (default 1)")->check(CLI::Range(0.0, 20.0));
}

}  // namespace

void add_print_command(CLI::App& app) {
  auto options = std::make_shared<PrintOptions>();
  auto* print = app.add_subcommand("print", "print an STL model or a G-code file on a printer or a simulated one");
  print->add_option("MODEL", options->input, "the STL model (sliced first) or G-code file")
      ->required()
      ->check(CLI::ExistingFile);
  add_link_options(*print, options->link);
  print->add_option("--pause-at-layer", options->pause_at,
                    "pause before these layers start, counted from 1 (e.g. 20,45)")
      ->delimiter(',');
  print->add_option("--journal", options->journal,
                    "where to keep the job journal (default: a file in $XDG_RUNTIME_DIR/mahost)");
  // Slice options, handed to `mahost slice` for an STL.
  for (const char* flag : {"--printer", "--material", "--layer", "--contour", "--perimeters",
                           "--infill", "--units", "--scale", "--height", "--up"}) {
    print->add_option_function<std::string>(
        flag, [options, flag](const std::string& value) { options->slice_args.emplace_back(flag, value); },
        "slice option (see mahost slice --help)");
  }
  print->add_option_function<std::vector<std::string>>(
      "--set",
      [options](const std::vector<std::string>& values) {
        for (const std::string& v : values) options->slice_args.emplace_back("--set", v);
      },
      "slice option: override a profile key (see mahost slice --help)");
  print->callback([options] { run_print(*options); });

  auto resume_options = std::make_shared<ResumeOptions>();
  auto* resume = app.add_subcommand("resume", "finish a job after the host, the link or the printer died");
  resume->add_option("JOURNAL", resume_options->journal, "the job's journal (printed when it started)")
      ->required()
      ->check(CLI::ExistingFile);
  add_link_options(*resume, resume_options->link);
  resume->callback([resume_options] { run_resume(*resume_options); });
}

}  // namespace host
