#include "printer/planner_mirror.h"

#include <algorithm>

namespace printer {

namespace {

PlannerMirror::Time seconds_of(double seconds) {
  return std::chrono::duration_cast<PlannerMirror::Time>(std::chrono::duration<double>(std::max(seconds, 0.0)));
}

}  // namespace

void PlannerMirror::set_depth(std::size_t depth) {
  depth_ = depth < 1 ? 1 : depth;
  while (ends_.size() > depth_) ends_.pop_front();
}

void PlannerMirror::entered(Time written, Time at, double seconds, bool prompt) {
  if (ends_.size() >= depth_) {
    // The oldest of the `depth` held must have ended for this one to enter: when the planner
    // was full it ended right then; it cannot have ended later than that.
    const Time freed = ends_.front();
    if (!prompt || freed > written || freed > at) {
      for (Time& end : ends_) end += at - freed;
    }
  }
  push(at, seconds);
}

void PlannerMirror::entered_unseen(Time written, double seconds) {
  push(room_at(written), seconds);
}

void PlannerMirror::drained(Time) { ends_.clear(); }

PlannerMirror::Time PlannerMirror::room_at(Time written) const {
  if (ends_.size() < depth_) return written;
  return std::max(written, ends_.front());
}

PlannerMirror::Time PlannerMirror::dry_at(Time now) const {
  return ends_.empty() ? now : std::max(now, ends_.back());
}

std::size_t PlannerMirror::held(Time now) const {
  return static_cast<std::size_t>(std::count_if(ends_.begin(), ends_.end(), [&](Time end) { return end > now; }));
}

void PlannerMirror::push(Time start, double seconds) {
  if (!ends_.empty()) start = std::max(start, ends_.back());
  ends_.push_back(start + seconds_of(seconds));
  while (ends_.size() > depth_) ends_.pop_front();
}

}  // namespace printer
