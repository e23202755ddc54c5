// The host's mirror of the firmware's planner (printer/planner_mirror.h), against moves of
// known length.
#include "printer/planner_mirror.h"

#include <doctest/doctest.h>

namespace planner_mirror_test {

using printer::PlannerMirror;
using namespace std::chrono_literals;

TEST_CASE("moves_queue_behind_each_other_and_room_comes_when_the_oldest_of_depth_ends") {
  PlannerMirror mirror(3);
  CHECK(mirror.room_at(0s) == 0s);
  CHECK(mirror.dry_at(5s) == 5s);  // nothing held
  mirror.entered(0s, 0s, 1.0, true);
  mirror.entered(0s, 0s, 2.0, true);
  CHECK(mirror.room_at(0s) == 0s);  // two of three
  mirror.entered(0s, 0s, 3.0, true);
  CHECK(mirror.room_at(0s) == 1s);  // full: when the first ends
  CHECK(mirror.dry_at(0s) == 6s);
  CHECK(mirror.held(1500ms) == 2);
  mirror.drained(6s);
  CHECK(mirror.dry_at(6s) == 6s);
}

TEST_CASE("an_ok_held_back_shows_when_the_oldest_move_really_ended") {
  // Three moves of a second each in a planner of three; the fourth move's ok comes at 1.5 s:
  // the printer runs half a second behind the model, and the mirror follows it.
  PlannerMirror mirror(3);
  for (int i = 0; i < 3; ++i) mirror.entered(0s, 0s, 1.0, true);
  CHECK(mirror.room_at(0s) == 1s);
  mirror.entered(0s, 1500ms, 1.0, false);
  CHECK(mirror.dry_at(1500ms) == 4500ms);  // 2.5, 3.5, then the new one ends at 4.5
  // An ok that comes sooner than the mirror thought moves it earlier.
  mirror.entered(1500ms, 2s, 1.0, true);
  CHECK(mirror.room_at(2s) == 3s);
}

TEST_CASE("a_move_credited_late_entered_when_it_could") {
  // A move whose own ok was lost entered as soon as it had room after it was written, not
  // when a later answer credited it.
  PlannerMirror mirror(2);
  mirror.entered(0s, 0s, 2.0, true);
  mirror.entered_unseen(100ms, 1.0);
  CHECK(mirror.dry_at(0s) == 3s);
}

}  // namespace planner_mirror_test
