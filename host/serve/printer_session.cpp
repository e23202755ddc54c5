#include "host/serve/printer_session.h"

#include <sys/stat.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

#include <fmt/core.h>

#include "app/error.h"
#include "app/job.h"
#include "app/slice.h"
#include "host/control_socket.h"
#include "host/local_time.h"
#include "printer/error.h"
#include "printer/gcode_writer.h"
#include "printer/gcode_file.h"
#include "printer/gcode_line.h"
#include "sim/record.h"

namespace host::serve {

namespace fs = std::filesystem;
using namespace std::chrono_literals;

namespace {

constexpr std::size_t kHistoryPoints = 900;  // 15 min at one a second
constexpr std::size_t kEvents = 200;
constexpr std::size_t kCommandsWaiting = 256;  // G-code lines from the API not yet sent
constexpr auto kTemperatureEvery = std::chrono::seconds(2);  // M105 while idle, as OctoPrint
constexpr auto kRetryAfter = std::chrono::seconds(5);        // reopening a port that failed
// Heating, as the page shows it: a heater counts as there within kHeatedWithin of its target
// (°C; Marlin's M109 waits to within TEMP_WINDOW, 1 °C by default), and its time left is
// extrapolated from its rise over the last kHeatingWindow seconds once it rises faster than
// kRisingAtLeast (°C/s: below that the heater holds or cools, and no time can be told).
constexpr double kHeatedWithin = 2;
constexpr std::int64_t kHeatingWindow = 20;
constexpr double kRisingAtLeast = 0.05;

// The printer halted on an emergency stop: it needs a reset (a reconnect) before it takes
// anything, so the session waits for the user instead of reconnecting by itself.
struct Halted {
  std::string reason;
};

std::int64_t unix_now() { return static_cast<std::int64_t>(std::time(nullptr)); }

std::string random_hex(std::size_t bytes) {
  std::string out;
  std::random_device random;
  for (std::size_t i = 0; i < bytes; ++i) out += fmt::format("{:02x}", random() & 0xff);
  return out;
}

// The file's content_hash, read a MiB at a time; "" when it cannot be read.
std::string file_hash(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return {};
  printer::ContentHasher hash;
  std::vector<char> buffer(1 << 20);
  while (in.read(buffer.data(), static_cast<std::streamsize>(buffer.size())) || in.gcount() > 0) {
    hash.add(std::string_view(buffer.data(), static_cast<std::size_t>(in.gcount())));
  }
  return in.bad() ? std::string() : hash.text();
}

// "mid contour, support buildplate, brim 5 mm, no raft, adaptive within 0.25 mm, orient auto":
// the settings of a slice, those left to the profile left out, for the event log.
std::string slice_settings_text(const app::SliceOptions& o) {
  std::string text = o.contour + " contour";
  const auto add = [&](const std::string& part) { text += ", " + part; };
  if (o.layer) add(fmt::format("layer {:g} mm", *o.layer));
  if (!o.support.placement.empty()) add("support " + o.support.placement);
  if (o.support.brim) add(fmt::format("brim {:g} mm", *o.support.brim));
  if (o.support.raft) add(*o.support.raft ? "raft" : "no raft");
  const app::AdaptiveRequest& a = o.adaptive;
  if (a.max_layers > 0) add(fmt::format("adaptive, at most {} layers", a.max_layers));
  else if (a.max_seconds > 0) add(fmt::format("adaptive, within {}", printer::format_duration(a.max_seconds)));
  else if (a.wanted()) add(fmt::format("adaptive within {:g} mm", a.tolerance > 0 ? a.tolerance : app::kDefaultTolerance));
  if (o.model.orient != "none") add("orient " + o.model.orient);
  return text;
}

}  // namespace

std::string state_text(const Status& s) {
  switch (s.connection) {
    case Connection::connecting: return "Opening serial connection";
    case Connection::closed: return "Offline";
    case Connection::error: return s.error.empty() ? "Error" : "Offline after error";
    case Connection::operational: break;
  }
  if (!s.job_active) return "Operational";
  if (s.cancel_requested) return "Cancelling";
  if (!s.progress) return "Printing";
  switch (s.progress->state) {
    case printer::JobState::pausing: return "Pausing";
    case printer::JobState::paused: return "Paused";
    case printer::JobState::cancelling: return "Cancelling";
    case printer::JobState::printing:
      return s.progress->pause_before_layer > 0 ? "Pausing" : "Printing";
    default: return "Operational";
  }
}

std::vector<std::pair<std::string, std::string>> file_locks(const Status& s) {
  std::vector<std::pair<std::string, std::string>> locks;
  if (s.job_active && !s.job_file.empty()) {
    locks.emplace_back(s.job_file, fmt::format("{} is being printed", s.job_file));
  }
  if (s.interrupted && !s.interrupted->name.empty()) {
    locks.emplace_back(s.interrupted->name,
                       fmt::format("{} is the interrupted job's file (its part may be on the bed): "
                                   "finish or discard that job first",
                                   s.interrupted->name));
  }
  if (s.slicing && s.slicing->stage != "done" && s.slicing->stage != "failed") {
    locks.emplace_back(s.slicing->gcode, fmt::format("{} is being sliced", s.slicing->gcode));
  }
  return locks;
}

std::string file_lock(const Status& s, const std::string& name) {
  for (const auto& [locked, reason] : file_locks(s)) {
    if (locked == name) return reason;
  }
  return {};
}

std::string start_refusal(const Status& s) {
  if (s.connection != Connection::operational) return "the printer is not operational: " + state_text(s);
  if (s.job_active) return "a job is already running";
  if (s.interrupted) {
    return fmt::format("an interrupted job waits ({} at layer {}/{}): its part may still be on the bed; "
                       "finish it or discard it first",
                       fs::path(s.interrupted->file).filename().string(), s.interrupted->layer,
                       s.interrupted->layers);
  }
  return {};
}

namespace {

// A job is about to start on FILE: the page shows it running from nothing done, with no
// cancel asked and no earlier end.
void mark_job_starting(Status& s, const std::string& file) {
  s.job_active = true;
  s.job_file = file;
  s.cancel_requested = false;
  s.ended.reset();
  s.progress.reset();
}

}  // namespace

PrinterSession::PrinterSession(Options options, FileStore& files)
    : options_(std::move(options)), files_(files) {
  status_.instance = random_hex(8);
  status_.dry_run = options_.link.dry_run;
  status_.link = options_.link.dry_run ? "simulated printer" : options_.link.port;
}

PrinterSession::~PrinterSession() {
  shut_down(true);
  wait();
}

void PrinterSession::start() {
  job_thread_ = std::thread([this] { run(); });
}

void PrinterSession::shut_down(bool at_once) {
  std::lock_guard lock(mutex_);
  const bool again = shutting_down_;
  shutting_down_ = true;
  pending_start_.reset();
  if (status_.job_active) {
    job_requests_.push_back(at_once || again ? printer::JobRequest::stop : printer::JobRequest::cancel);
  }
  work_.notify_all();
  changed_.notify_all();
}

void PrinterSession::wait() {
  if (job_thread_.joinable()) job_thread_.join();
  if (slice_thread_.joinable()) slice_thread_.join();
}

bool PrinterSession::finished() const {
  std::lock_guard lock(mutex_);
  return finished_;
}

Status PrinterSession::status() const {
  std::lock_guard lock(mutex_);
  return status_;
}

Status PrinterSession::wait_for_change(std::uint64_t version, std::chrono::milliseconds timeout) const {
  std::unique_lock lock(mutex_);
  changed_.wait_for(lock, timeout, [&] { return status_.version > version || shutting_down_; });
  return status_;
}

std::vector<TemperaturePoint> PrinterSession::history(std::size_t limit) const {
  std::lock_guard lock(mutex_);
  const std::size_t n = std::min(limit, history_.size());
  return {history_.end() - static_cast<std::ptrdiff_t>(n), history_.end()};
}

std::vector<Event> PrinterSession::events_after(std::uint64_t id) const {
  std::lock_guard lock(mutex_);
  std::vector<Event> out;
  for (const Event& e : events_) {
    if (e.id > id) out.push_back(e);
  }
  return out;
}

std::shared_ptr<const JobFile> PrinterSession::job_file() const {
  std::lock_guard lock(mutex_);
  return job_file_;
}

void PrinterSession::publish(bool) {
  // mutex_ held by the caller.
  ++status_.version;
  changed_.notify_all();
}

void PrinterSession::add_event(const std::string& text) {
  std::fprintf(stderr, "%s %s\n", local_time().c_str(), text.c_str());
  std::fflush(stderr);
  std::lock_guard lock(mutex_);
  events_.push_back(Event{next_event_++, unix_now(), text});
  while (events_.size() > kEvents) events_.pop_front();
  publish();
}

void PrinterSession::sample_temperatures(const std::optional<printer::Temperatures>& temperatures) {
  if (!temperatures) return;
  const auto now = std::chrono::steady_clock::now();
  std::lock_guard lock(mutex_);
  status_.temperatures = temperatures;
  if (now - last_sample_ < 1s) return;
  last_sample_ = now;
  history_.push_back(TemperaturePoint{unix_now(), *temperatures});
  while (history_.size() > kHistoryPoints) history_.pop_front();
}

bool PrinterSession::sim_at_full_speed() const {
  return link_.sim != nullptr && options_.link.time_scale == 0;
}

// ---- HTTP side -----------------------------------------------------------------------------

Outcome PrinterSession::select(const std::string& name, bool print) {
  // The file is read and analysed before the lock: the job thread publishes under it.
  const std::optional<StoredFile> file = files_.find(name);
  if (!file) return {404, fmt::format("{}: no such file", name)};
  if (file->kind != FileKind::gcode) {
    return {415, fmt::format("{} is a model: slice it first (the slice command)", name)};
  }
  if (file->analysis && !file->analysis->error.empty()) return {415, file->analysis->error};
  std::lock_guard lock(mutex_);
  return select_found(*file, print);
}

Outcome PrinterSession::select_found(const StoredFile& file, bool print) {
  // mutex_ held by the caller.
  if (status_.job_active) return {409, "a job is running: select a file once it has ended"};
  if (slicing_ && status_.slicing && status_.slicing->gcode == file.name) {
    return {409, fmt::format("{} is being sliced: select it once the slice is done", file.name)};
  }
  status_.selected = file;
  publish();
  if (!print) return {};
  if (const std::string refused = start_refusal(status_); !refused.empty()) return {409, refused};
  pending_start_ = JobStart{file.name, std::nullopt, {}};
  mark_job_starting(status_, file.name);
  publish();
  work_.notify_all();
  return {};
}

Outcome PrinterSession::start_job() {
  std::unique_lock lock(mutex_);
  if (const std::string refused = start_refusal(status_); !refused.empty()) return {409, refused};
  if (!status_.selected) return {409, "no file is selected: select one first"};
  const std::string name = status_.selected->name;
  lock.unlock();
  return select(name, true);
}

Outcome PrinterSession::cancel_job() {
  std::lock_guard lock(mutex_);
  if (!status_.job_active) return {409, "no job is running"};
  if (pending_start_) {
    pending_start_.reset();
    status_.job_active = false;
    status_.job_file.clear();
    status_.ended = printer::JobState::cancelled;
    status_.ended_reason = "cancelled before it started";
    publish();
    return {};
  }
  job_requests_.push_back(printer::JobRequest::cancel);
  status_.cancel_requested = true;
  publish();
  return {};
}

Outcome PrinterSession::pause_job(PauseAction action) {
  std::unique_lock lock(mutex_);
  if (!status_.job_active) return {409, "no job is running"};
  if (status_.cancel_requested ||
      (status_.progress && status_.progress->state == printer::JobState::cancelling)) {
    return {409, "the job is being cancelled"};
  }
  // Paused, pausing, or a pause waiting for its layer: the last request not yet taken says it,
  // else what the job last published.
  bool paused = false;
  if (status_.progress) {
    const auto state = status_.progress->state;
    paused = state == printer::JobState::paused || state == printer::JobState::pausing ||
             status_.progress->pause_before_layer > 0;
  }
  for (printer::JobRequest r : job_requests_) {
    if (r == printer::JobRequest::pause) paused = true;
    if (r == printer::JobRequest::resume) paused = false;
  }
  const bool want_paused = action == PauseAction::pause    ? true
                           : action == PauseAction::resume ? false
                                                           : !paused;
  if (want_paused == paused) return {};  // as OctoPrint: pausing a paused job does nothing
  job_requests_.push_back(want_paused ? printer::JobRequest::pause : printer::JobRequest::resume);
  publish();
  if (want_paused) {
    // A job pauses at a layer start: say which, and that a heat-up runs to its end first.
    const int before = status_.progress ? status_.progress->layer + 1 : 1;
    const bool heating = status_.heating.has_value();
    lock.unlock();
    add_event(fmt::format("pause asked for: the job pauses before layer {}{}", before,
                          heating ? ", once the heat-up it waits for has ended" : ""));
  }
  return {};
}

Outcome PrinterSession::restart_job() {
  std::lock_guard lock(mutex_);
  if (!status_.job_active || !status_.progress || status_.progress->state != printer::JobState::paused) {
    return {409, "restart takes a paused job"};
  }
  job_requests_.push_back(printer::JobRequest::cancel);
  status_.cancel_requested = true;
  restart_after_cancel_ = true;
  publish();
  return {};
}

Outcome PrinterSession::set_pause_at(std::vector<int> layers) {
  for (int layer : layers) {
    if (layer < 1) return {400, fmt::format("layer {}: layers count from 1", layer)};
  }
  std::sort(layers.begin(), layers.end());
  layers.erase(std::unique(layers.begin(), layers.end()), layers.end());
  std::lock_guard lock(mutex_);
  status_.pause_at = std::move(layers);
  publish();
  return {};
}

Outcome PrinterSession::emergency_stop() {
  std::lock_guard lock(mutex_);
  if (status_.connection != Connection::operational) {
    return {409, "the printer is not operational: " + state_text(status_)};
  }
  if (status_.job_active && !pending_start_) {
    job_requests_.push_back(printer::JobRequest::stop);
  } else {
    stop_pending_start();
    stop_now_ = true;
  }
  publish();
  work_.notify_all();
  return {};
}

void PrinterSession::stop_pending_start() {
  // mutex_ held by the caller.
  if (!pending_start_) return;
  pending_start_.reset();
  status_.job_active = false;
  status_.job_file.clear();
  status_.ended = printer::JobState::stopped;
  status_.ended_reason = "emergency stop (M112) before the job started";
}

std::optional<std::string> tune_refusal(std::string_view command) {
  const printer::GcodeCommand c = printer::parse_gcode_line(command);
  if (c.letter == 'M') {
    switch (c.code) {
      case 104: case 140:            // hotend and bed targets
      case 106: case 107:            // part fan
      case 220: case 221:            // speed and flow factors, %
      case 290:                      // babystep, mm
      case 117:                      // a message on the printer's display
      case 105: case 114:            // temperature and position reports
        return std::nullopt;
      case 109: case 190:
        return fmt::format("{} would hold the print until the heater reaches its target: set the "
                           "target with {} while a job prints",
                           command, c.code == 109 ? "M104" : "M140");
      default:
        break;
    }
  }
  return fmt::format(
      "{} is not taken while a job prints: mid-job mahost sends temperatures (M104, M140), the fan "
      "(M106, M107), speed and flow (M220, M221), babysteps (M290), M117, M105 and M114; pause, "
      "resume and cancel through /api/job, M112 stops at once",
      command);
}

Outcome PrinterSession::send_commands(const std::vector<std::string>& commands) {
  std::lock_guard lock(mutex_);
  if (status_.connection != Connection::operational) {
    return {409, "the printer is not operational: " + state_text(status_)};
  }
  const bool all_stops = !commands.empty() && std::all_of(commands.begin(), commands.end(),
                                                          [](const std::string& c) { return c == "M112"; });
  if (status_.job_active) {
    if (all_stops) {
      if (pending_start_) {
        stop_pending_start();
        stop_now_ = true;
      } else {
        job_requests_.push_back(printer::JobRequest::stop);
      }
      publish();
      work_.notify_all();
      return {};
    }
    for (const std::string& c : commands) {
      if (const std::optional<std::string> why = tune_refusal(c)) return {409, *why};
    }
    if (job_tunes_.size() + commands.size() > kCommandsWaiting) {
      return {409, fmt::format("the job has {} commands waiting already: try again when they are sent",
                               kCommandsWaiting)};
    }
    job_tunes_.insert(job_tunes_.end(), commands.begin(), commands.end());
    return {};
  }
  if (pending_commands_.size() + commands.size() > kCommandsWaiting) {
    return {409, fmt::format("the printer has {} commands waiting already: try again when they are done",
                             kCommandsWaiting)};
  }
  for (const std::string& c : commands) {
    if (c == "M112") {
      stop_now_ = true;
      break;
    }
    pending_commands_.push_back(c);
  }
  work_.notify_all();
  return {};
}

Outcome PrinterSession::reconnect() {
  std::lock_guard lock(mutex_);
  if (status_.job_active) return {409, "a job is running: cancel it before reconnecting"};
  reconnect_requested_ = true;
  work_.notify_all();
  return {};
}

Outcome PrinterSession::resume_interrupted() {
  std::lock_guard lock(mutex_);
  if (!status_.interrupted) return {409, "no interrupted job to resume"};
  if (status_.connection != Connection::operational) {
    return {409, "the printer is not operational: " + state_text(status_)};
  }
  if (status_.job_active) return {409, "a job is already running"};
  printer::JournalRecord record;
  try {
    record = printer::read_journal(status_.interrupted->journal);
  } catch (const printer::ConfigError& e) {
    status_.interrupted.reset();
    publish();
    return {409, e.what()};
  }
  pending_start_ = JobStart{fs::path(record.gcode_path).filename().string(), record,
                            status_.interrupted->journal};
  // The job names its file, in the folder or (a `mahost print` job's) beside its journal.
  StoredFile file;
  file.name = pending_start_->name;
  struct stat info {};
  if (::stat(record.gcode_path.c_str(), &info) == 0) {
    file.size = static_cast<std::uint64_t>(info.st_size);
    file.date = info.st_mtim.tv_sec;
  }
  status_.selected = file;
  mark_job_starting(status_, status_.interrupted->name);
  status_.interrupted.reset();
  publish();
  work_.notify_all();
  return {};
}

Outcome PrinterSession::discard_interrupted() {
  std::lock_guard lock(mutex_);
  if (!status_.interrupted) return {409, "no interrupted job to discard"};
  // The journal, and the control socket the dead process left beside it.
  const std::string& journal = status_.interrupted->journal;
  remove_files({journal, fs::path(journal).replace_extension(".sock").string()});
  status_.interrupted.reset();
  publish();
  return {};
}

Outcome PrinterSession::slice(SliceRequest request) {
  {
    std::lock_guard lock(mutex_);
    if (shutting_down_) return {503, "the server is shutting down"};
    if (slicing_) return {409, "a model is being sliced: wait until it is done"};
    if (const std::string lock = file_lock(status_, request.gcode); !lock.empty()) {
      return {409, lock + ": slice to another name"};
    }
    slicing_ = true;
    status_.slicing = SliceStatus{request.model, request.gcode, "starting", 0, 0, {}, {}, {}};
    publish();
  }
  if (slice_thread_.joinable()) slice_thread_.join();  // the last one, done
  slice_thread_ = std::thread([this, request = std::move(request)]() mutable { slice_worker(std::move(request)); });
  return {202, {}};
}

Outcome PrinterSession::unselect() {
  std::lock_guard lock(mutex_);
  if (!status_.selected || status_.job_active) return {409, "no file is selected, or a job is running"};
  status_.selected.reset();
  publish();
  return {};
}

void PrinterSession::forget_selection(const std::string& name) {
  // mutex_ held by the caller.
  if (status_.selected && status_.selected->name == name && !status_.job_active) {
    status_.selected.reset();
    publish();
  }
}

PrinterSession::Stored PrinterSession::store_upload(FileStore::Upload& upload, const std::string& name,
                                                    const std::optional<GcodeAnalysis>& analysis, bool select,
                                                    bool print) {
  Stored stored;
  std::lock_guard lock(mutex_);
  if (const std::string lock_reason = file_lock(status_, name); !lock_reason.empty()) {
    stored.outcome = {409, lock_reason + ": upload it under another name"};
    return stored;
  }
  if (!upload.commit(name)) {
    stored.outcome = {500, fmt::format("{}: the upload could not be stored", name)};
    return stored;
  }
  if (analysis) files_.remember(name, *analysis);
  forget_selection(name);  // the file selected before is gone
  stored.outcome = {201, {}};
  if (select && analysis) {
    const std::optional<StoredFile> file = files_.find(name);  // its analysis just remembered
    const Outcome o = file ? select_found(*file, print) : Outcome{404, fmt::format("{}: no such file", name)};
    stored.selected = status_.selected && status_.selected->name == name;
    stored.printing = print && o.ok();
    if (print && !o.ok()) stored.not_printed = o.message;
  }
  publish();
  return stored;
}

Outcome PrinterSession::delete_file(const std::string& name) {
  std::lock_guard lock(mutex_);
  if (const std::string lock_reason = file_lock(status_, name); !lock_reason.empty()) return {409, lock_reason};
  if (!files_.remove(name)) return {404, fmt::format("{}: no such file", name)};
  forget_selection(name);
  return {};
}

// ---- The slicing thread --------------------------------------------------------------------

std::string PrinterSession::client_text(std::string text) const {
  // The client knows its files by name, not by the server's folder.
  for (std::size_t at; (at = text.find(files_.folder() + "/")) != std::string::npos;) {
    text.erase(at, files_.folder().size() + 1);
  }
  return text;
}

void PrinterSession::slice_worker(SliceRequest request) {
  app::SliceOptions options = request.options;
  options.model.path = files_.path_of(request.model);
  const std::string output = files_.path_of(request.gcode);
  auto last = std::chrono::steady_clock::now() - 1s;
  bool ok = false;
  std::string summary, plan, error;
  add_event(fmt::format("slicing {} to {} ({})", request.model, request.gcode, slice_settings_text(options)));
  try {
    app::SliceEvents events;
    events.progress = [&](app::SliceStage stage, std::size_t done, std::size_t total) {
      std::lock_guard lock(mutex_);
      const auto now = std::chrono::steady_clock::now();
      if (done != 0 && done != total && now - last < 100ms) return;
      last = now;
      if (status_.slicing) {
        status_.slicing->stage = std::string(app::stage_name(stage));
        status_.slicing->done = done;
        status_.slicing->total = total;
      }
      publish();
    };
    events.warning = [&](const std::string& line) { add_event(client_text(line)); };
    events.cancelled = [&] {
      std::lock_guard lock(mutex_);
      return shutting_down_;
    };
    const app::SliceResult result = app::slice(options, output, events);
    summary = app::slice_summary_text(result);
    plan = app::slice_plan_text(result);
    ok = true;
  } catch (const app::SliceCancelled&) {
    error = "the server is shutting down";
  } catch (const app::InputError& e) {
    error = e.what();
  } catch (const printer::ConfigError& e) {
    error = e.what();
  } catch (const std::exception& e) {
    error = fmt::format("internal error while slicing: {} (please report this)", e.what());
  }
  error = client_text(error);
  {
    std::lock_guard lock(mutex_);
    slicing_ = false;
    if (status_.slicing) {
      status_.slicing->stage = ok ? "done" : "failed";
      status_.slicing->error = error;
      status_.slicing->summary = summary;
      status_.slicing->plan = plan;
    }
    if (!ok && request.print && !status_.job_active) {
      // The print asked for did not start: GET /api/job says so, as for a job that failed.
      status_.ended = printer::JobState::failed;
      status_.ended_reason = fmt::format("slicing {} failed: {}", request.model, error);
      status_.progress.reset();
    }
    publish();
  }
  add_event(ok ? fmt::format("sliced {}: {}{}", request.gcode, summary, plan.empty() ? "" : "; " + plan)
               : fmt::format("slicing {} failed: {}", request.model, error));
  if (ok && (request.select || request.print)) {
    const Outcome o = select(request.gcode, request.print);
    if (!o.ok()) add_event(fmt::format("{} sliced but not {}: {}", request.gcode,
                                       request.print ? "printed" : "selected", o.message));
  }
}

// ---- The job thread ------------------------------------------------------------------------

void PrinterSession::run() {
  bool retry = false;  // reopen by itself: the port failed (not a halt the user must see to)
  std::string last_failure;  // said once while the same failure repeats (a printer unplugged)
  while (true) {
    {
      std::unique_lock lock(mutex_);
      if (shutting_down_) break;
    }
    std::string failure;
    bool halted = false;
    try {
      connect_printer(retry);
      find_interrupted();
      last_failure.clear();
      serve_printer();
      retry = false;
      std::lock_guard lock(mutex_);
      if (shutting_down_) break;
      continue;  // a reconnect was asked for
    } catch (const Halted& h) {
      failure = h.reason;
      halted = true;
    } catch (const printer::LinkError& e) {
      failure = e.what();
      retry = true;
    } catch (const printer::PrinterError& e) {
      failure = e.what();
      halted = true;
    } catch (const printer::ConfigError& e) {
      failure = e.what();
    } catch (const std::exception& e) {
      failure = fmt::format("internal error: {} (please report this)", e.what());
    }
    if (protocol_) protocol_->on_wait = nullptr;
    protocol_.reset();
    if (link_.sim == nullptr) link_.link.reset();  // a port is reopened; the sim keeps its record
    write_record();
    const bool again = retry && failure == last_failure;
    if (!again) {
      add_event(fmt::format("printer {}: {}{}", halted ? "halted" : "link failed", failure,
                            retry ? fmt::format(" (trying again every {} s)", kRetryAfter.count()) : ""));
    }
    last_failure = failure;
    std::unique_lock lock(mutex_);
    status_.connection = Connection::error;
    status_.error = failure;
    status_.retries = retry ? status_.retries + 1 : 0;
    status_.job_active = false;
    status_.job_file.clear();
    pending_start_.reset();
    job_requests_.clear();
    job_tunes_.clear();
    pending_commands_.clear();
    publish();
    if (shutting_down_) break;
    if (retry) {
      work_.wait_for(lock, kRetryAfter, [&] { return shutting_down_ || reconnect_requested_; });
    } else {
      work_.wait(lock, [&] { return shutting_down_ || reconnect_requested_; });
    }
    reconnect_requested_ = false;
  }
  if (protocol_) protocol_->on_wait = nullptr;
  write_record();
  std::lock_guard lock(mutex_);
  status_.connection = Connection::closed;
  finished_ = true;
  publish();
}

void PrinterSession::connect_printer(bool retrying) {
  if (!retrying) {
    // A retry after a failed link keeps saying what failed until the printer answers.
    std::lock_guard lock(mutex_);
    status_.connection = Connection::connecting;
    publish();
  }
  protocol_.reset();
  if (link_.sim != nullptr) {
    // The same simulated printer, reset: it keeps its record of what it printed.
    sim::Printer& printer = link_.sim->printer();
    if (printer.state() == sim::PrinterState::disconnected) link_.sim->reconnect();
    else if (printer.state() == sim::PrinterState::halted) printer.reset();
  } else {
    link_.link.reset();
    link_ = open_link(options_.link, options_.profiles.printer, options_.baud);
  }
  protocol_ = std::make_unique<printer::LineProtocol>(*link_.link, protocol_options(options_.link, options_.profiles.printer));
  install_idle_hook();
  host::connect(*protocol_, link_);
  autoreport_ = protocol_->firmware().autoreport_temperature;
  if (autoreport_) {
    // The printer reports its temperatures by itself, during jobs too.
    protocol_->send("M155 S2");
    protocol_->wait_acknowledged();
  }
  // The temperatures before the first client asks.
  protocol_->send("M105");
  protocol_->wait_acknowledged();
  last_m105_ = protocol_->link().now();
  sample_temperatures(protocol_->temperatures());
  add_event(fmt::format("connected to {}{}", link_.link->name(),
                        protocol_->firmware().name.empty() ? "" : " (" + protocol_->firmware().name + ")"));
  std::lock_guard lock(mutex_);
  status_.connection = Connection::operational;
  status_.error.clear();
  status_.retries = 0;
  status_.firmware = protocol_->firmware().name;
  status_.link = link_.link->name();
  publish();
}

void PrinterSession::install_idle_hook() {
  // While a command of the user's runs (a G28, an M109 of minutes): an emergency stop goes out
  // at once, and the temperatures stay fresh. A job sets its own hook and clears it.
  protocol_->on_wait = [this] {
    bool stop = false;
    {
      std::lock_guard lock(mutex_);
      stop = stop_now_;
      stop_now_ = false;
    }
    if (stop) protocol_->emergency("M112");
    sample_temperatures(protocol_->temperatures());
  };
}

std::optional<InterruptedJob> PrinterSession::interrupted_job(const std::string& journal) const {
  printer::JournalRecord record;
  try {
    record = printer::read_journal(journal);
  } catch (const printer::ConfigError&) {
    return std::nullopt;
  }
  const std::string port = options_.link.dry_run ? "" : options_.link.port;
  if (record.state == printer::JobState::completed || record.state == printer::JobState::cancelled) return std::nullopt;
  if (record.port != port || other_mahost_running(record.pid)) return std::nullopt;
  if (file_hash(record.gcode_path) != record.gcode_hash) return std::nullopt;  // gone or changed
  InterruptedJob job;
  job.journal = journal;
  job.file = record.gcode_path;
  job.state = std::string(printer::to_string(record.state));
  job.reason = record.reason;
  job.updated = record.updated;
  if (fs::path(record.gcode_path).parent_path() == fs::path(files_.folder())) {
    job.name = fs::path(record.gcode_path).filename().string();
  }
  job.layer = record.layer_index + 1;
  job.layers = static_cast<int>(record.layers);
  return job;
}

void PrinterSession::find_interrupted() {
  std::vector<InterruptedJob> found;
  std::error_code error;
  for (const fs::directory_entry& entry : fs::directory_iterator(printer::job_directory(), error)) {
    if (entry.path().extension() != ".journal") continue;
    if (std::optional<InterruptedJob> job = interrupted_job(entry.path().string())) found.push_back(std::move(*job));
  }
  std::optional<InterruptedJob> best;
  {
    std::lock_guard lock(mutex_);
    // A resume taken since the link came back (the job it left was offered from the moment it
    // failed) is no longer interrupted: its journal is the job about to run.
    const std::string resuming = pending_start_ && pending_start_->recover ? pending_start_->recover_journal : "";
    for (InterruptedJob& job : found) {
      if (job.journal != resuming && (!best || job.updated > best->updated)) best = std::move(job);
    }
    status_.interrupted = best;
    publish();
  }
  if (best) {
    add_event(fmt::format("found an interrupted job: {} at layer {}/{} ({}): finish or discard it",
                          fs::path(best->file).filename().string(), best->layer, best->layers, best->state));
  }
}

void PrinterSession::serve_printer() {
  while (true) {
    std::optional<JobStart> start;
    std::vector<std::string> commands;
    bool stop = false;
    {
      std::lock_guard lock(mutex_);
      if (shutting_down_) return;
      if (reconnect_requested_) {
        reconnect_requested_ = false;
        return;
      }
      start = std::move(pending_start_);
      pending_start_.reset();
      commands.swap(pending_commands_);
      stop = stop_now_;
      stop_now_ = false;
    }
    if (stop) {
      protocol_->emergency("M112");
      try {
        protocol_->poll(2000ms);
      } catch (const printer::PrinterError&) {
      }
      throw Halted{"emergency stop (M112): the printer is halted; reconnect to reset it"};
    }
    if (start) {
      run_job(*start);
      continue;
    }
    if (!commands.empty()) {
      run_commands(commands);
      continue;
    }
    idle_step();
  }
}

void PrinterSession::idle_step() {
  if (!autoreport_) {
    const auto now = protocol_->link().now();
    if (last_m105_.count() < 0 || now - last_m105_ >= kTemperatureEvery) {
      protocol_->send("M105");
      last_m105_ = now;
    }
  }
  const auto has_work = [&] {
    return pending_start_ || !pending_commands_.empty() || stop_now_ || shutting_down_ || reconnect_requested_;
  };
  if (link_.sim != nullptr && options_.link.time_scale == 0) {
    // At full speed the simulated clock would race: idle in real time.
    std::unique_lock lock(mutex_);
    work_.wait_for(lock, 100ms, has_work);
    lock.unlock();
    protocol_->poll(100ms);
  } else if (link_.sim != nullptr) {
    protocol_->poll(std::chrono::milliseconds(static_cast<long>(100 * options_.link.time_scale)));
  } else {
    protocol_->poll(100ms);
  }
  sample_temperatures(protocol_->temperatures());
  std::lock_guard lock(mutex_);
  publish();
}

void PrinterSession::run_commands(const std::vector<std::string>& commands) {
  for (const std::string& command : commands) protocol_->send(command);
  protocol_->wait_acknowledged();
  add_event(commands.size() == 1 ? fmt::format("sent {}", commands.front())
                                 : fmt::format("sent {} commands, {} first", commands.size(), commands.front()));
}

void PrinterSession::take_planned_pause(printer::Job& job) {
  // A pause asked for while layer n prints takes effect before layer n + 1: so the pause
  // before layer N is asked for while N - 1 prints (or before the first, for N = 1).
  const printer::JobProgress p = job.progress();
  if (p.state != printer::JobState::printing || p.pause_before_layer > 0) return;
  std::lock_guard lock(mutex_);
  auto& planned = status_.pause_at;
  // Layers already behind are dropped: the print has passed them.
  while (!planned.empty() && planned.front() <= p.layer) planned.erase(planned.begin());
  if (!planned.empty() && planned.front() == p.layer + 1) {
    planned.erase(planned.begin());
    job.request(printer::JobRequest::pause);
    publish();
  }
}

void PrinterSession::publish_job(printer::Job& job) {
  const printer::JobProgress p = job.progress();
  sample_temperatures(p.temperatures);
  const auto now = std::chrono::steady_clock::now();
  std::lock_guard lock(mutex_);
  const bool changed = !status_.progress || status_.progress->state != p.state ||
                       status_.progress->layer != p.layer ||
                       status_.progress->pause_before_layer != p.pause_before_layer;
  if (!changed && now - last_publish_ < 100ms) return;
  last_publish_ = now;
  status_.progress = p;
  status_.heating = heating_of(p);
  if (job_file_) {
    status_.filepos = p.bytes_done;
    const auto& layers = job_file_->gcode.layers;
    status_.layer_z = p.layer > 0 && static_cast<std::size_t>(p.layer) <= layers.size()
                          ? layers[static_cast<std::size_t>(p.layer - 1)].z
                          : std::nullopt;
  }
  publish();
}

std::optional<Heating> PrinterSession::heating_of(const printer::JobProgress& p) const {
  // mutex_ held by the caller. Before the first layer, with a heater short of its target.
  if (p.layer > 0 || p.state != printer::JobState::printing || !p.temperatures) return std::nullopt;
  const printer::Temperatures& now = *p.temperatures;
  // The window's first sample (one a second), to take each heater's rise from.
  const TemperaturePoint* then = nullptr;
  for (const TemperaturePoint& point : history_) {
    if (point.time >= history_.back().time - kHeatingWindow) {
      then = &point;
      break;
    }
  }
  const double span = then != nullptr ? static_cast<double>(history_.back().time - then->time) : 0;
  double left = 0;
  bool heating = false, known = true;
  const auto heater = [&](std::optional<double> actual, std::optional<double> target, std::optional<double> before) {
    if (!actual || !target || *target <= 0 || *actual >= *target - kHeatedWithin) return;
    heating = true;
    const double rate = span > 0 && before ? (*actual - *before) / span : 0;  // °C/s
    if (rate > kRisingAtLeast) {
      left = std::max(left, (*target - *actual) / rate);
    } else {
      known = false;
    }
  };
  heater(now.hotend, now.hotend_target, then != nullptr ? then->temperatures.hotend : std::nullopt);
  heater(now.bed, now.bed_target, then != nullptr ? then->temperatures.bed : std::nullopt);
  if (!heating) return std::nullopt;
  return Heating{known ? std::optional<double>(left) : std::nullopt};
}

std::shared_ptr<JobFile> PrinterSession::read_job(const JobStart& start, const std::string& path) {
  try {
    auto file = std::make_shared<JobFile>(read_job_file(path));
    if (start.recover) app::check_resumable_file(*start.recover, file->gcode);
    return file;
  } catch (const printer::ConfigError& e) {
    {
      std::lock_guard lock(mutex_);
      status_.job_active = false;
      status_.ended = printer::JobState::failed;
      status_.ended_reason = e.what();
      publish();
    }
    add_event(fmt::format("cannot print {}: {}", start.name, e.what()));
    return nullptr;
  }
}

PrinterSession::JobSetup PrinterSession::job_setup(const JobStart& start, const JobFile& file,
                                                   const std::string& path) const {
  const bool dry_run = options_.link.dry_run;
  const printer::PrinterProfile& machine = options_.profiles.printer;
  JobSetup setup;
  if (start.recover) {
    setup.journal = start.recover_journal;
    setup.options = app::resume_job_options(*start.recover, machine, pause_options(options_.link, machine),
                                            setup.journal, dry_run ? "" : options_.link.port,
                                            dry_run ? 0 : options_.baud, !dry_run);
  } else {
    setup.journal = (fs::path(printer::job_directory()) /
                     (job_name(fs::path(start.name).stem().string()) + ".journal"))
                        .string();
    setup.options = job_options_for(file.gcode, path, machine, options_.link, options_.baud, setup.journal);
  }
  setup.options.resume_command =
      dry_run ? std::string("reconnect, then resume it on the mahost serve page")
              : fmt::format("reconnect and resume it on the mahost serve page, or stop mahost serve "
                            "and run {}",
                            printer::resume_command(setup.journal, options_.link.port));
  if (sim_at_full_speed()) setup.options.paused_wait = wait_real_time;
  return setup;
}

void PrinterSession::show_job(std::shared_ptr<const JobFile> file, const std::string& journal) {
  std::lock_guard lock(mutex_);
  job_file_ = std::move(file);
  status_.journal = journal;
  status_.filepos = 0;
  status_.layer_z.reset();
  publish();
}

void PrinterSession::job_tick(printer::Job& job, ControlSocket* control) {
  std::vector<printer::JobRequest> requests;
  std::vector<std::string> tunes;
  {
    std::lock_guard lock(mutex_);
    requests.swap(job_requests_);
    tunes.swap(job_tunes_);
  }
  for (printer::JobRequest r : requests) job.request(r);
  for (const std::string& c : tunes) {
    add_event(job.tune(c) ? fmt::format("tune: {}", c) : fmt::format("{} not sent: the job was ending", c));
  }
  take_planned_pause(job);
  if (control != nullptr) control->serve(job);
  publish_job(job);
}

void PrinterSession::end_job(printer::Job& job, const std::string& journal, printer::JobState state,
                             const std::string& reason, bool printer_lost) {
  const printer::JobProgress last = job.progress();
  // A job that failed or was stopped left its journal: from now on it is the interrupted
  // job, its file locked, not only once the printer is back.
  const std::optional<InterruptedJob> left =
      state == printer::JobState::failed || state == printer::JobState::stopped ? interrupted_job(journal)
                                                                                : std::nullopt;
  std::vector<std::string> unsent;  // tunes that came after the job's last look
  {
    std::lock_guard lock(mutex_);
    if (left) status_.interrupted = left;
    status_.progress = last;
    status_.filepos = last.bytes_done;
    status_.job_active = false;
    status_.cancel_requested = false;
    status_.ended = state;
    status_.ended_reason = reason;
    status_.job_file.clear();
    status_.heating.reset();
    if (printer_lost) {
      status_.connection = Connection::error;
      status_.error = reason;
    }
    job_requests_.clear();
    unsent.swap(job_tunes_);
    publish();
  }
  for (const std::string& c : unsent) add_event(fmt::format("{} not sent: the job had ended", c));
}

void PrinterSession::after_job(const JobStart& start, const printer::JobResult& result, const std::string& journal,
                               const JobFile& file) {
  if (result.state == printer::JobState::completed || result.state == printer::JobState::cancelled) {
    // Nothing to resume: the journal goes (and a G-code `mahost print` sliced beside it).
    const std::string base = fs::path(journal).replace_extension().string();
    std::vector<std::string> own{journal};
    if (start.recover && start.recover->gcode_path == base + ".gcode") own.push_back(base + ".gcode");
    remove_files(own);
  }
  add_event(result.state == printer::JobState::completed
                ? fmt::format("completed {}: {} commands, {} layers", start.name, result.commands_done,
                              file.gcode.layers.size())
                : fmt::format("{} {}: {}", printer::to_string(result.state), start.name, result.reason));
  write_record();
  if (result.state == printer::JobState::stopped) throw Halted{result.reason};
  std::lock_guard lock(mutex_);
  if (restart_after_cancel_) {
    restart_after_cancel_ = false;
    if (result.state == printer::JobState::cancelled && !shutting_down_) {
      pending_start_ = JobStart{start.name, std::nullopt, {}};
      mark_job_starting(status_, start.name);
      publish();
    }
  }
}

void PrinterSession::run_job(const JobStart& start) {
  const std::string path = start.recover ? start.recover->gcode_path : files_.path_of(start.name);
  const std::shared_ptr<const JobFile> file = read_job(start, path);
  if (!file) return;
  JobSetup setup = job_setup(start, *file, path);
  const std::string journal = setup.journal;
  show_job(file, journal);
  std::optional<ControlSocket> control;
  try {
    control.emplace(fs::path(journal).replace_extension(".sock").string());
  } catch (const printer::ConfigError&) {
    // `mahost ctl` cannot reach this job (a path too long for a socket); the page can.
  }
  printer::Job job(*protocol_, file->gcode, std::move(setup.options));
  job.on_event = [this](const std::string& line) { add_event(line); };
  job.on_tick = [&](printer::Job& j) { job_tick(j, control ? &*control : nullptr); };
  add_event(start.recover ? fmt::format("resuming {} at layer {}/{}", start.name,
                                        start.recover->layer_index + 1, file->gcode.layers.size())
                          : fmt::format("printing {}: {} layers, {} commands", start.name,
                                        file->gcode.layers.size(), file->gcode.size()));
  printer::JobResult result;
  try {
    result = job.run();
    install_idle_hook();
  } catch (const printer::LinkError& e) {
    end_job(job, journal, printer::JobState::failed, e.what(), true);
    throw;
  } catch (const printer::PrinterError& e) {
    end_job(job, journal, printer::JobState::failed, e.what(), true);
    throw;
  }
  end_job(job, journal, result.state, result.reason, result.state == printer::JobState::stopped);
  control.reset();
  after_job(start, result, journal, *file);
}

void PrinterSession::write_record() const {
  if (link_.sim == nullptr) return;
  try {
    if (!options_.record_path.empty()) sim::write_record_json(link_.sim->printer(), options_.record_path);
    if (!options_.printed_stl_path.empty()) sim::write_printed_stl(link_.sim->printer(), options_.printed_stl_path);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "mahost serve: %s\n", e.what());
  }
}

}  // namespace host::serve
