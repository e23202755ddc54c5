// The motion model: how long the printer takes to run moves (trapezoidal acceleration with
// look-ahead junction speeds, as Marlin's planner does).
//
// One model serves the G-code writer's print-time estimate and the simulated printer's clock,
// so the two agree. Moves are pushed one at a time; like the firmware's planner buffer, the
// model keeps the last `lookahead` moves open (their exit speeds may still rise) and fixes a
// move's duration when it leaves that window or on flush(). Units: mm, s, mm/s, mm/s^2.
#pragma once

#include <array>
#include <cstddef>
#include <memory>

namespace printer {

struct MotionLimits {
  std::array<double, 4> max_speed{300, 300, 10, 60};                 // X Y Z E, mm/s (M203)
  std::array<double, 4> max_acceleration{3000, 3000, 100, 5000};     // X Y Z E, mm/s^2 (M201)
  double print_acceleration = 1000;    // moves that extrude, mm/s^2 (M204 P)
  double travel_acceleration = 1500;   // moves that do not, mm/s^2 (M204 T)
  double retract_acceleration = 3000;  // E-only moves, mm/s^2 (M204 R)
  double junction_deviation = 0.013;   // mm (Marlin's JUNCTION_DEVIATION_MM)
  double min_feedrate = 0.0;           // mm/s
};

struct AxisPosition {
  double x = 0, y = 0, z = 0, e = 0;
};

class MotionModel {
 public:
  explicit MotionModel(MotionLimits limits, std::size_t lookahead = 16);
  ~MotionModel();
  MotionModel(MotionModel&&) noexcept;
  MotionModel& operator=(MotionModel&&) noexcept;

  // Queues a move from the current position to `target` at `feedrate` (mm/s, clamped to the
  // axis limits). Returns the seconds of motion that became final with this push (moves that
  // left the look-ahead window), possibly 0. A move of zero length takes no time.
  double push(AxisPosition target, double feedrate);

  // Plans out every open move (the buffer drains, the last move ends at rest); returns their
  // seconds.
  double flush();

  // Sets the position without motion (G92, homing).
  void set_position(AxisPosition position);
  AxisPosition position() const;

  // Seconds of all moves made final so far.
  double total_time() const;
  // Seconds the open moves take as planned now (the newest ending at rest): with
  // total_time(), the time of everything pushed so far, should no more moves come.
  double pending_time() const;
  // Moves still open in the look-ahead window.
  std::size_t pending() const;
  // Moves pushed so far that take time (a move of zero length does not count).
  std::size_t blocks() const;

  const MotionLimits& limits() const;
  void set_limits(const MotionLimits& limits);  // M201/M203/M204 change them mid-print

 private:
  struct Planner;
  std::unique_ptr<Planner> planner_;
};

}  // namespace printer
