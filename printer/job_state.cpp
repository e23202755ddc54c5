#include "printer/job_state.h"

#include <array>

namespace printer {

namespace {

constexpr std::array<JobState, 8> kStates{JobState::printing,   JobState::pausing,
                                          JobState::paused,     JobState::cancelling,
                                          JobState::completed,  JobState::cancelled,
                                          JobState::stopped,    JobState::failed};

}  // namespace

std::string_view to_string(JobState state) {
  switch (state) {
    case JobState::printing: return "printing";
    case JobState::pausing: return "pausing";
    case JobState::paused: return "paused";
    case JobState::cancelling: return "cancelling";
    case JobState::completed: return "completed";
    case JobState::cancelled: return "cancelled";
    case JobState::stopped: return "stopped";
    case JobState::failed: return "failed";
  }
  return "unknown";
}

std::optional<JobState> parse_job_state(std::string_view text) {
  for (const JobState state : kStates) {
    if (to_string(state) == text) return state;
  }
  return std::nullopt;
}

}  // namespace printer
