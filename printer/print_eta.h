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
//
// The model runs while the job prints, a slice at a time (work()), so the first line goes out
// at once whatever the file's size: two runs of it over the file from its start, one for the
// whole file's time, one that keeps each command's time for the block of commands the job is
// in. Until both reach what the job needs the time is not known (an ETA "estimating"). Memory:
// a block of commands and its times, however long the file.
#pragma once

#include <cstddef>
#include <optional>
#include <vector>

#include "printer/gcode_file.h"
#include "printer/motion_model.h"
#include "printer/print_time.h"

namespace printer {

// Commands the model reads per work() call: about 10 ms of CPU, once a tick (100 ms) of the job.
inline constexpr std::size_t kEtaCommandsPerStep = 16384;

class PrintEta {
 public:
  // Models nothing yet. `first_command`: where the job starts (a resume's layer start).
  PrintEta(const GcodeFile& file, const MotionLimits& limits, std::size_t first_command = 0);

  // Models up to `budget` more commands: first up to the block of the job's next command (the
  // job has done `commands`), then on through the file for total().
  void work(std::size_t commands, std::size_t budget = kEtaCommandsPerStep);
  // Models everything work() has still to do for `commands` done.
  void finish(std::size_t commands);

  // Model seconds from the start of the file to the end of its first `commands` commands, for
  // `commands` in the block of the job's next command (unknown elsewhere, or before work() got
  // there). at(file.size()) is the whole file's estimate. Moves count once the planner made
  // them final, as the printer runs them a buffer behind the commands it acknowledged.
  std::optional<double> at(std::size_t commands) const;
  std::optional<double> total() const { return total_; }
  // at(first_command), once known.
  std::optional<double> at_first_command() const { return at_first_; }

  // The pace may start at `commands` done (the job passes a layer start after the heat-up and
  // homing, which the model does not time); it starts at the first command done after that
  // which the model counts time for, when the printer runs the layer's moves. Later calls
  // change nothing once one found its time known.
  void arm_pace(std::size_t commands);
  // A command is done: `commands` in all, at `printing_seconds` of printing time. Crossing
  // into the next block models that block at once, so a job that started at its file's first
  // block always knows the time of its next command.
  void command_done(std::size_t commands, double printing_seconds);
  bool pace_started() const { return pace_start_.has_value(); }

  // The pace (printing time over model time) from the pace's start to `commands` done at
  // `printing_seconds`, once the model has seen min_sample seconds since then; nullopt before.
  std::optional<double> pace(std::size_t commands, double printing_seconds) const;

  // Seconds left at `now` (printing time), the job having finished `commands` commands at
  // `done_at`; nullopt while still estimating. Between two commands the printer runs the move
  // the next one's acknowledgement waits for, so the time since done_at counts against that
  // move's share.
  std::optional<double> remaining(std::size_t commands, double done_at, double now) const;

  // Share of the model's time done after `commands` commands, 0..1 (of the commands, for a
  // file without motion); nullopt while still estimating.
  std::optional<double> fraction(std::size_t commands) const;

  // Commands the model's readers hold in memory: at most two blocks.
  std::size_t commands_held() const { return near_.reader.commands_held() + whole_.reader.commands_held(); }

  // Model seconds since the pace started before it is trusted. At an acknowledgement the
  // printer may be a move ahead of or behind the model (how its planner counts the move it
  // runs), so the pace is off by up to one move's time over this span at first.
  double min_sample = 60;

 private:
  // The model run over the file from its start, a block at a time.
  struct Run {
    Run(const GcodeFile& file, const MotionLimits& limits) : clock(limits), reader(file) {}
    PrintClock clock;
    GcodeReader reader;
    std::size_t next = 0;  // commands read
  };
  // Reads the next block into `run`; `times` (when given) gets at() of its start and after
  // each of its commands. Returns the commands read.
  std::size_t read_block(Run& run, std::vector<float>* times);
  std::size_t block_of(std::size_t commands) const;

  struct PaceStart {
    double model = 0, printing = 0;
  };
  const GcodeFile& file_;
  std::size_t first_command_ = 0;
  Run near_;                 // up to the job's block, whose times it keeps
  Run whole_;                // through the file, for total()
  std::optional<std::size_t> near_block_;  // the block times_ holds
  std::vector<float> times_;  // at(near_block_ * block + k) = times_[k]; float: 2 ms over 10 hours
  std::optional<double> total_, at_first_;
  std::optional<double> armed_model_;
  std::optional<PaceStart> pace_start_;
};

}  // namespace printer
