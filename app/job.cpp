// A print job resumed from its journal; see job.h.
#include "app/job.h"

#include <fmt/core.h>

#include "app/profile_paths.h"
#include "printer/error.h"

namespace app {

void check_resumable_file(const printer::JournalRecord& record, const printer::GcodeFile& file) {
  if (file.hash != record.gcode_hash || file.size() != record.commands) {
    throw printer::ConfigError(fmt::format(
        "{}: the file changed since the job started ({} then, {} now): resuming would print a "
        "different part",
        record.gcode_path, record.gcode_hash, file.hash));
  }
}

printer::PrinterProfile resume_profile(const printer::JournalRecord& record,
                                       const std::function<void(const std::string&)>& note) {
  const std::string name = record.printer.empty() ? printer::kDefaultPrinter : record.printer;
  printer::PrinterProfile machine;
  try {
    machine = printer::load_printer_profile(name, profile_search_path());
  } catch (const printer::ConfigError& e) {
    if (note) note(fmt::format("{}; the remaining time uses Marlin's default motion limits", e.what()));
  }
  if (const auto firmware = printer::parse_firmware(record.firmware)) machine.firmware = *firmware;
  return machine;
}

printer::JobOptions resume_job_options(const printer::JournalRecord& record,
                                       const printer::PrinterProfile& machine,
                                       const printer::PauseOptions& pause, const std::string& journal,
                                       const std::string& port, int baud, bool durable) {
  printer::JobOptions options;
  options.pause = pause;
  options.motion = machine.motion;
  options.first_command = record.resume_command;
  if (record.layer_index >= 0) options.recover_from = record.state_at_resume;
  if (!journal.empty()) {
    options.journal_path = journal;
    options.journal_durable = durable;
    options.journal = record;
    options.journal.port = port;
    options.journal.baud = baud;
    options.journal.pid = 0;
  }
  return options;
}

}  // namespace app
