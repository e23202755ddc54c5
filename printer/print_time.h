// The print-time estimate: the motion model (motion_model.h) run over a G-code program, read
// by printer/gcode_interpreter.h's rules (Marlin's: modes, units, G92, G28, firmware
// retraction): the G-code header's estimate; the host's ETA for a file.
//
// Besides the interpreter's moves: F is modal, 25 mm/s until the first (Marlin's default);
// M201 X Y Z E, M203 X Y Z E (mm/s), M204 P R T S, M205 J: the limits change for later moves.
// The planner drains (flush) before G28, G4, M400, M109 and M190 (the firmware waits there);
// G4 P<ms> or S<s> adds its dwell. Heating time is not counted: the estimate is motion (and
// dwell) time. Everything else is ignored. Units: mm, s.
#pragma once

#include <string_view>

#include "printer/gcode_interpreter.h"
#include "printer/gcode_line.h"
#include "printer/motion_model.h"

namespace printer {

class PrintClock {
 public:
  explicit PrintClock(MotionLimits limits, std::size_t lookahead = 16);

  void line(std::string_view text);        // one line of G-code, comments allowed
  void command(const GcodeCommand& command);
  void linear_move(const MoveWords& words);  // a G0/G1 in the current modes

  // Seconds so far, counting only moves the planner has made final (lags by its window).
  double elapsed() const;
  // Seconds of everything read so far, the moves still open as planned now (the last ending at
  // rest): elapsed() without the lag.
  double modeled() const;
  // Moves that take time: queued so far, and made final so far (their time is in elapsed()).
  std::size_t moves_queued() const { return model_.blocks(); }
  std::size_t moves_final() const;
  // Drains the planner and returns the whole program's seconds so far.
  double finish();

  AxisPosition position() const { return machine_position(state_); }
  bool relative_e() const { return state_.relative_e; }

 private:
  void drain();
  void run(const GcodeStep& step);
  void push(const Motion& move);
  MotionModel model_;
  GcodeState state_;
  double dwell_ = 0;
};

// The estimate for a whole program's text.
double estimate_print_time(std::string_view program, const MotionLimits& limits);

}  // namespace printer
