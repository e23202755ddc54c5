// The simulated printer's motion (sim/printer.h): where the head is in the G-code's modes,
// the planner that times the moves (printer::MotionModel, the same model the G-code writer's
// estimate uses), and what the moves deposit.
//
// Input: G0-G3, G28, G92, G90/G91, M82/M83, M201-M205, M220/M221 as parsed commands, at sim
// times (s). Output: when each move entered the planner (its ok is due then: a full planner
// holds the ok until the oldest move runs out), when all moves end, the position and the
// extruding moves in the DepositionRecord. Arcs are cut into 1 mm chords (Marlin's
// MM_PER_ARC_SEGMENT); homing runs through the planner from where the head is.
// Units: mm, mm/s, s.
#pragma once

#include <deque>
#include <string>

#include "printer/gcode_line.h"
#include "printer/motion_model.h"
#include "sim/config.h"
#include "sim/deposition.h"

namespace sim {

class Motion {
 public:
  // Logical coordinates as the G-code set them (E before flow is applied).
  struct Head {
    double x = 0, y = 0, z = 0, e = 0;
  };

  // Powers on at 0,0,0 with Marlin's boot modes; extruding moves go to `record`.
  Motion(const Config& config, DepositionRecord& record, double now);

  // G0/G1, G2 (clockwise)/G3: returns when the move (the last chord) entered the planner.
  double move(const printer::GcodeCommand& c, double now);
  double arc(const printer::GcodeCommand& c, bool clockwise, double now);
  // G28 (all axes, or the ones named): returns when homing ends.
  double home(const printer::GcodeCommand& c, double now);
  void set_position(const printer::GcodeCommand& c);   // G92
  void set_limits(const printer::GcodeCommand& c);     // M201, M203, M204, M205

  // G90/G91 (both also set E to follow, as Marlin's do), M82/M83.
  void absolute_positioning(bool absolute);
  void absolute_extrusion(bool absolute);
  void set_feed_percent(double percent) { feed_percent_ = percent; }  // M220
  void set_flow_percent(double percent) { flow_percent_ = percent; }  // M221

  // planner.synchronize(): every queued move runs out; returns when the last one ends.
  double finish(double now);
  // M410 and kill(): queued moves are dropped from the clock. The sim cannot say where
  // inside a move the head stopped: the position stays where the last command put it.
  void quickstop(double now);

  const Head& head() const { return head_; }
  double feedrate() const { return feedrate_; }  // mm/s, the last F
  int planner_free() const;
  double motion_time() const { return planner_.total_time(); }  // s of motion planned so far
  double end_time() const { return stepper_free_; }             // when the moves made final end
  // Seconds the head stood still between moves because the next one had not arrived: the
  // planner ran empty while printing. Waits the firmware drains the planner for (M400, G28,
  // M109, the end of the print, ...) are not counted.
  double starved() const { return starved_; }

 private:
  bool e_relative() const;
  Head destination(const printer::GcodeCommand& c);
  double line_to(const Head& target, double now);
  double plan_move(printer::AxisPosition target, double speed, double now);

  const Config* config_;
  DepositionRecord* record_;
  printer::MotionModel planner_;
  std::deque<double> open_moves_;  // arrival time of each move still open in the planner
  double stepper_free_ = 0;        // when all moves made final so far have run
  bool drained_ = true;            // the planner was emptied on purpose since the last move
  double starved_ = 0;
  Head head_;
  double fed_ = 0;                 // filament actually fed (flow applied), the planner's E
  double feedrate_ = 25;           // mm/s (Marlin boots with 1500 mm/min)
  bool relative_ = false;
  enum class EMode { follow, absolute, relative } e_mode_ = EMode::follow;
  double feed_percent_ = 100, flow_percent_ = 100;
};

}  // namespace sim
