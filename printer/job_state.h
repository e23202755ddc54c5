// Where a print job stands: what the job reports while it runs (printer/job.h) and what its
// journal records (printer/journal.h), the same words in both.
#pragma once

#include <optional>
#include <string_view>

namespace printer {

enum class JobState { printing, pausing, paused, cancelling, completed, cancelled, stopped, failed };

// "printing", "pausing", ... as the journal file and the messages write them.
std::string_view to_string(JobState state);
// The state a word names; nullopt for any other text.
std::optional<JobState> parse_job_state(std::string_view text);

}  // namespace printer
