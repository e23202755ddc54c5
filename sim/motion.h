// The simulated printer's motion (sim/printer.h): where the head is, read by the one G-code
// interpreter (printer/gcode_interpreter.h, with the dialect's GcodeRules), the planner that
// times the moves (printer::MotionModel, the same model the G-code writer's estimate uses),
// and what the moves deposit.
//
// Input: G0-G3, G28 (and Teacup's G161/G162), G92, G90/G91, M82/M83, G20/G21, M201-M205,
// M220/M221 as parsed commands, at sim times (s). Output: when each move entered the planner
// (its ok is due then: a full planner holds the ok until the oldest move runs out), when all
// moves end, the position and the extruding moves in the DepositionRecord. Arcs are the
// interpreter's chords (Marlin's plan_arc); homing runs through the planner from where the
// head is.
// Units: mm, mm/s, s.
#pragma once

#include <deque>
#include <string>

#include "printer/gcode_interpreter.h"
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

  // Powers on at 0,0,0 with the boot modes and the G-code rules of the config's dialect
  // (sim/dialect.h gcode_rules); extruding moves go to `record`.
  Motion(const Config& config, DepositionRecord& record, double now);

  // What a G0-G3 did: when its last move entered the planner; `bad_arc` for a G2/G3 without
  // a centre, which does not move.
  struct Queued {
    double entered = 0;
    bool bad_arc = false;
  };
  Queued move(const printer::GcodeCommand& c, double now);
  // G28 (all axes, or the ones named), Teacup's G161/G162 (the ones named, or all): returns
  // when homing ends.
  double home(const printer::GcodeCommand& c, double now);
  void set_position(const printer::GcodeCommand& c);   // G92
  void set_limits(const printer::GcodeCommand& c);     // M201, M203, M204, M205
  // A command that changes modes only: G90/G91, M82/M83, G20/G21, M221.
  void set_mode(const printer::GcodeCommand& c) { printer::interpret(state_, c); }
  void set_feed_percent(double percent) { feed_percent_ = percent; }  // M220

  // planner.synchronize(): every queued move runs out; returns when the last one ends.
  double finish(double now);
  // M410 and kill(): queued moves are dropped from the clock. The sim cannot say where
  // inside a move the head stopped: the position stays where the last command put it.
  void quickstop(double now);

  Head head() const { return {state_.x, state_.y, state_.z, state_.e}; }
  double feedrate() const { return state_.feedrate / 60.0; }  // mm/s, the last F
  bool inches() const { return state_.unit != 1; }            // G20 in effect
  int planner_free() const;
  double motion_time() const { return planner_.total_time(); }  // s of motion planned so far
  double end_time() const { return stepper_free_; }             // when the moves made final end
  // Seconds the head stood still between moves because the next one had not arrived: the
  // planner ran empty while printing. Waits the firmware drains the planner for (M400, G28,
  // M109, the end of the print, ...) are not counted.
  double starved() const { return starved_; }

 private:
  double line(const printer::Motion& move, double now);
  double plan_move(printer::AxisPosition target, double speed, double now);
  printer::AxisPosition planner_target() const;

  const Config* config_;
  DepositionRecord* record_;
  printer::MotionModel planner_;
  std::deque<double> open_moves_;  // arrival time of each move still open in the planner
  double stepper_free_ = 0;        // when all moves made final so far have run
  bool drained_ = true;            // the planner was emptied on purpose since the last move
  double starved_ = 0;
  printer::GcodeState state_;      // position, modes, units, feedrate, flow
  double fed_ = 0;                 // filament actually fed (flow applied), the planner's E
  double feed_percent_ = 100;
};

}  // namespace sim
