// `mahost print MODEL.stl|FILE.gcode (--port P [--baud B] | --dry-run) ...` and
// `mahost resume JOURNAL (--port P | --dry-run)`: a print job from the command line, with
// the terminal UI, the control socket for `mahost ctl`, and the journal for `mahost resume`.
// An STL is sliced first, in this process, by the slice pipeline (app/slice.h) with
// the same options as `mahost slice`.
//
// The files of a job: its journal, control socket and (for an STL) sliced G-code, in the job
// directory (printer::job_directory()). A dry run removes what it made when it ends, however
// it ends; a print removes them once it completes and keeps them otherwise, for `mahost
// resume`. --keep keeps them; a journal named with --journal is kept (it says "completed"),
// with the G-code it names; -o keeps the sliced G-code there.
#include <malloc.h>
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <fmt/core.h>

#include "app/job.h"
#include "app/model.h"
#include "app/slice.h"
#include "app/stage_options.h"
#include "host/check_while_connecting.h"
#include "host/commands.h"
#include "host/control_socket.h"
#include "host/job_setup.h"
#include "host/print_ui.h"
#include "host/slice_flags.h"
#include "printer/bead_model.h"
#include "printer/error.h"
#include "printer/gcode_file.h"
#include "printer/gcode_writer.h"
#include "printer/job.h"
#include "printer/journal.h"
#include "printer/line_protocol.h"
#include "printer/profile.h"
#include "printer/serial_link.h"
#include "sim/faults.h"
#include "sim/unsupported_extrusion.h"

namespace host {
namespace {

namespace fs = std::filesystem;

constexpr const char* kSliceGroup = "Slicing (a model; see mahost slice --help)";
constexpr const char* kDryRunHelp =
    "print on the in-process simulated printer, at full speed (a pause waits in real time), "
    "instead of a port (default: off; give --port or --dry-run)";

struct PrintOptions {
  std::string input;
  LinkOptions link;
  std::vector<int> pause_at;
  std::string journal;         // --journal: the user's path, kept
  std::string output;          // -o: where to keep the sliced G-code
  bool keep = false;
  app::SliceOptions slice;
  std::vector<std::string> model_options_given;  // slice options that need an STL, as given
};

bool in_job_directory(const std::string& path) {
  return fs::path(path).parent_path() == fs::path(printer::job_directory());
}

// The files a job made for itself, removed when it ends unless kept (see the file comment).
class JobFiles {
 public:
  JobFiles() = default;
  JobFiles(const JobFiles&) = delete;
  JobFiles& operator=(const JobFiles&) = delete;
  ~JobFiles() {
    if (!kept_) remove_files(paths_);
  }
  void add(const std::string& path) { paths_.push_back(path); }
  void keep() { kept_ = true; }

 private:
  std::vector<std::string> paths_;
  bool kept_ = false;
};

// "1 pause", "3 pauses".
std::string count_text(long n, const char* one, const char* many) {
  return fmt::format("{} {}", n, n == 1 ? one : many);
}

// "print time ... (estimated ...)" and where the job ran. The print time is what the print
// took, pauses not counted (what the same print takes unpaused); how long it stood paused is
// said beside it. On the simulated printer it runs to the end of the planned moves.
struct TimeAndPlace {
  std::string where;
  std::string time;
};

TimeAndPlace time_and_place(const printer::JobResult& result, const OpenLink& link,
                            std::optional<double> estimated_seconds, bool resumed) {
  const double elapsed = std::chrono::duration<double>(result.elapsed).count();
  const double paused = std::chrono::duration<double>(result.paused).count();
  const std::string paused_note =
      result.pauses > 0 ? fmt::format(" ({} paused, not counted)", printer::format_duration(paused)) : "";
  const std::string estimate =
      estimated_seconds ? fmt::format("estimated {}{}", printer::format_duration(*estimated_seconds),
                                      resumed ? " for the layers resumed" : "")
                        : "no estimate: the job ended before the model read the file";
  if (link.sim == nullptr) {
    return {fmt::format("on {}", link.link->name()),
            fmt::format("print time {}{} ({} of motion; heating not counted)",
                        printer::format_duration(elapsed - paused), paused_note, estimate)};
  }
  sim::Printer& printer = link.sim->printer();
  const double job_start = std::chrono::duration<double>(link.link->now()).count() - elapsed;
  printer.finish();  // the moves still in the planner run out
  const double seconds = std::max(elapsed, printer.motion_end_time() - job_start) - paused;
  return {"dry run on the simulated printer",
          fmt::format("print time {} on the simulated printer's clock{}: {} of motion ({}), "
                      "the rest heating and waiting",
                      printer::format_duration(seconds), paused_note,
                      printer::format_duration(printer.motion_time()), estimate)};
}

// "filament 4.85 m", with its weight when the job was sliced here (the material is known).
std::string filament_text(double filament_mm, const printer::Profiles* sliced_for) {
  std::string filament = fmt::format("filament {:.2f} m", filament_mm / 1000.0);
  if (sliced_for != nullptr) {
    filament += fmt::format(" ({:.1f} g {})",
                            printer::filament_weight(filament_mm, sliced_for->printer.filament_diameter,
                                                     sliced_for->material.density),
                            sliced_for->material.name);
  }
  return filament;
}

// What the link went through, and the firmware that answered with what it refused.
void print_link_summary(const printer::JobResult& result, const printer::LineProtocol& protocol) {
  const auto& stats = protocol.stats();
  fmt::print("link: {} lines sent, {} resent after {} resend requests ({} stale ignored), {} "
             "timeouts probed, {} duplicate oks, {} firmware errors, {}; longest "
             "silence {:.1f} s; {}\n",
             stats.lines_sent, stats.lines_resent, stats.resend_requests, stats.stale_resends,
             stats.probes, stats.duplicate_oks, stats.recoverable_errors,
             count_text(stats.refused_commands, "command refused", "commands refused"),
             std::chrono::duration<double>(stats.longest_silence).count(),
             count_text(result.pauses, "pause", "pauses"));
  const printer::FirmwareInfo& firmware = protocol.firmware();
  std::string refused;
  for (const std::string& c : protocol.refused()) refused += (refused.empty() ? "" : ", ") + c;
  fmt::print("firmware: {} ({} dialect){}\n",
             firmware.name.empty() ? "did not name itself in reply to M115" : firmware.name,
             protocol.dialect().name.empty() ? "unknown" : protocol.dialect().name,
             refused.empty() ? "" : "; refused: " + refused);
}

// A dry run's own lines: the deposit checked for unsupported extrusion, the faults injected,
// the wall time.
void print_dry_run_summary(const OpenLink& link, bool resumed, std::chrono::steady_clock::duration wall) {
  const sim::Printer& printer = link.sim->printer();
  // A resumed print starts on layers its record does not have: nothing to check it over.
  if (link.check && !resumed) {
    const sim::SupportCheck check = sim::check_unsupported_extrusion(printer.deposition(), *link.check);
    fmt::print("{}\n", sim::unsupported_summary(check, *link.check));
    if (!check.stretches.empty()) {
      const sim::UnsupportedStretch& s = check.stretches.front();
      fmt::print("  the first at layer {} (Z {:.2f}): {:.1f} mm from X{:.2f} Y{:.2f}{}\n", s.layer,
                 s.z, s.length, s.from.x, s.from.y,
                 s.anchored ? ", held at both ends but longer than a bridge may be" : "");
    }
  }
  if (printer.config().faults.any()) {
    fmt::print("simulated faults: {} injected ({})\n", printer.counters().faults_injected,
               sim::to_string(printer.config().faults));
  }
  fmt::print("wall time: {:.1f} s\n", std::chrono::duration<double>(wall).count());
}

// What the job did, on stdout: outcome, time, filament, what the link went through. A
// resume's estimate is that of the part it printed, from the interrupted layer on.
void print_summary(const printer::JobResult& result, const printer::GcodeFile& file,
                   const OpenLink& link, const printer::LineProtocol& protocol,
                   std::optional<double> estimated_seconds, bool resumed, const printer::Profiles* sliced_for,
                   std::chrono::steady_clock::duration wall) {
  const TimeAndPlace ran = time_and_place(result, link, estimated_seconds, resumed);
  fmt::print("{}: {}, {} of {} commands, {} layers\n", printer::to_string(result.state), ran.where,
             result.commands_done, file.size(), file.layers.size());
  fmt::print("{}; {}\n", ran.time, filament_text(result.filament_mm, sliced_for));
  print_link_summary(result, protocol);
  if (link.sim != nullptr) print_dry_run_summary(link, resumed, wall);
}

printer::JobResult run_job(printer::LineProtocol& protocol, const printer::GcodeFile& file,
                           OpenLink& link, printer::JobOptions job_options,
                           const std::string& socket_path, const std::string& journal_note,
                           const printer::Profiles* sliced_for) {
  const auto wall_start = std::chrono::steady_clock::now();
  install_print_signals();
  PrintUi ui;
  ControlSocket control(socket_path);
  if (link.sim != nullptr) job_options.paused_wait = wait_real_time;
  const bool resumed = job_options.first_command > 0;
  printer::Job job(protocol, file, std::move(job_options));
  job.on_event = [&](const std::string& line) { ui.event(line); };
  job.on_tick = [&](printer::Job& j) {
    ui.tick(j);
    control.serve(j);
  };
  if (!journal_note.empty()) ui.event(journal_note);
  ui.event(ui.keys() ? "control: keys p pause, r resume, c cancel, ! stop; or mahost ctl from "
                       "another terminal"
                     : fmt::format("control: mahost ctl pause|resume|cancel|stop|status --job {}",
                                   fs::path(socket_path).stem().string()));
  printer::JobResult result;
  try {
    result = job.run();
  } catch (const std::runtime_error&) {
    // A failed job says what the link went through too: often the reason is there.
    ui.finish();
    print_summary(job.result(), file, link, protocol, job.estimate_known(), resumed, sliced_for,
                  std::chrono::steady_clock::now() - wall_start);
    std::fflush(stdout);
    throw;
  }
  ui.finish();
  // A job that ended early says the estimate only if the model got that far (a cancel a minute
  // into a long file would spend seconds modelling the rest).
  const std::optional<double> estimate =
      result.state == printer::JobState::completed ? job.estimated_seconds() : job.estimate_known();
  print_summary(result, file, link, protocol, estimate, resumed, sliced_for,
                std::chrono::steady_clock::now() - wall_start);
  return result;
}

// The flags checked against each other and the input before anything is read or sliced; a
// port that is not there is news before minutes of slicing, not after.
void check_print_options(const PrintOptions& options, bool stl) {
  check_link_choice(options.link, "print");
  for (int layer : options.pause_at) {
    if (layer < 1) throw printer::ConfigError(fmt::format("--pause-at-layer {}: layers count from 1", layer));
  }
  if (!stl && !options.model_options_given.empty()) {
    throw printer::ConfigError(fmt::format(
        "{}: {} is G-code, already sliced; slice options other than --printer and --set apply "
        "to a model (STL, 3MF, OBJ)",
        options.model_options_given.front(), options.input));
  }
  if (!stl && !options.output.empty()) {
    throw printer::ConfigError(fmt::format(
        "-o: {} is G-code, already sliced; -o names where to keep the G-code sliced from an STL",
        options.input));
  }
  if (!options.link.dry_run) printer::check_serial_port(options.link.port);
}

// Where a job keeps its journal, and the name its socket and sliced G-code share (the
// journal's path without its extension).
struct JobPaths {
  bool named_journal = false;  // --journal given: kept
  std::string journal;
  std::string base;
};

JobPaths job_paths(const PrintOptions& options) {
  JobPaths paths;
  paths.named_journal = !options.journal.empty();
  const std::string name = job_name(fs::path(options.input).stem().string());
  paths.journal = fs::absolute(paths.named_journal ? fs::path(options.journal)
                                                   : fs::path(printer::job_directory()) / (name + ".journal"))
                      .string();
  paths.base = fs::path(paths.journal).replace_extension().string();
  return paths;
}

// The model sliced to gcode_path, its summary and plan on stdout. Ctrl-C while slicing stops
// at the next layer, and the job's files go with it.
app::SliceResult slice_for_print(const PrintOptions& options, const std::string& gcode_path, bool shown_path) {
  app::SliceOptions slice = options.slice;
  slice.model.path = options.input;
  install_print_signals();
  app::SliceEvents events = terminal_slice_events(slice.contour);
  events.cancelled = [] { return interrupt_count() > 0; };
  std::optional<app::SliceResult> sliced;
  try {
    sliced = app::slice(slice, gcode_path, events);
  } catch (const app::SliceCancelled&) {
    throw CommandExit{kExitInterrupted, "interrupted while slicing; nothing was printed"};
  }
  fmt::print("sliced {}{}: {}\n", options.input, shown_path ? " to " + gcode_path : "",
             app::slice_summary_text(*sliced));
  if (const std::string plan = app::slice_plan_text(*sliced); !plan.empty()) fmt::print("{}\n", plan);
  std::fflush(stdout);
  // The slicer's meshes and toolpaths are freed; hand their pages back before the job
  // loads the file, so the print's memory does not stack on the slicer's.
  ::malloc_trim(0);
  return std::move(*sliced);
}

// Every --pause-at-layer within the file's layers.
void check_pause_layers(const PrintOptions& options, const printer::GcodeFile& file, const std::string& shown_name) {
  for (int layer : options.pause_at) {
    if (static_cast<std::size_t>(layer) > file.layers.size()) {
      throw printer::ConfigError(
          fmt::format("--pause-at-layer {}: {} has {} layers", layer, shown_name, file.layers.size()));
    }
  }
}

// The command that resumes the job, set in its options, and the journal's line for the
// terminal: a print's resumes on its port, a kept dry run's as a dry run, and an unkept dry
// run's journal goes with it.
std::string set_resume_command(printer::JobOptions& job_options, const PrintOptions& options,
                               const std::string& journal, bool keep) {
  if (!options.link.dry_run) {
    job_options.resume_command = printer::resume_command(journal, options.link.port);
    return fmt::format("journal: {} (if the print is interrupted: {})", journal, *job_options.resume_command);
  }
  if (keep) {
    job_options.resume_command = printer::resume_command(journal, "");
    return fmt::format("journal: {} (kept; if the dry run is interrupted: {})", journal,
                       *job_options.resume_command);
  }
  job_options.resume_command = "";
  return fmt::format("journal: {} (a dry run's: removed when it ends; --keep keeps it)", journal);
}

void run_print(const PrintOptions& options) {
  const bool stl = app::is_model_name(options.input);
  check_print_options(options, stl);
  // The printer the job is for: an STL is sliced for it, and its motion limits time the job
  // (and are what a dry run simulates).
  const printer::Profiles profiles = app::load_slice_profiles(options.slice);
  const JobPaths paths = job_paths(options);
  const bool dry_run = options.link.dry_run;
  const bool keep = options.keep || paths.named_journal;

  JobFiles own;
  if (!paths.named_journal) own.add(paths.journal);
  std::string gcode_path = options.input;
  std::optional<app::SliceResult> sliced;
  if (stl) {
    gcode_path = !options.output.empty() ? options.output : paths.base + ".gcode";
    if (options.output.empty() && !paths.named_journal) own.add(gcode_path);
    sliced = slice_for_print(options, gcode_path, !options.output.empty() || keep);
  }
  const int baud = options.link.baud > 0 ? options.link.baud : profiles.printer.baud;
  OpenLink link;
  std::optional<printer::LineProtocol> connected;
  const printer::GcodeFile file = check_while_connecting(
      [&] { return read_job_gcode(gcode_path, options.link); },
      [&] {
        link = open_link(options.link, profiles.printer, baud);
        if (link.sim != nullptr) link.check = app::support_check_options(profiles);
        connect(connected.emplace(*link.link, protocol_options(options.link, profiles.printer)), link);
      });
  check_pause_layers(options, file, stl ? options.input : gcode_path);
  if (options.link.window > 1 && !connected->advanced_ok()) {
    fmt::print(stderr,
               "note: the firmware does not report its buffer space (ADVANCED_OK): --window {} "
               "falls back to one line at a time\n",
               options.link.window);
  }

  printer::JobOptions job_options =
      job_options_for(file, gcode_path, profiles.printer, options.link, baud, paths.journal);
  job_options.pause_at_layers = options.pause_at;
  const std::string note = set_resume_command(job_options, options, paths.journal, keep);
  printer::JobResult result;
  try {
    result = run_job(*connected, file, link, std::move(job_options), paths.base + ".sock", note,
                     sliced ? &sliced->profiles : nullptr);
  } catch (...) {
    // A print that failed keeps its journal and G-code for `mahost resume`.
    if (!dry_run || keep) own.keep();
    throw;
  }
  if (keep || (!dry_run && result.state != printer::JobState::completed)) own.keep();
  if (result.state == printer::JobState::cancelled || result.state == printer::JobState::stopped) {
    throw CommandExit{kExitCancelled, result.reason};
  }
}

struct ResumeOptions {
  std::string journal;
  LinkOptions link;
};

void run_resume(const ResumeOptions& options) {
  check_link_choice(options.link, "resume");
  const std::string journal = fs::absolute(options.journal).string();
  const printer::JournalRecord record = printer::read_journal(journal);
  if (record.state == printer::JobState::completed) {
    throw printer::ConfigError(fmt::format("{}: the job completed; there is nothing to resume", journal));
  }
  if (other_mahost_running(record.pid)) {
    throw printer::ConfigError(fmt::format(
        "{}: the job is still running (process {}); steer it with mahost ctl", journal, record.pid));
  }
  // The printer profile the job was sliced and timed for: its motion limits time the rest.
  const printer::PrinterProfile machine = app::resume_profile(
      record, [](const std::string& line) { fmt::print(stderr, "note: {}\n", line); });
  const int baud = options.link.baud > 0   ? options.link.baud
                   : record.baud > 0       ? record.baud
                                           : machine.baud;
  OpenLink link;
  std::optional<printer::LineProtocol> connected;
  const printer::GcodeFile file = check_while_connecting(
      [&] {
        printer::GcodeFile read = read_job_gcode(record.gcode_path, options.link);
        app::check_resumable_file(record, read);
        return read;
      },
      [&] {
        link = open_link(options.link, machine, baud);
        connect(connected.emplace(*link.link, protocol_options(options.link, machine)), link);
      });
  printer::LineProtocol& protocol = *connected;

  const bool dry_run = options.link.dry_run;
  const std::string base = fs::path(journal).replace_extension().string();
  printer::JobOptions job_options =
      app::resume_job_options(record, machine, pause_options(options.link, machine),
                              dry_run ? "" : journal, options.link.port, baud, true);
  std::string note, socket = base + ".sock";
  if (dry_run) {
    // A rehearsal: the journal stays as it is, for the real resume.
    job_options.resume_command = "";
    socket = (fs::path(printer::job_directory()) /
              fmt::format("{}-dry-run-{}.sock", fs::path(base).filename().string(), ::getpid()))
                 .string();
    note = fmt::format("dry run: {} is left as it was, for the real resume", journal);
  } else {
    job_options.resume_command = printer::resume_command(journal, options.link.port);
    note = fmt::format("journal: {} (if the print is interrupted again: {})", journal,
                       *job_options.resume_command);
  }
  const printer::JobResult result =
      run_job(protocol, file, link, std::move(job_options), socket, note, nullptr);
  if (!dry_run && result.state == printer::JobState::completed && in_job_directory(journal)) {
    // The job's own files, as `mahost print` removes them on completion.
    std::vector<std::string> own{journal};
    if (record.gcode_path == base + ".gcode") own.push_back(record.gcode_path);
    remove_files(own);
  }
  if (result.state == printer::JobState::cancelled || result.state == printer::JobState::stopped) {
    throw CommandExit{kExitCancelled, result.reason};
  }
}

}  // namespace

void add_print_command(CLI::App& app) {
  auto options = std::make_shared<PrintOptions>();
  auto* print = app.add_subcommand("print", "Print a model or a G-code file");
  print->footer(
      "A model (STL, 3MF or OBJ) is sliced first, as mahost slice would. Layers are numbered from 1 as the "
      "progress line shows them (layer n/N); layer n is the file's ;LAYER:n-1 comment. Keys on "
      "a terminal: p pause, r resume, c cancel, ! emergency stop; without one, mahost ctl. A "
      "dry run removes its journal and sliced G-code when it ends; a print removes them once "
      "it completes and keeps them otherwise, for mahost resume.");
  print->add_option("MODEL", options->input,
                    "the model (STL, 3MF or OBJ; sliced first) or G-code file to print")
      ->required()
      ->check(CLI::ExistingFile);
  add_link_options(*print, options->link, "the printer profile's serial.baud", kDryRunHelp);
  print->add_option("--pause-at-layer", options->pause_at,
                    "pause before these layers start, numbered from 1 as the progress line "
                    "shows them (layer n is the file's ;LAYER:n-1), e.g. 20,45 (default: none)")
      ->delimiter(',')
      ->group(kJobGroup);
  print->add_option("--journal", options->journal,
                    "keep the job journal at this path, and the sliced G-code beside it "
                    "(default: in $XDG_RUNTIME_DIR/mahost, removed when the job completes)")
      ->group(kJobGroup);
  print->add_flag("--keep", options->keep,
                  "keep the journal and the sliced G-code when the job completes or a dry run "
                  "ends (default: removed)")
      ->group(kJobGroup);
  print->add_option("-o,--output", options->output,
                    "keep the G-code sliced from an STL in this file (default: removed with the "
                    "job's other files)")
      ->group(kSliceGroup);
  add_slice_options(*print, options->slice, kSliceGroup);
  print->callback([options, print] {
    options->model_options_given.clear();
    for (const std::string& name : app::model_only_slice_flags()) {
      if (print->count(name) > 0) options->model_options_given.push_back(name);
    }
    run_print(*options);
  });

  auto resume_options = std::make_shared<ResumeOptions>();
  auto* resume = app.add_subcommand("resume", "Finish a print whose host, link or printer died");
  resume->footer(
      "Re-heats, homes X and Y only, sets Z from the journal and reprints the interrupted layer "
      "from its start. A --dry-run rehearses it on the simulated printer and leaves the "
      "journal as it was.");
  resume->add_option("JOURNAL", resume_options->journal,
                     "the job's journal, as mahost print named it when it started")
      ->required()
      ->check(CLI::ExistingFile);
  add_link_options(*resume, resume_options->link, "the journal's, else its printer profile's serial.baud",
                   kDryRunHelp);
  resume->callback([resume_options] { run_resume(*resume_options); });
}

}  // namespace host
