#include "printer/print_eta.h"

#include <algorithm>
#include <limits>

namespace printer {

PrintEta::PrintEta(const GcodeFile& file, const MotionLimits& limits, std::size_t first_command)
    : file_(file),
      first_command_(std::min(first_command, file.size())),
      near_(file, limits),
      whole_(file, limits) {
  if (first_command_ == 0) at_first_ = 0.0;
}

std::size_t PrintEta::block_of(std::size_t commands) const {
  // The block of the next command; past the end, the last block (which holds the end).
  const std::size_t last = file_.size() == 0 ? 0 : (file_.size() - 1) / file_.block_size();
  return std::min(commands / file_.block_size(), last);
}

std::size_t PrintEta::read_block(Run& run, std::vector<float>* times) {
  const std::size_t end = std::min(file_.size(), (run.next / file_.block_size() + 1) * file_.block_size());
  const std::size_t first = run.next;
  if (times != nullptr) {
    times->clear();
    times->push_back(static_cast<float>(run.clock.elapsed()));
  }
  for (; run.next < end; ++run.next) {
    run.clock.line(run.reader.command(run.next));
    // The file's last command ends with the planner drained: the printer runs everything.
    const double t = run.next + 1 == file_.size() ? run.clock.finish() : run.clock.elapsed();
    if (times != nullptr) times->push_back(static_cast<float>(t));
    if (&run == &near_ && run.next + 1 == first_command_) at_first_ = t;
    if (&run == &whole_ && run.next + 1 == file_.size()) total_ = t;
  }
  return end - first;
}

void PrintEta::work(std::size_t commands, std::size_t budget) {
  if (file_.size() == 0) {
    total_ = 0.0;
    return;
  }
  const std::size_t want = block_of(commands);
  std::size_t done = 0;
  while (done < budget && near_.next < file_.size() && (!near_block_ || *near_block_ < want)) {
    const std::size_t block = near_.next / file_.block_size();
    done += read_block(near_, block == want ? &times_ : nullptr);
    if (block == want) near_block_ = block;
  }
  while (done < budget && !total_) done += read_block(whole_, nullptr);
}

void PrintEta::finish(std::size_t commands) { work(commands, std::numeric_limits<std::size_t>::max()); }

std::optional<double> PrintEta::at(std::size_t commands) const {
  if (commands == 0) return 0.0;
  if (commands >= file_.size() && total_) return total_;
  if (commands == first_command_ && at_first_) return at_first_;
  if (!near_block_) return std::nullopt;
  const std::size_t first = *near_block_ * file_.block_size();
  if (commands < first || commands - first >= times_.size()) return std::nullopt;
  return times_[commands - first];
}

void PrintEta::arm_pace(std::size_t commands) {
  if (!armed_model_) armed_model_ = at(commands);
}

void PrintEta::command_done(std::size_t commands, double printing_seconds) {
  // The job crossed into the next block: model it now, as the job reads it.
  const std::size_t block = block_of(commands);
  if (near_block_ && *near_block_ + 1 == block && near_.next == block * file_.block_size()) {
    read_block(near_, &times_);
    near_block_ = block;
  }
  if (pace_start_ || !armed_model_) return;
  const std::optional<double> now = at(commands);
  if (now && *now > *armed_model_) pace_start_ = PaceStart{*now, printing_seconds};
}

std::optional<double> PrintEta::pace(std::size_t commands, double printing_seconds) const {
  const std::optional<double> now = at(commands);
  if (!pace_start_ || !now) return std::nullopt;
  const double modelled = *now - pace_start_->model;
  const double measured = printing_seconds - pace_start_->printing;
  if (modelled < min_sample || !(measured > 0)) return std::nullopt;
  return measured / modelled;
}

std::optional<double> PrintEta::remaining(std::size_t commands, double done_at, double now) const {
  const std::optional<double> here = at(commands);
  const std::optional<double> next = at(std::min(commands + 1, file_.size()));
  if (!total_ || !here || !next) return std::nullopt;
  const double pace_now = pace(commands, done_at).value_or(1.0);
  const double left = std::max(0.0, *total_ - *here) * pace_now;
  const double next_move = (*next - *here) * pace_now;
  return std::max(0.0, left - std::clamp(now - done_at, 0.0, next_move));
}

std::optional<double> PrintEta::fraction(std::size_t commands) const {
  const std::optional<double> here = at(commands);
  if (!total_ || !here) return std::nullopt;
  if (*total_ > 0) return std::clamp(*here / *total_, 0.0, 1.0);
  // Nothing that takes time (heating, settings): the share of the commands.
  const std::size_t all = file_.size();
  return all > 0 ? static_cast<double>(std::min(commands, all)) / static_cast<double>(all) : 1.0;
}

}  // namespace printer
