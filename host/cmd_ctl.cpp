// `mahost ctl pause|resume|cancel|stop|status [--job J]`: steer a running print from another
// terminal or a script, through the job's control socket (host/control_socket.h). Without
// --job, the user's one running job is found in the job directory.
#include <filesystem>
#include <memory>
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

// --job takes the socket, the journal or the job's name.
std::string socket_for(const std::string& job) {
  if (job.empty()) {
    const std::vector<std::string> running = running_jobs();
    if (running.empty()) {
      throw printer::LinkError(fmt::format(
          "no running mahost job found in {}; give --job with the job's journal", printer::job_directory()));
    }
    if (running.size() > 1) {
      std::string names;
      for (const std::string& r : running) names += " " + fs::path(r).stem().string();
      throw printer::ConfigError(fmt::format("{} jobs are running:{}; choose one with --job NAME",
                                             running.size(), names));
    }
    return running.front();
  }
  fs::path path(job);
  if (path.extension() == ".sock") return path.string();
  if (path.extension() == ".journal" || path.has_parent_path()) return path.replace_extension(".sock").string();
  return (fs::path(printer::job_directory()) / (job + ".sock")).string();
}

void run_ctl(const CtlOptions& options) {
  const std::string socket = socket_for(options.job);
  const std::string reply = send_control(socket, options.action);
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
  auto* ctl = app.add_subcommand("ctl", "pause, resume, cancel, stop or ask the status of a running print");
  ctl->add_option("ACTION", options->action, "pause, resume, cancel, stop or status")
      ->required()
      ->check(CLI::IsMember({"pause", "resume", "cancel", "stop", "status"}));
  ctl->add_option("--job", options->job, "the job: its name, journal or socket (default: the one running)");
  ctl->callback([options] { run_ctl(*options); });
}

}  // namespace host
