// The printer behind `mahost serve`: the connected link, the one job that runs on it, the STL
// being sliced, and the state the API and the page read (DESIGN.md §1, §4).
//
// One thread owns the link and the protocol and does all the talking to the printer: it
// connects (and reconnects after a failure), keeps the temperatures fresh while idle (M155
// auto-report when the firmware has it, else M105 every 2 s), sends the G-code lines a client
// asks for, and runs each job through printer::Job exactly as `mahost print` does, with the
// same journal. The HTTP threads never touch the link: they queue requests, which the job
// thread applies in Job::on_tick (about every 100 ms of link time), and read a snapshot the
// job thread publishes under a mutex. So however many clients poll, the printer sees exactly
// the file's commands, in order, once.
//
// At every connect the job directory is searched for an interrupted job of this printer (a
// journal whose process died mid-print, whose G-code is unchanged): the page offers to finish
// it (`mahost resume`'s recovery) or to drop it.
#pragma once

#include <condition_variable>
#include <cstdint>
#include <deque>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

#include "app/slice_options.h"
#include "host/job_setup.h"
#include "host/serve/file_store.h"
#include "host/serve/job_file.h"
#include "printer/job.h"
#include "printer/journal.h"
#include "printer/profile.h"
#include "printer/replies.h"

namespace host {
class ControlSocket;
}

namespace host::serve {

enum class Connection { connecting, operational, error, closed };

struct TemperaturePoint {
  std::int64_t time = 0;  // Unix seconds
  printer::Temperatures temperatures;
};

struct Event {
  std::uint64_t id = 0;   // increasing from 1
  std::int64_t time = 0;  // Unix seconds
  std::string text;
};

// An STL being (or last) sliced on the host.
struct SliceStatus {
  std::string model, gcode;      // names in the files folder
  std::string stage;             // "contours", "toolpaths", "writing", "done", "failed"
  std::size_t done = 0, total = 0;
  std::string error;
  std::string summary;           // slice_summary_text once done
  std::string plan;              // slice_plan_text once done ("" for uniform layers)
};

// An interrupted job found in the job directory.
struct InterruptedJob {
  std::string journal;           // its path
  std::string file;              // the G-code's path
  std::string name;              // its name in the files folder; "" for a file elsewhere
  std::string state, reason, updated;
  int layer = 0, layers = 0;     // the layer a resume reprints, from 1
};

// A job waiting for its heaters before its first layer: how far each is, and the time left
// at the pace they rose at over the last kHeatingWindow (unknown until they have risen).
struct Heating {
  std::optional<double> seconds_left;
};

// Everything the API and the page show, as of `version`.
struct Status {
  std::string instance;          // this server process's, so a page notices a restart
  std::uint64_t version = 0;
  Connection connection = Connection::connecting;
  std::string link;              // "/dev/ttyUSB0", "simulated printer"
  std::string firmware;
  std::string error;             // why the link or the printer failed
  int retries = 0;               // reopenings tried since the link failed (every kRetryAfter)
  bool dry_run = false;
  std::optional<printer::Temperatures> temperatures;

  std::optional<StoredFile> selected;  // the file a start prints
  bool job_active = false;       // a job is starting or running (printing ... cancelling)
  std::string job_file;          // the name in the files folder a starting or running job prints
  bool cancel_requested = false;
  std::optional<printer::JobProgress> progress;  // the running job's, else the last one's
  std::optional<Heating> heating;                // while the running job heats before layer 1
  std::optional<printer::JobState> ended;        // how the last job ended, when none runs
  std::string ended_reason;
  std::uint64_t filepos = 0;
  std::optional<double> layer_z;
  std::string journal;           // the running job's

  std::optional<SliceStatus> slicing;
  std::optional<InterruptedJob> interrupted;
  // Layers (from 1) a print pauses before, as `mahost print --pause-at-layer`; kept for the
  // next job too, each taken once it is reached.
  std::vector<int> pause_at;
};

// Why the file `name` in the files folder may not be replaced, deleted or printed over now
// (one line, for a 409), or "" when it may: the file a job prints or is about to, the
// interrupted job's file (its part is still on the bed: a resume reprints from it), the
// G-code a slice is writing.
std::string file_lock(const Status& status, const std::string& name);
// The names file_lock refuses, with its reason each.
std::vector<std::pair<std::string, std::string>> file_locks(const Status& status);

// Why a new job may not start now, or "": an interrupted job waits to be finished or discarded
// (nothing prints over a part on the bed), a job runs, the printer is not operational.
std::string start_refusal(const Status& status);

// What a request came to, as an HTTP status and a one-line message for the client.
struct Outcome {
  int status = 204;
  std::string message;
  bool ok() const { return status < 300; }
};

enum class PauseAction { pause, resume, toggle };

// Options for slicing an STL upload on the host, as the page and the slice command give them.
struct SliceRequest {
  std::string model;             // a clean STL name in the files folder
  std::string gcode;             // the clean G-code name to write
  app::SliceOptions options;     // printer, material, layer, contour, placement (model.path set here)
  bool select = false, print = false;
};

// Why `command` (upper case, as http_api's checked_command gives it) is not taken while a job
// prints, or nothing when it is: a temperature (M104, M140), the fan (M106, M107), the speed
// and flow factors (M220, M221), a babystep (M290), a message (M117) or a report (M105,
// M114), as OctoPrint's tune controls send. Moves, homing, waits and anything else would
// change what the file does under it.
std::optional<std::string> tune_refusal(std::string_view command);

class PrinterSession {
 public:
  struct Options {
    LinkOptions link;
    printer::Profiles profiles;  // the printer it serves: a dry run simulates it
    int baud = 115200;
    std::string record_path;     // dry run: the sim's record, written after each job and at exit
    std::string printed_stl_path;
  };

  PrinterSession(Options options, FileStore& files);
  ~PrinterSession();
  PrinterSession(const PrinterSession&) = delete;
  PrinterSession& operator=(const PrinterSession&) = delete;

  void start();
  // Asks the session to end: a running job is cancelled (stopped at once with `at_once`);
  // returns at once. wait() joins the threads.
  void shut_down(bool at_once);
  void wait();
  bool finished() const;

  Status status() const;
  // Waits until the status is newer than `version` or `timeout` passes, or the session ends.
  Status wait_for_change(std::uint64_t version, std::chrono::milliseconds timeout) const;
  std::vector<TemperaturePoint> history(std::size_t limit) const;
  std::vector<Event> events_after(std::uint64_t id) const;
  // The file the running (or last) job prints, for the page's drawing; null before any job.
  std::shared_ptr<const JobFile> job_file() const;
  const printer::Profiles& profiles() const { return options_.profiles; }

  // OctoPrint's job and file commands; each answers 204 (or 202) or the status of its
  // precondition: 409 when the printer or the job is not in a state for it, 404 for a file
  // that is not there, 415 for one that cannot be printed.
  Outcome select(const std::string& name, bool print);
  Outcome start_job();
  Outcome cancel_job();
  Outcome pause_job(PauseAction action);
  Outcome restart_job();
  Outcome emergency_stop();
  // The layers to pause before (from 1; replaces the list). 400 for a layer below 1.
  Outcome set_pause_at(std::vector<int> layers);
  // G-code lines for the printer: any when no job runs; while one runs (or waits paused), the
  // tunes tune_refusal takes, sent between the job's lines, or M112, which stops it at once;
  // else 409 with tune_refusal's reason.
  Outcome send_commands(const std::vector<std::string>& commands);
  Outcome reconnect();
  Outcome resume_interrupted();
  Outcome discard_interrupted();
  Outcome slice(SliceRequest request);
  Outcome unselect();

  // What storing an upload came to: refused (409: the name is locked, file_lock), or stored
  // and, as asked, selected and started; when a print was asked for and not started, why.
  struct Stored {
    Outcome outcome;
    bool selected = false, printing = false;
    std::string not_printed;
  };
  // Moves a complete, checked upload into place as `name` and selects and starts it as asked,
  // in one step: no other request comes between the check of the name's lock, the rename and
  // the start, so two uploads of one name never both print, and neither replaces a file a job
  // prints. A G-code upload passes its analysis (kept, not read again).
  Stored store_upload(FileStore::Upload& upload, const std::string& name,
                      const std::optional<GcodeAnalysis>& analysis, bool select, bool print);
  // Deletes a file unless it is locked (409); 404 when there is none.
  Outcome delete_file(const std::string& name);
  // A line for the event log the page shows (and stderr).
  void note(const std::string& text) { add_event(text); }

 private:
  struct JobStart {
    std::string name;                      // in the files folder
    std::optional<printer::JournalRecord> recover;  // an interrupted job to finish
    std::string recover_journal;
  };

  // Both with mutex_ held.
  Outcome select_found(const StoredFile& file, bool print);
  void forget_selection(const std::string& name);
  void run();
  // `retrying`: an automatic reopening after the link failed (the status keeps the failure).
  void connect_printer(bool retrying);
  void serve_printer();
  void idle_step();
  // A job, from its file to its end, in the steps below.
  void run_job(const JobStart& start);
  // The job's file read and checked (a resume's against its journal); nullptr, the job ended
  // failed and the event said, when it cannot be printed.
  std::shared_ptr<JobFile> read_job(const JobStart& start, const std::string& path);
  struct JobSetup {
    printer::JobOptions options;
    std::string journal;
  };
  // The job's options and journal: a new job's, or a resume's from its journal.
  JobSetup job_setup(const JobStart& start, const JobFile& file, const std::string& path) const;
  // The job's file and journal published (the layer drawings and filepos read them).
  void show_job(std::shared_ptr<const JobFile> file, const std::string& journal);
  // A tick of the job: the clients' requests and tunes handed to it, a planned pause taken,
  // `mahost ctl` served (when `control`), the progress published.
  void job_tick(printer::Job& job, ControlSocket* control);
  // The job's end published; `printer_lost`: it ended with the link or the printer (failed
  // with the link, or a halt), and the connection is down in the same update, so no client
  // sees the printer operational between the two and has a start or a resume taken, then
  // dropped.
  void end_job(printer::Job& job, const std::string& journal, printer::JobState state, const std::string& reason,
               bool printer_lost);
  // After the end: a finished or cancelled job's journal removed, the event, the record, a
  // halt thrown (Halted), a restart asked with the cancel queued.
  void after_job(const JobStart& start, const printer::JobResult& result, const std::string& journal,
                 const JobFile& file);
  void run_commands(const std::vector<std::string>& commands);
  void stop_pending_start();
  void find_interrupted();
  // The journal's job when it can be finished here (not ended, this printer's, no other mahost
  // at it, its G-code unchanged).
  std::optional<InterruptedJob> interrupted_job(const std::string& journal) const;
  void install_idle_hook();
  void slice_worker(SliceRequest request);
  // `text` with the files folder's paths as the client names the files.
  std::string client_text(std::string text) const;
  void publish(bool force = false);
  void publish_job(printer::Job& job);
  std::optional<Heating> heating_of(const printer::JobProgress& progress) const;
  void take_planned_pause(printer::Job& job);
  void sample_temperatures(const std::optional<printer::Temperatures>& temperatures);
  void add_event(const std::string& text);
  void write_record() const;
  bool sim_at_full_speed() const;

  Options options_;
  FileStore& files_;

  // The job thread's own (never touched by the HTTP threads).
  OpenLink link_;
  std::unique_ptr<printer::LineProtocol> protocol_;
  std::chrono::steady_clock::time_point last_publish_{}, last_sample_{};
  std::chrono::nanoseconds last_m105_{-1};
  bool autoreport_ = false;

  mutable std::mutex mutex_;
  mutable std::condition_variable changed_;  // status_ changed; the session is ending
  std::condition_variable work_;             // a request for the job thread
  Status status_;
  std::deque<TemperaturePoint> history_;
  std::deque<Event> events_;
  std::uint64_t next_event_ = 1;
  std::shared_ptr<const JobFile> job_file_;

  // Requests for the job thread, guarded by mutex_.
  std::optional<JobStart> pending_start_;
  std::vector<printer::JobRequest> job_requests_;
  std::vector<std::string> pending_commands_;
  std::vector<std::string> job_tunes_;       // for the running job, between its lines
  bool restart_after_cancel_ = false;
  bool reconnect_requested_ = false;
  bool stop_now_ = false;                    // emergency stop with no job
  bool shutting_down_ = false;
  bool finished_ = false;
  bool slicing_ = false;

  std::thread job_thread_, slice_thread_;
};

// OctoPrint's text for the state: "Operational", "Printing", "Pausing", "Paused",
// "Cancelling", "Error", "Offline", "Opening serial connection".
std::string state_text(const Status& status);

}  // namespace host::serve
