// How the simulated printer is built: the Marlin configuration it emulates, its heaters, its
// motion limits and its faults. Defaults are Marlin 2.x's stock Configuration(_adv).h.
// Units: mm, s, mm/s, °C.
#pragma once

#include <array>

#include "printer/motion_model.h"
#include "sim/dialect.h"
#include "sim/faults.h"

namespace sim {

// A heater and what it heats, as a first-order system: at full power the temperature T
// rises as dT/dt = heating_rate - (T - ambient) / time_constant, with the power off it falls
// as dT/dt = -(T - ambient) / time_constant. The controller (standing in for Marlin's PID)
// heats at full power until the target, then holds it exactly with the power that balances
// the losses. So heating from T0 to S takes time_constant * ln((Tmax - T0) / (Tmax - S)),
// Tmax = ambient + heating_rate * time_constant, a closed form the tests use.
struct HeaterConstants {
  double time_constant = 120;  // s
  double heating_rate = 4;     // °C/s at full power, at ambient temperature
  double window = 1;           // M109/M190 wait until within this of the target (TEMP_WINDOW)
  double residency = 10;       // ... and then this long (TEMP_RESIDENCY_TIME), s
};

struct Config {
  // Which firmware it speaks as (sim/dialect.h); the settings below are Marlin's names for
  // what every one of them has.
  Dialect dialect = Dialect::marlin;
  // Serial protocol (Marlin's BUFSIZE, BLOCK_BUFFER_SIZE, RX_BUFFER_SIZE, MAX_CMD_SIZE).
  int queue_depth = 4;        // commands the firmware queues before it stops reading serial
  // Moves the planner holds (also the motion model's look-ahead): BLOCK_BUFFER_SIZE 16 keeps
  // one block free (Marlin/src/module/planner.h, moves_free()), so a new move waits while 15 do.
  int planner_depth = 15;
  int rx_buffer_size = 128;   // bytes; bytes arriving when it is full are lost, as on Marlin
  int max_cmd_size = 96;      // a longer line is cut at max_cmd_size - 1 characters
  bool advanced_ok = false;   // ADVANCED_OK: "ok N<line> P<planner free> B<queue free>"
  // "ok" after "Resend:" (queue.cpp flush_and_request_resend): Marlin 1.1 and 2.1.x send it,
  // 2.0.9.x did not. Teacup and Repetier always send it (sim/dialect.h).
  bool ok_after_resend = true;
  // Teacup's REQUIRE_LINENUMBER (gcode_parse.h, off in its stock configuration): lines need an
  // N at least the expected one.
  bool teacup_require_linenumber = false;
  // Repetier's ACK_WITH_LINENUMBER (Configuration.h, 1 in its example configuration): "ok <n>".
  bool repetier_ack_with_linenumber = true;
  // EMERGENCY_PARSER: M108, M112 and M410 act the moment their line arrives, even when the
  // queue is full. Off, they act when the firmware reads the line, and only unnumbered ones
  // (queue.cpp's early check looks at the raw line, which starts with N when numbered).
  bool emergency_parser = true;  // Marlin only
  double busy_interval = 2;   // s between "echo:busy: processing" (M113 S; 0 = off)
  double idle_wait_interval = 0;  // s between "wait" when idle (NO_TIMEOUTS; 0 = off)
  double boot_time = 0;       // s after power-on or reset before "start"; input is lost meanwhile

  // The link: bits per second, 10 bits per byte both ways; 0 = bytes take no time.
  double baud = 0;
  // Wall-clock pacing for SimLink (the pty front end has its own): 0 = as fast as possible,
  // 1 = real time, N = N times faster than real time.
  double time_scale = 0;

  // Machine.
  double ambient = 20;                                  // °C
  HeaterConstants hotend{};                             // heats 20 -> 210 °C in ~60 s
  HeaterConstants bed{300, 0.6, 1, 10};                 // 20 -> 60 °C in ~75 s
  double max_hotend_temp = 260;  // targets are clamped: HEATER_0_MAXTEMP 275 - HOTEND_OVERSHOOT
  double max_bed_temp = 140;     // BED_MAXTEMP 150 - BED_OVERSHOOT
  double runaway_period = 40, runaway_hysteresis = 4;   // THERMAL_PROTECTION_PERIOD/_HYSTERESIS
  printer::MotionLimits motion{};                       // M201/M203/M204/M205 change them
  std::array<double, 4> steps_per_mm{80, 80, 400, 93};  // X Y Z E, for M114's Count
  std::array<double, 3> homing_feedrate{50, 50, 4};     // mm/s (HOMING_FEEDRATE_MM_M / 60)
  std::array<double, 3> homing_bump{5, 5, 2};           // mm backed off and re-approached
  double filament_diameter = 1.75;                      // mm, for bead widths

  FaultSpec faults{};
};

}  // namespace sim
