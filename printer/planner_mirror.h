// The host's picture of the firmware's planner: when the moves it has acknowledged end, when
// it can take one more, when it runs dry (DESIGN.md §4). The protocol engine reads from it when
// a line's ok is due, so that a lost ok is noticed a little after its answer was expected and
// before the printer runs out of moves, not after a fixed silence.
//
// Input: the moves the firmware acknowledged, each with its seconds from the motion model
// (printer/print_time.h's PrintClock, the writer's estimate) and, when its own ok told it, the
// link time it entered the planner; drains (a command answered only once every move ran).
// Output: link times. The firmware takes a move once fewer than `depth` are queued
// (printer/firmware_dialect.h's planner_depth), so a move acknowledged while the mirror holds
// `depth` of them shows when the oldest really ended: the mirror shifts to agree, and its
// error stays within the time of the moves it holds rather than growing over a print.
#pragma once

#include <chrono>
#include <cstddef>
#include <deque>

namespace printer {

class PlannerMirror {
 public:
  using Time = std::chrono::nanoseconds;

  explicit PlannerMirror(std::size_t depth = 16) : depth_(depth < 1 ? 1 : depth) {}
  void set_depth(std::size_t depth);

  // A move of `seconds`, written at `written`, entered the planner at `at`, as its own ok says.
  // Where the mirror held `depth` moves at `written`, or the ok came late (not `prompt`: later
  // than the line and its answer take on the wire), the planner was full and the oldest move
  // ended at `at`: the mirror shifts to agree.
  void entered(Time written, Time at, double seconds, bool prompt);
  // A move acknowledged without its own ok (credited by a later answer): it entered as soon as
  // there was room after it was written.
  void entered_unseen(Time written, double seconds);
  // Every move has run by `at` (the answer to a command that waits for the moves).
  void drained(Time at);

  // When a move written at `written` can enter: at once, or when the oldest of the `depth`
  // moves held ends.
  Time room_at(Time written) const;
  // When the last move held ends; `now` when there is none.
  Time dry_at(Time now) const;
  std::size_t held(Time now) const;

 private:
  void push(Time start, double seconds);
  std::size_t depth_;
  std::deque<Time> ends_;  // end of each of the newest `depth` moves, oldest first
};

}  // namespace printer
