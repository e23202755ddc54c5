// The print-time estimate: the motion model (motion_model.h) run over a G-code program, reading
// each line as Marlin does: the G-code header's estimate, and the host's ETA for a file.
//
// Understood: G0/G1 (and G2/G3 as a straight move to their end point) with X Y Z E F, F in
// mm/min and modal (25 mm/s until the first F, Marlin's default); G90/G91 (G90 and G91 switch
// E too, as in Marlin), M82/M83, G92; G28 (the axes named, or all, go to 0); M201 X Y Z E,
// M203 X Y Z E (mm/s), M204 P R T S, M205 J: the limits change for later moves. The planner
// drains (flush) before G28, G4, M400, M109 and M190 (the firmware waits there); G4 P<ms> or
// S<s> adds its dwell. Heating time is not counted: the estimate is motion (and dwell) time.
// Everything else is ignored. Units: mm, s.
#pragma once

#include <optional>
#include <string_view>

#include "printer/gcode_line.h"
#include "printer/motion_model.h"

namespace printer {

// The words of a G0/G1 as written; absent words keep their axis (or the modal feedrate).
struct MoveWords {
  std::optional<double> x, y, z, e;
  std::optional<double> f;  // mm/min
};

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
  std::size_t moves_queued() const { return moves_; }
  std::size_t moves_final() const;
  // Drains the planner and returns the whole program's seconds so far.
  double finish();

  AxisPosition position() const { return position_; }
  bool relative_e() const { return relative_e_; }

 private:
  void drain();
  MotionModel model_;
  AxisPosition position_;
  double feedrate_ = 25.0;  // mm/s
  bool relative_xyz_ = false, relative_e_ = false;
  double dwell_ = 0;
  std::size_t moves_ = 0;
};

// The estimate for a whole program's text.
double estimate_print_time(std::string_view program, const MotionLimits& limits);

}  // namespace printer
