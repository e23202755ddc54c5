// `mahost ctl pause|resume|cancel|stop|status [--job J]`: steer a running print from another
// terminal or a script, through the job's control socket (host/control_socket.h). Without
// --job, the user's one running job is found in the job directory.
#include <filesystem>
#include <memory>
#include <optional>
#include <string>

#include <CLI/CLI.hpp>
#include <fmt/core.h>

#include "host/commands.h"
#include "host/control_socket.h"
#include "printer/error.h"
#include "printer/journal.h"

namespace host {
namespace {

namespace fs = std::filesystem;

struct CtlOptions {
  std::string action;
  std::string job;
};

// --job takes the socket, the journal or the job's name. No job, or several, to choose from
// is a usage matter (exit 2): the line says what to run.
std::string socket_for(const std::string& job) {
  if (job.empty()) {
    const std::vector<std::string> running = running_jobs();
    if (running.empty()) {
      throw printer::ConfigError(fmt::format(
          "no running mahost job in {}: start one with mahost print, or give --job JOURNAL for "
          "a job kept elsewhere or one that ended",
          printer::job_directory()));
    }
    if (running.size() > 1) {
      std::string journals;
      for (const std::string& r : running) {
        journals += (journals.empty() ? " " : ", ") + fs::path(r).replace_extension(".journal").string();
      }
      throw printer::ConfigError(fmt::format("{} jobs are running; choose one with --job PATH:{}",
                                             running.size(), journals));
    }
    return running.front();
  }
  fs::path path(job);
  if (path.extension() == ".sock") return path.string();
  if (path.extension() == ".journal" || path.has_parent_path()) return path.replace_extension(".sock").string();
  return (fs::path(printer::job_directory()) / (job + ".sock")).string();
}

// The journal beside a control socket, if there is one to read.
std::optional<printer::JournalRecord> journal_beside(const std::string& socket) {
  const std::string journal = fs::path(socket).replace_extension(".journal").string();
  std::error_code error;
  if (!fs::exists(journal, error)) return std::nullopt;
  try {
    return printer::read_journal(journal);
  } catch (const printer::ConfigError&) {
    return std::nullopt;
  }
}

// A job that no longer answers: what its journal says, for `status`, or why the action cannot
// be done.
void report_ended_job(const CtlOptions& options, const std::string& socket,
                      const printer::JournalRecord& record) {
  const std::string journal = fs::path(socket).replace_extension(".journal").string();
  std::string what;
  if (record.state == printer::JobState::completed) {
    what = fmt::format("completed, {} layers (journal updated {})", record.layers, record.updated);
  } else {
    const bool interrupted =
        record.state == printer::JobState::printing || record.state == printer::JobState::paused;
    what = fmt::format("{} at layer {}/{} (journal updated {}){}; {} finishes it",
                       interrupted ? "not running: interrupted" : printer::to_string(record.state),
                       record.layer_index + 1, record.layers, record.updated,
                       record.reason.empty() ? "" : ": " + record.reason,
                       printer::resume_command(journal, printer::kAnyPort));
  }
  if (options.action == "status") {
    fmt::print("{}\n", what);
    return;
  }
  throw CommandExit{kExitBadInput, fmt::format("{}: the job is not running: {}",
                                               fs::path(socket).stem().string(), what)};
}

void run_ctl(const CtlOptions& options) {
  const std::string socket = socket_for(options.job);
  std::string reply;
  try {
    reply = send_control(socket, options.action);
  } catch (const printer::LinkError&) {
    if (const auto record = journal_beside(socket)) {
      report_ended_job(options, socket, *record);
      return;
    }
    std::error_code error;
    if (!fs::exists(socket, error)) {
      // A --job that names nothing: a usage matter, like no job at all.
      throw printer::ConfigError(fmt::format(
          "--job {}: no such mahost job (neither {} nor its journal exists); give the journal "
          "mahost print named, or leave --job out for the one job running",
          options.job, socket));
    }
    throw;
  }
  if (reply.starts_with("ok")) {
    fmt::print("{}\n", reply.size() > 3 ? reply.substr(3) : std::string("done"));
    return;
  }
  throw CommandExit{kExitBadInput, fmt::format("{}: {}", fs::path(socket).stem().string(),
                                               reply.starts_with("error: ") ? reply.substr(7) : reply)};
}

}  // namespace

void add_ctl_command(CLI::App& app) {
  auto options = std::make_shared<CtlOptions>();
  auto* ctl = app.add_subcommand("ctl", "Pause, resume, cancel, stop or query a running print");
  ctl->footer(
      "pause waits for the next layer start; cancel lets the lines in flight finish, then "
      "turns the heaters off, lifts, parks and turns the motors off; stop is an emergency "
      "stop (M112). status prints the job's progress line, or what the journal of a job that "
      "ended says.");
  ctl->add_option("ACTION", options->action, "pause, resume, cancel, stop or status")
      ->required()
      ->check(CLI::IsMember({"pause", "resume", "cancel", "stop", "status"}));
  ctl->add_option("--job", options->job,
                  "the job: its name, journal or control socket (default: the one job running "
                  "in $XDG_RUNTIME_DIR/mahost)");
  ctl->callback([options] { run_ctl(*options); });
}

}  // namespace host
