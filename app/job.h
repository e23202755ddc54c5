// A print job resumed from its journal (printer/journal.h), set up the one way `mahost resume`
// and `mahost serve` both do it: the file checked against the journal, the printer profile
// the job was sliced for, and the job's options to continue at the interrupted layer.
#pragma once

#include <functional>
#include <string>

#include "printer/gcode_file.h"
#include "printer/job.h"
#include "printer/journal.h"
#include "printer/pause.h"
#include "printer/profile.h"

namespace app {

// Throws printer::ConfigError naming the file when `file` is not the one the journal's job
// printed (its content hash or command count differ): resuming would print a different part.
void check_resumable_file(const printer::JournalRecord& record, const printer::GcodeFile& file);

// The printer profile the job was sliced and timed for (the default printer's when the
// journal names none) with the firmware the job ran (a --set firmware=... the profile file
// does not hold). A profile that cannot be loaded gives Marlin's default motion limits, and
// `note` hears why.
printer::PrinterProfile resume_profile(const printer::JournalRecord& record,
                                       const std::function<void(const std::string&)>& note);

// The options that continue the job at its interrupted layer: `pause`, the machine's motion
// limits, the first command and the printer's state before it. With a `journal` path, the
// record is kept there as the job goes on (printing at `port` and `baud`: "" and 0 for a dry
// run; fsync'ed when `durable`). resume_command is left unset.
printer::JobOptions resume_job_options(const printer::JournalRecord& record,
                                       const printer::PrinterProfile& machine,
                                       const printer::PauseOptions& pause, const std::string& journal,
                                       const std::string& port, int baud, bool durable);

}  // namespace app
