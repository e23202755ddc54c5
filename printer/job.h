// A print job: streams a G-code file through the protocol engine, pauses at layer
// boundaries, cancels safely, stops at once, and keeps the journal (DESIGN.md §4).
//
// Input: a GcodeFile (read a block at a time as the job reaches it), a connected LineProtocol, requests from the user (pause, resume,
// cancel, stop) that arrive through on_tick. Output: the file's commands sent exactly once
// and in order (a resume starts at a layer start), one-line events, the journal rewritten at
// each layer start, and a JobResult. The job knows layers and commands, never reply syntax:
// the engine owns that. Time is the link's clock.
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "printer/gcode_file.h"
#include "printer/job_state.h"
#include "printer/journal.h"
#include "printer/line_protocol.h"
#include "printer/motion_model.h"
#include "printer/pause.h"
#include "printer/print_eta.h"
#include "printer/print_state.h"

namespace printer {

enum class JobRequest { pause, resume, cancel, stop };

struct JobProgress {
  JobState state = JobState::printing;
  std::size_t commands_done = 0, commands_total = 0;  // of the file
  int layer = 0, layers = 0;       // layer being printed counted from 1; 0 before the first
  std::chrono::nanoseconds elapsed{0};                 // since the job started (link clock)
  // The motion model's time left for the file, scaled by the pace kept so far (print_eta.h);
  // heating and pauses to come are not in it. Unset while the model still reads the file.
  std::optional<std::chrono::nanoseconds> remaining;
  // Share of the file's modelled print time done, 0..1; while estimating, of its commands.
  double fraction = 0;
  bool estimating = false;         // the model has not read far enough yet: no remaining time
  std::uint64_t bytes_done = 0;    // the file's bytes through the last command done
  // Current temperatures from the printer's last report (while paused the job asks for one
  // every 2 s of link time); targets as the file's commands last set them (the report's until
  // the file sets one: a printer heated by hand).
  std::optional<Temperatures> temperatures;
  int pause_before_layer = 0;      // a requested pause waits for this layer (from 1), 0: none
};

struct JobOptions {
  std::vector<int> pause_at_layers;  // pause before these layers start, counted from 1
  PauseOptions pause;
  std::string journal_path;          // "" keeps no journal
  bool journal_durable = true;       // fsync each record (a dry run need not)
  JournalRecord journal;             // job, G-code path and hash, port, baud: copied into it
  // What a failure's message tells the user to run to finish the part; unset:
  // resume_command(journal, kAnyPort); empty: nothing (a journal that will not outlive the job).
  std::optional<std::string> resume_command;
  MotionLimits motion;               // the printer's, for the remaining time (print_eta.h)
  // A resume: start at this command with the printer first brought back onto the part.
  std::size_t first_command = 0;
  // State at first_command; set: run recover_print, which sets Z from it where the printer
  // lost its own (z_forgotten, by M114).
  std::optional<PrintState> recover_from;
  // While paused, how the job waits between two looks at the user and the printer; returns
  // how far the link's clock may run meanwhile. Unset: one tick (100 ms) of the link's clock,
  // right for a real printer, whose clock is the wall clock. A simulated printer at full
  // speed would race through a pause of seconds in hours; a dry run waits real time here and
  // lets the simulated clock run as long as it waited, never longer.
  std::function<std::chrono::milliseconds()> paused_wait;
};

struct JobResult {
  JobState state = JobState::completed;
  std::string reason;                    // for cancelled and stopped
  std::size_t commands_done = 0;
  std::chrono::nanoseconds elapsed{0};   // link time from start to end, pauses included
  int pauses = 0;                        // pauses begun, also one the job was cancelled in
  // Link time the printer stood paused: from its queue running empty at the pause to the
  // return to the part. Not printing time: elapsed - paused is what the print took.
  std::chrono::nanoseconds paused{0};
  double filament_mm = 0;                // fed by the file's commands
};

class Job {
 public:
  Job(LineProtocol& protocol, const GcodeFile& file, JobOptions options);

  // Takes effect at the next chance: pause at the next layer start, resume a pause, cancel
  // at once (within 10 s of link time however the link behaves: moves stopped, heaters off,
  // lift, park; M112 if the printer does not confirm), stop (M112) at once.
  void request(JobRequest request);
  // Sends `command` between two of the file's commands, before the next one (while paused, at
  // once): a user's tune mid-print (a temperature, the fan, speed or flow factor, babystep).
  // Its effect on the state is kept, so a temperature set here is the one a pause or resume
  // restores. The caller decides what is safe mid-job. False when the job sends no more (its
  // file all sent, or cancelling or stopping): the command is not sent.
  bool tune(std::string command);
  JobProgress progress() const;
  const std::string& journal_path() const { return options_.journal_path; }
  // The motion model's time for the commands this job sends (the whole file, or from a
  // resume's first command on), s: the print-time estimate to hold its motion against. Models
  // what the job has not yet (a job that ended early).
  double estimated_seconds();
  // estimated_seconds() once the model has read the file, without modelling the rest: a job
  // cancelled early in a long file need not spend seconds on it. Unset before.
  std::optional<double> estimate_known() const;
  // Commands of the file this job holds in memory (the block it sends from and the model's):
  // a few blocks, however long the file.
  std::size_t commands_held() const { return reader_.commands_held() + eta_.commands_held(); }

  // Called while the job streams and waits, about every 100 ms of link time: the UI draws
  // and reads keys, the control socket answers; either may call request().
  std::function<void(Job&)> on_tick;
  // One-line events for the user: "paused before layer 20 ...", "resumed".
  std::function<void(const std::string&)> on_event;

  // Runs the job. A failed link or printer turns the heaters off (M104 S0 and M140 S0, or M112
  // if the printer does not confirm; the firmware did so itself where it stopped or reset),
  // writes the journal and rethrows the LinkError or PrinterError with how to resume appended;
  // a CommandRefused (the firmware refused to heat, wait or home) is rethrown without it: the
  // file needs slicing again. A file changed on disk under the job (GcodeFileChanged: nothing
  // of the changed block is sent) or no longer readable (ConfigError) fails the job the same way.
  JobResult run();
  // What the job did so far: after run() returned, its result; after it threw, the same for
  // the failed job (state failed, the commands the firmware accepted), for a summary.
  JobResult result() const;

 private:
  struct StopNow {};
  struct CancelNow {};      // leave whatever the job waits for: the user cancelled
  struct CancelOverdue {};  // the cancel took longer than its bound
  // The steps of run(): the recovery or the first journal, the file's commands, and how the
  // job ended; each end returns the result's reason or throws what run() says.
  std::string print_to_the_end();
  void recover();
  void send_the_file();
  std::string end_cancelled();
  void end_completed();
  std::string halt_after_m112();
  [[noreturn]] void refuse_the_file(const CommandRefused& e);
  std::string firmware_stopped(const FirmwareStopped& e);
  void tick(bool force = false);
  // Sends the tunes asked for since the last call; `also` (a pause's saved state) follows them.
  void send_tunes(PrintState* also = nullptr);
  void ask_temperatures(std::chrono::nanoseconds now);
  void start_layer(int layer, std::size_t command);
  void pause_here(int layer);
  // The safe end of a cancelled job, within kCancelBound; what went wrong, for the reason
  // ("; the printer did not confirm ..."), or "".
  std::string cancel_here();
  // Every failure but the firmware's own stop ends here: the lines in hand handled, M104 S0
  // and M140 S0 sent and confirmed within kCancelBound, else M112. What went wrong, for the
  // message ("; sent M112 ..."), or "".
  std::string heaters_off_after_failure();
  void write_journal_now(JobState state, int layer, std::size_t command, const PrintState& at,
                         const std::string& reason = {});
  // A failed job: the heaters off and the journal written; what went wrong turning them off,
  // as heaters_off_after_failure says.
  std::string fail(const std::string& reason);
  // The journal of a job that ended early: the layer a resume reprints, with its state.
  void journal_interrupted(JobState state, const std::string& reason);
  // "; to finish the part: mahost resume ..." for a failure's message, or "".
  std::string resume_hint() const;
  void event(const std::string& text);
  int resume_layer_after_failure() const;
  // Link time since the job started, less the time spent pausing or paused.
  std::chrono::nanoseconds printing_time(std::chrono::nanoseconds now) const;

  LineProtocol& protocol_;
  const GcodeFile& file_;
  GcodeReader reader_;
  JobOptions options_;
  PrintState state_;
  JobState job_state_ = JobState::printing;
  std::size_t done_ = 0;
  std::uint64_t bytes_done_ = 0;  // JobProgress::bytes_done
  int layer_ = -1;
  std::vector<long> layer_sequence_;  // commands_sent() before each layer's first command
  std::vector<PrintState> layer_state_;  // the state at each layer's start
  bool pause_requested_ = false, resume_requested_ = false;
  bool cancel_requested_ = false, stop_requested_ = false, stop_sent_ = false;
  bool break_sent_ = false;
  std::vector<std::string> tunes_;  // tune() commands not yet sent
  bool tunes_closed_ = false;       // the file's commands all sent: tune() takes no more
  std::chrono::nanoseconds start_{0}, paused_for_{0}, last_tick_{-1};
  std::optional<std::chrono::nanoseconds> paused_since_;  // set while pausing or paused
  std::chrono::nanoseconds done_at_{0};  // printing time when done_ last grew
  int layers_reached_ = 0;
  PrintEta eta_;
  int pauses_ = 0;
  std::chrono::nanoseconds stood_paused_{0};  // JobResult::paused
  std::optional<std::chrono::nanoseconds> cancel_deadline_;  // set while cancelling
  std::optional<std::chrono::nanoseconds> last_report_request_;
  std::string reason_;  // JobResult::reason
};

}  // namespace printer
