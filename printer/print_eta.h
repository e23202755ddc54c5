// The remaining time of a print job: the motion model's time for the commands still to send
// (PrintClock, the writer's estimate read line by line), scaled by the pace the printer has
// kept so far: elapsed printing time over the model's time for the same commands. The pace is
// read when a command is done, the moment the model and the printer are at the same move.
//
// Heating and homing are not in the model, so the pace is measured from a layer start after
// them (the job takes its second layer: past the start G-code or a resume's recovery);
// before that, and until the model has seen min_sample seconds of motion since then, the
// remaining time is the model's alone. Pauses are the caller's to leave out of the printing
// time. Units: s.
#pragma once

#include <cstddef>
#include <optional>
#include <vector>

#include "printer/gcode_file.h"
#include "printer/motion_model.h"

namespace printer {

class PrintEta {
 public:
  // Runs the model over the whole file once (a bunny's 100 000 commands take a few ms).
  PrintEta(const GcodeFile& file, const MotionLimits& limits);

  // Model seconds from the start of the file to the end of its first `commands` commands;
  // at(file.size()) is the whole file's estimate. Moves count once the planner made them
  // final, as the printer runs them a buffer behind the commands it acknowledged.
  double at(std::size_t commands) const;
  double total() const { return times_.empty() ? 0.0 : times_.back(); }

  // The pace may start at `commands` done (the job passes a layer start after the heat-up and
  // homing, which the model does not time); it starts at the first command done after that
  // which the model counts time for, when the printer runs the layer's moves. Later calls
  // change nothing.
  void arm_pace(std::size_t commands);
  // A command is done: `commands` in all, at `printing_seconds` of printing time.
  void command_done(std::size_t commands, double printing_seconds);
  bool pace_started() const { return pace_start_.has_value(); }

  // The pace (printing time over model time) from the pace's start to `commands` done at
  // `printing_seconds`, once the model has seen min_sample seconds since then; nullopt before.
  std::optional<double> pace(std::size_t commands, double printing_seconds) const;

  // Seconds left at `now` (printing time), the job having finished `commands` commands at
  // `done_at`. Between two commands the printer runs the move the next one's
  // acknowledgement waits for, so the time since done_at counts against that move's share.
  double remaining(std::size_t commands, double done_at, double now) const;

  // Share of the model's time done after `commands` commands, 0..1 (of the commands, for a
  // file without motion).
  double fraction(std::size_t commands) const;

  // Model seconds since the pace started before it is trusted. At an acknowledgement the
  // printer may be a move ahead of or behind the model (how its planner counts the move it
  // runs), so the pace is off by up to one move's time over this span at first.
  double min_sample = 60;

 private:
  struct PaceStart {
    double model = 0, printing = 0;
  };
  std::vector<float> times_;  // times_[i] = at(i); float: 2 ms steps over 10 hours suffice
  std::optional<std::size_t> armed_at_;
  std::optional<PaceStart> pace_start_;
};

}  // namespace printer
