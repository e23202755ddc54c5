#include "printer/job.h"

#include <algorithm>

#include <fmt/core.h>

#include "printer/error.h"

namespace printer {

namespace {

using std::chrono::nanoseconds;

constexpr nanoseconds kTick = std::chrono::milliseconds(100);
// While paused nothing else comes from the printer: ask for its temperatures this often, so
// `mahost ctl status` and the progress line show the heaters as they are (OctoPrint polls
// an idle printer every 2 s too).
constexpr nanoseconds kPausedReportEvery = std::chrono::seconds(2);
// While printing, a temperature report at least this often (where the firmware does not
// report by itself): the progress line and `mahost ctl status` show the heaters as they are.
constexpr nanoseconds kPrintingReportEvery = std::chrono::seconds(5);
// A cancel ends within this much link time, however the link behaves: the lines in
// flight get kCancelDrain to be answered before the job gives up on them, and the heaters-off
// sequence the rest; past it the job sends M112, which turns the heaters off on any firmware.
constexpr nanoseconds kCancelBound = std::chrono::seconds(10);
constexpr std::chrono::milliseconds kCancelDrain{2000};
// A failed job's heaters-off lines may have to wait behind a heat-up the firmware cannot break
// (Repetier reads nothing while M190 waits, Commands.cpp): past kCancelBound the job waits on
// while the firmware says it is busy, up to this, before it sends M112 (which would wait too).
constexpr nanoseconds kHeatUpBound = std::chrono::minutes(15);
constexpr nanoseconds kAliveWithin = std::chrono::seconds(5);

}  // namespace

Job::Job(LineProtocol& protocol, const GcodeFile& file, JobOptions options)
    : protocol_(protocol),
      file_(file),
      reader_(file),
      options_(std::move(options)),
      eta_(file, options_.motion, options_.first_command) {
  layer_sequence_.assign(file_.layers.size(), -1);
  layer_state_.assign(file_.layers.size(), PrintState{});
  done_ = std::min(options_.first_command, file_.size());
  if (options_.recover_from) {
    state_ = *options_.recover_from;
    state_.hotend_target_set = state_.bed_target_set = true;  // the journal's, which recovery sets
  }
  layer_ = file_.layer_index_of(done_);
  // A resume starts at a layer start; a failure while it recovers, before start_layer runs,
  // journals that layer again, with the state the recovery restores.
  if (layer_ >= 0 && file_.layer_starting_at(done_) == layer_) {
    layer_state_[static_cast<std::size_t>(layer_)] = state_;
  }
}

void Job::request(JobRequest request) {
  switch (request) {
    case JobRequest::pause:
      if (job_state_ == JobState::printing) pause_requested_ = true;
      break;
    case JobRequest::resume:
      if (job_state_ == JobState::paused || job_state_ == JobState::pausing) resume_requested_ = true;
      pause_requested_ = false;  // a pause still waiting for its layer is called off
      break;
    case JobRequest::cancel:
      cancel_requested_ = true;
      break;
    case JobRequest::stop:
      stop_requested_ = true;
      break;
  }
}

bool Job::tune(std::string command) {
  const bool sending = job_state_ == JobState::printing || job_state_ == JobState::pausing ||
                       job_state_ == JobState::paused;
  if (tunes_closed_ || !sending || cancel_requested_ || stop_requested_) return false;
  tunes_.push_back(std::move(command));
  return true;
}

void Job::send_tunes(PrintState* also) {
  // Swapped out first: a send may tick, and a tick may add tunes for the next call.
  std::vector<std::string> tunes;
  tunes.swap(tunes_);
  for (const std::string_view command : tunes) {
    protocol_.send(command);
    apply(state_, command);
    if (also != nullptr) apply(*also, command);
  }
}

JobProgress Job::progress() const {
  JobProgress p;
  p.state = job_state_;
  p.commands_done = done_;
  p.commands_total = file_.size();
  p.layers = static_cast<int>(file_.layers.size());
  p.layer = layer_ + 1;
  const nanoseconds now = protocol_.link().now();
  p.elapsed = now - start_;
  const double printing = std::chrono::duration<double>(printing_time(now)).count();
  const double done_at = std::chrono::duration<double>(done_at_).count();
  if (const std::optional<double> left = eta_.remaining(done_, done_at, printing)) {
    p.remaining = std::chrono::duration_cast<nanoseconds>(std::chrono::duration<double>(*left));
  }
  p.estimating = !p.remaining;
  p.fraction = eta_.fraction(done_).value_or(
      file_.size() > 0 ? static_cast<double>(done_) / static_cast<double>(file_.size()) : 1.0);
  p.bytes_done = bytes_done_;
  p.temperatures = protocol_.temperatures();
  // The last report may be old (a printer reports only when asked, and the job asks while
  // paused only), but the targets are what the file's commands set: those sent are in state_.
  if (state_.hotend_target_set || state_.bed_target_set) {
    Temperatures t = p.temperatures.value_or(Temperatures{});
    if (state_.hotend_target_set) t.hotend_target = state_.hotend_target;
    if (state_.bed_target_set) t.bed_target = state_.bed_target;
    p.temperatures = t;
  }
  if (pause_requested_) p.pause_before_layer = layer_ + 2;
  return p;
}

nanoseconds Job::printing_time(nanoseconds now) const {
  nanoseconds paused = paused_for_;
  if (paused_since_) paused += now - *paused_since_;
  return now - start_ - paused;
}

void Job::event(const std::string& text) {
  if (on_event) on_event(text);
}

void Job::tick(bool force) {
  const nanoseconds now = protocol_.link().now();
  if (!force && last_tick_.count() >= 0 && now - last_tick_ < kTick) return;
  last_tick_ = now;
  // The model reads on (print_eta.h), before the UI asks for the time left; not while a cancel
  // ends the job.
  if (!cancel_deadline_) eta_.work(done_);
  if (on_tick) on_tick(*this);
  if (stop_requested_ && !stop_sent_) {
    protocol_.emergency("M112");
    stop_sent_ = true;
    throw StopNow{};
  }
  if (cancel_deadline_) {
    if (now >= *cancel_deadline_) throw CancelOverdue{};
    return;
  }
  if (!cancel_requested_) {
    if (job_state_ == JobState::printing && layer_ >= 0) ask_temperatures(now);
    return;
  }
  // A cancel must not wait out a heat-up or a wait for the user (M108 breaks those), nor a
  // stalled link: it leaves whatever wait it is in. A pause the user is in ends by itself.
  if (!break_sent_ && protocol_.long_command_in_flight() && protocol_.dialect().emergency_m108_m410) {
    protocol_.emergency("M108");
    break_sent_ = true;
  }
  if (job_state_ != JobState::paused) throw CancelNow{};
}

void Job::ask_temperatures(nanoseconds now) {
  const auto at = protocol_.temperatures_at();
  if (at && now - *at < kPrintingReportEvery) return;
  if (last_report_request_ && now - *last_report_request_ < kPrintingReportEvery) return;
  last_report_request_ = now;
  protocol_.request_temperatures();
}

void Job::write_journal_now(JobState state, int layer, std::size_t command,
                            const PrintState& at, const std::string& reason) {
  if (options_.journal_path.empty()) return;
  JournalRecord record = options_.journal;
  record.commands = file_.size();
  record.layers = file_.layers.size();
  record.state = state;
  record.reason = reason;
  record.layer_index = layer;
  record.resume_command = command;
  record.state_at_resume = at;
  record.updated.clear();
  write_journal(options_.journal_path, record, options_.journal_durable);
}

void Job::start_layer(int layer, std::size_t command) {
  layer_ = layer;
  // Between layers, the heaters as they are (M155 where the firmware reports by itself).
  if (!protocol_.autoreporting()) {
    last_report_request_ = protocol_.link().now();
    protocol_.request_temperatures();
  }
  layer_sequence_[static_cast<std::size_t>(layer)] = protocol_.commands_sent();
  layer_state_[static_cast<std::size_t>(layer)] = state_;
  // The pace is measured from the second layer the job reaches: the heat-up, homing or
  // recovery before the first are not in the model, and the printer's planner may still be
  // running them when the first layer's commands are acknowledged.
  if (layers_reached_++ > 0) eta_.arm_pace(command);
  write_journal_now(JobState::printing, layer, command, state_);
  const int counted = layer + 1;
  const bool planned = std::find(options_.pause_at_layers.begin(), options_.pause_at_layers.end(),
                                 counted) != options_.pause_at_layers.end();
  if (pause_requested_ || planned) pause_here(layer);
}

void Job::pause_here(int layer) {
  pause_requested_ = false;
  resume_requested_ = false;
  job_state_ = JobState::pausing;
  const nanoseconds began = protocol_.link().now();
  paused_since_ = began;
  event(fmt::format("pausing before layer {}/{}: finishing the moves in the printer's queue",
                    layer + 1, file_.layers.size()));
  PausePoint point = pause_print(protocol_, state_, options_.pause);
  // Counted once the printer stands paused: a pause the job is cancelled in is one too.
  ++pauses_;
  job_state_ = JobState::paused;
  write_journal_now(JobState::paused, layer, file_.layers[static_cast<std::size_t>(layer)].first_command,
                    state_);
  event(fmt::format(
      "paused before layer {}/{} at X{:.2f} Y{:.2f} Z{:.2f}{}; nozzle parked at Z{:.2f}, "
      "heaters kept at {:.0f}/{:.0f} °C",
      layer + 1, file_.layers.size(), point.state.x, point.state.y, point.state.z,
      point.reported ? "" : " (the printer did not report its position; the file's is used)",
      point.lifted_z, state_.hotend_target, state_.bed_target));
  // The first report at once: the last one may date from the first layer's heat-up.
  std::optional<nanoseconds> last_report;
  while (!resume_requested_ && !cancel_requested_) {
    if (!last_report || protocol_.link().now() - *last_report >= kPausedReportEvery) {
      protocol_.send("M105");
      last_report = protocol_.link().now();
    }
    const auto wait = options_.paused_wait
                          ? options_.paused_wait()
                          : std::chrono::duration_cast<std::chrono::milliseconds>(kTick);
    protocol_.poll(wait);
    tick();
    // A temperature tuned while paused is the one the resume heats to.
    send_tunes(&point.state);
  }
  if (cancel_requested_) {
    stood_paused_ += protocol_.link().now() - point.stopped_at;
    return;
  }
  resume_requested_ = false;
  event("resuming: re-heating if needed, returning to the part");
  resume_print(protocol_, point, options_.pause);
  stood_paused_ += protocol_.link().now() - point.stopped_at;
  paused_for_ += protocol_.link().now() - began;
  paused_since_.reset();
  job_state_ = JobState::printing;
  write_journal_now(JobState::printing, layer, file_.layers[static_cast<std::size_t>(layer)].first_command,
                    state_);
  event(fmt::format("resumed at layer {}/{}", layer + 1, file_.layers.size()));
}

std::string Job::cancel_here() {
  job_state_ = JobState::cancelling;
  const nanoseconds began = protocol_.link().now();
  cancel_deadline_ = began + kCancelBound;
  event("cancelling: stopping the moves, heaters off, lift, park, motors off");
  std::string trouble;
  try {
    protocol_.drop_unsent();  // the command the job was sending when the cancel came
    // The planner's moves would run on for seconds: Marlin's M410 drops them at once.
    if (protocol_.dialect().emergency_m108_m410 && protocol_.firmware().emergency_parser) {
      protocol_.emergency("M410");
    }
    if (!protocol_.wait_acknowledged_for(kCancelDrain)) {
      protocol_.abandon_unacknowledged();
      event("cancelling: the printer did not answer the lines in flight; going on without them");
    }
    cancel_print(protocol_, state_, options_.pause);
  } catch (const CancelOverdue&) {
    trouble = fmt::format("the printer did not confirm the cancel within {:.0f} s",
                          std::chrono::duration<double>(kCancelBound).count());
  } catch (const PrinterError& e) {
    trouble = e.what();
  } catch (const LinkError& e) {
    trouble = e.what();
  }
  cancel_deadline_.reset();
  if (trouble.empty()) return "";
  // Heaters off whatever state the firmware is in: M112 kills it, and kill() turns them off.
  protocol_.on_wait = nullptr;
  try {
    protocol_.emergency("M112");
    stop_sent_ = true;
  } catch (const LinkError&) {
    return fmt::format("; {}, and the link is gone: check the heaters are off", trouble);
  }
  // Nothing says the M112 arrived on a link that stopped answering: say so.
  return fmt::format("; {}: sent M112, which turns the heaters off if it reaches the printer: "
                     "check they are off, and reset the printer (power or M999) before the next "
                     "job",
                     trouble);
}

std::string Job::heaters_off_after_failure() {
  // Bounded like a cancel, the printer may have stopped answering; longer while it says it is
  // busy with a command that may run long (see kHeatUpBound).
  struct Overdue {};
  const nanoseconds began = protocol_.link().now();
  protocol_.on_wait = [this, began] {
    const nanoseconds now = protocol_.link().now();
    const bool busy = protocol_.long_command_in_flight() && protocol_.quiet_for() < kAliveWithin;
    if (now - began >= kHeatUpBound || (now - began >= kCancelBound && !busy)) throw Overdue{};
  };
  bool confirmed = false;
  try {
    // What came already first: an ok in hand frees the line it answers (a refusal's ok).
    protocol_.drop_unsent();
    protocol_.handle_received();
    // A heat-up in flight would hold the heaters-off lines back: M108 breaks it where it can.
    if (protocol_.long_command_in_flight() && protocol_.dialect().emergency_m108_m410) {
      protocol_.emergency("M108");
    }
    if (!protocol_.wait_acknowledged_for(kCancelDrain) && !protocol_.long_command_in_flight()) {
      protocol_.abandon_unacknowledged();
    }
    protocol_.send("M104 S0");
    protocol_.send("M140 S0");
    protocol_.wait_acknowledged();
    confirmed = true;
  } catch (const Overdue&) {
  } catch (const std::runtime_error&) {
  }
  protocol_.on_wait = nullptr;
  if (confirmed) return "";
  // M112 turns the heaters off on any firmware, if it arrives.
  try {
    protocol_.emergency("M112");
    stop_sent_ = true;
  } catch (const LinkError&) {
    return "; the link is gone before the heaters could be turned off: check that they are off";
  }
  return "; the printer did not confirm the heaters off: sent M112, which turns them off if it "
         "reaches the printer: check they are off, and reset it (power or M999) before the next "
         "job";
}

int Job::resume_layer_after_failure() const {
  // The first command the firmware did not confirm may not have run: reprint its layer.
  const long accepted = protocol_.commands_accepted();
  int layer = -1;
  for (std::size_t l = 0; l < layer_sequence_.size(); ++l) {
    if (layer_sequence_[l] < 0) continue;
    if (layer_sequence_[l] <= accepted) layer = static_cast<int>(l);
  }
  return layer < 0 ? layer_ : std::min(layer, layer_);
}

void Job::journal_interrupted(JobState state, const std::string& reason) {
  const int layer = resume_layer_after_failure();
  if (layer < 0) {
    // Before the first layer: a resume starts from the beginning.
    write_journal_now(state, -1, 0, PrintState{}, reason);
    return;
  }
  write_journal_now(state, layer, file_.layers[static_cast<std::size_t>(layer)].first_command,
                    layer_state_[static_cast<std::size_t>(layer)], reason);
}

std::string Job::fail(const std::string& reason) {
  job_state_ = JobState::failed;
  const std::string safe = heaters_off_after_failure();
  journal_interrupted(JobState::failed, reason);
  return safe;
}

std::string Job::resume_hint() const {
  if (options_.resume_command) {
    return options_.resume_command->empty() ? "" : "; to finish the part: " + *options_.resume_command;
  }
  if (options_.journal_path.empty()) return "";
  return "; to finish the part: " + resume_command(options_.journal_path, kAnyPort);
}

JobResult Job::run() {
  start_ = protocol_.link().now();
  protocol_.on_wait = [this] { tick(); };
  // A firmware that keeps alive every second lets a lost ok be noticed in a second and a half.
  protocol_.use_keepalive(std::chrono::seconds(1));
  try {
    reason_ = print_to_the_end();
  } catch (const StopNow&) {
    reason_ = halt_after_m112();
  } catch (const CommandRefused& e) {
    refuse_the_file(e);
  } catch (const FirmwareStopped& e) {
    reason_ = firmware_stopped(e);
  } catch (const PrinterError& e) {
    const std::string safe = fail(e.what());
    throw PrinterError(std::string(e.what()) + safe + resume_hint());
  } catch (const LinkError& e) {
    const std::string safe = fail(e.what());
    throw LinkError(std::string(e.what()) + safe + resume_hint());
  } catch (const GcodeFileChanged& e) {
    // What is left to print is not the file that was checked: no resume, the heaters go off.
    const std::string safe = fail(e.what());
    throw GcodeFileChanged(std::string(e.what()) + safe);
  } catch (const ConfigError& e) {
    // The file cannot be read any more (a disk error).
    const std::string safe = fail(e.what());
    throw ConfigError(std::string(e.what()) + safe + resume_hint());
  }
  protocol_.on_wait = nullptr;
  return result();
}

std::string Job::print_to_the_end() {
  try {
    if (options_.recover_from) {
      recover();
    } else {
      write_journal_now(JobState::printing, file_.layer_index_of(done_), done_, state_);
    }
    send_the_file();
  } catch (const CancelNow&) {
  }
  if (cancel_requested_) return end_cancelled();
  end_completed();
  return "";
}

void Job::recover() {
  const int layer = file_.layer_index_of(done_);
  write_journal_now(JobState::printing, layer, done_, state_);
  // Where Z is comes from the printer itself, not from whether it said `start`.
  const std::optional<ReportedPosition> at = position_in_mm(protocol_, state_);
  const bool z_lost = z_forgotten(at, state_);
  event(fmt::format(
      "resuming at layer {}/{}: heating, lifting, homing X and Y{}", layer + 1, file_.layers.size(),
      !z_lost ? fmt::format(" (the printer kept Z: it reports {:.2f})", at->z)
      : at    ? fmt::format(", setting Z from the journal (the printer reports Z {:.2f}, the "
                            "journal {:.2f})",
                            at->z, state_.z)
              : ", setting Z from the journal (the printer does not report its position)"));
  recover_print(protocol_, state_, z_lost, options_.pause);
}

void Job::send_the_file() {
  if (done_ > 0) bytes_done_ = reader_.command_end(done_ - 1);
  for (std::size_t i = done_; i < file_.size(); ++i) {
    if (const int layer = file_.layer_starting_at(i); layer >= 0) start_layer(layer, i);
    tick();
    if (cancel_requested_) break;
    send_tunes();
    const std::string_view command = reader_.command(i);
    protocol_.send(command);
    apply(state_, command);
    done_ = i + 1;
    bytes_done_ = reader_.command_end(i);
    done_at_ = printing_time(protocol_.link().now());
    eta_.command_done(done_, std::chrono::duration<double>(done_at_).count());
  }
}

std::string Job::end_cancelled() {
  const std::string trouble = cancel_here();
  job_state_ = JobState::cancelled;
  const std::string reason =
      fmt::format("cancelled at layer {}/{}{}", layer_ + 1, file_.layers.size(), trouble);
  const int layer = std::max(layer_, 0);
  write_journal_now(JobState::cancelled, layer_ < 0 ? -1 : layer,
                    layer_ < 0 ? 0 : file_.layers[static_cast<std::size_t>(layer)].first_command,
                    layer_ < 0 ? PrintState{} : layer_state_[static_cast<std::size_t>(layer)], reason);
  return reason;
}

void Job::end_completed() {
  // Tunes taken while the last command was being sent go after it.
  send_tunes();
  tunes_closed_ = true;
  protocol_.wait_acknowledged();
  job_state_ = JobState::completed;
  write_journal_now(JobState::completed, -1, file_.size(), state_);
}

std::string Job::halt_after_m112() {
  job_state_ = JobState::stopped;
  // Marlin answers M112 with "Printer halted"; wait a moment for it, to say so.
  protocol_.on_wait = nullptr;
  bool confirmed = false;
  try {
    protocol_.poll(std::chrono::milliseconds(2000));
  } catch (const PrinterError&) {
    confirmed = true;
  } catch (const LinkError&) {
  }
  const std::string reason = fmt::format(
      "emergency stop (M112) at layer {}/{}: {}; reset it (power or M999) before the next job",
      layer_ + 1, file_.layers.size(),
      confirmed ? "the printer halted" : "the printer did not confirm the halt within 2 s");
  journal_interrupted(JobState::stopped, reason);
  return reason;
}

void Job::refuse_the_file(const CommandRefused& e) {
  // The firmware cannot print this file as written: nothing to resume, the file is to be
  // sliced again. The heaters it did set go off.
  const std::string where =
      state_.filament_fed <= 0 && !options_.recover_from ? "before anything was extruded"
      : layer_ >= 0 ? fmt::format("at layer {}/{}, the part printed so far left on the bed", layer_ + 1,
                                  file_.layers.size())
                    : fmt::format("before the first layer, after {:.1f} mm of filament", state_.filament_fed);
  const std::string safe = fail(CommandRefused(e.refusal, where, e.advice).what());
  throw CommandRefused(e.refusal, where, e.advice + safe);
}

std::string Job::firmware_stopped(const FirmwareStopped& e) {
  // kill() or a reset turned the heaters off; the firmware reads nothing more.
  protocol_.on_wait = nullptr;
  if (!stop_sent_) {
    job_state_ = JobState::failed;
    journal_interrupted(JobState::failed, e.what());
    throw PrinterError(std::string(e.what()) + resume_hint());
  }
  job_state_ = JobState::stopped;
  return "emergency stop (M112): the printer is halted";
}

double Job::estimated_seconds() {
  try {
    eta_.finish(done_);
  } catch (const ConfigError&) {
    // The file changed or cannot be read: the estimate is of what could be read.
  }
  return eta_.total().value_or(0.0) - eta_.at_first_command().value_or(0.0);
}

std::optional<double> Job::estimate_known() const {
  if (!eta_.total() || !eta_.at_first_command()) return std::nullopt;
  return *eta_.total() - *eta_.at_first_command();
}

JobResult Job::result() const {
  JobResult result;
  result.state = job_state_;
  result.reason = reason_;
  result.commands_done = done_;
  result.elapsed = protocol_.link().now() - start_;
  result.pauses = pauses_;
  result.paused = stood_paused_;
  result.filament_mm = state_.filament_fed;
  return result;
}

}  // namespace printer
