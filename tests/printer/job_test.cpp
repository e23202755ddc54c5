// Jobs against the simulated printer (sim::SimLink): what the printer executed and deposited,
// with faults, pauses, cancels and stops (DESIGN.md §4).
#include "printer/job.h"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <limits>
#include <optional>
#include <sstream>

#include <doctest/doctest.h>
#include <fmt/core.h>

#include "printer/error.h"
#include "printer/gcode_line.h"
#include "printer/scripted_firmware.h"
#include "printer/split_link.h"
#include "printer/test_program.h"
#include "sim/dialect.h"
#include "sim/faults.h"
#include "sim/sim_link.h"
#include "support/run_command.h"

namespace job_test {

using namespace printer;

namespace {

// What the printer executed of the job: without the host's own M110, M115, M105, M155, M113.
std::vector<std::string> job_part(const std::vector<std::string>& executed) {
  std::vector<std::string> out;
  for (const std::string& c : executed) {
    const GcodeCommand parsed = parse_gcode_line(c);
    if (parsed.is('M', 110) || parsed.is('M', 115) || parsed.is('M', 105) || parsed.is('M', 155) ||
        parsed.is('M', 113)) {
      continue;
    }
    out.push_back(c);
  }
  return out;
}

std::vector<std::string> commands_of(const GcodeFile& file) {
  std::vector<std::string> out;
  for (std::size_t i = 0; i < file.size(); ++i) out.emplace_back(file.command(i));
  return out;
}

struct Printed {
  std::vector<std::string> executed;
  sim::DepositionRecord deposition;
  JobResult result;
  ProtocolStats stats;
};

Printed print(const GcodeFile& file, sim::Config config, JobOptions options = {},
              ProtocolOptions protocol_options = {},
              const std::function<void(Job&)>& on_tick = {}) {
  sim::SimLink link(config);
  LineProtocol protocol(link, protocol_options);
  protocol.connect();
  Job job(protocol, file, options);
  job.on_tick = on_tick;
  Printed printed;
  printed.result = job.run();
  link.printer().finish();
  printed.executed = link.printer().executed_commands();
  printed.deposition = link.printer().deposition();
  printed.stats = protocol.stats();
  return printed;
}

bool same_moves(const sim::DepositionRecord& a, const sim::DepositionRecord& b) {
  if (a.moves.size() != b.moves.size()) return false;
  for (std::size_t i = 0; i < a.moves.size(); ++i) {
    const sim::DepositedMove& m = a.moves[i];
    const sim::DepositedMove& n = b.moves[i];
    if (m.z != n.z || m.start.x != n.start.x || m.start.y != n.start.y || m.end.x != n.end.x ||
        m.end.y != n.end.y || m.e != n.e || m.feedrate != n.feedrate) {
      return false;
    }
  }
  return true;
}

// The ring program as each firmware takes it: Teacup heats with M116 (no M109 or M190) and
// has no M107.
std::string ring_program_for(sim::Dialect dialect, int layers, int segments) {
  std::string text = test_support::ring_program(layers, segments);
  if (dialect == sim::Dialect::teacup) {
    text.replace(text.find("M190 S60\nM109 S210\n"), 19, "M116\n");
    text.replace(text.find("M107\n"), 5, "M106 S0\n");
  }
  return text;
}

// `text` written in inches: G20 first, every X Y Z E and F divided by 25.4, to a millionth of
// an inch (25 nm; Marlin reads lines of 82 characters at most).
std::string in_inches(const std::string& text) {
  std::string out = "G20\n";
  std::istringstream lines(text);
  for (std::string line; std::getline(lines, line);) {
    const std::size_t comment = line.find(';');
    std::istringstream words(line.substr(0, comment));
    std::string written;
    for (std::string word; words >> word;) {
      if (word.size() > 1 && std::string_view("XYZEF").find(word[0]) != std::string_view::npos) {
        word = fmt::format("{}{:.6f}", word[0], std::stod(word.substr(1)) / 25.4);
      }
      written += (written.empty() ? "" : " ") + word;
    }
    if (comment != std::string::npos) written += (written.empty() ? "" : " ") + line.substr(comment);
    out += written + "\n";
  }
  return out;
}

// The ring program in inches for `dialect`, and that dialect's simulated printer.
GcodeFile inch_ring(sim::Dialect dialect, int layers, int segments) {
  return parse_gcode(in_inches(ring_program_for(dialect, layers, segments)), "ring.gcode");
}
sim::Config speaking(sim::Dialect dialect) {
  sim::Config config;
  config.dialect = dialect;
  return config;
}

// A host that dies 0.3 s into layer 10 (the job abandoned from its tick: no heaters off, no
// journal of the failure) printing `file` on `link`'s printer; then the printer is reset or
// not, and the moves it had queued run out. The journal the host left.
JournalRecord host_dies_in_layer_10(sim::SimLink& link, const GcodeFile& file, const std::string& journal_path,
                                    bool reset) {
  struct HostDied {};
  JobOptions options;
  options.journal_path = journal_path;
  {
    LineProtocol protocol(link);
    protocol.connect();
    Job job(protocol, file, options);
    int ticks = 0;  // 100 ms of link time each: 0.3 s into a layer of about 4 s
    job.on_tick = [&ticks](Job& j) {
      if (j.progress().layer == 10 && ++ticks == 3) throw HostDied{};
    };
    CHECK_THROWS_AS(job.run(), HostDied);
  }
  if (reset) link.printer().reset();
  link.printer().run_until(link.printer().now() + 5);
  return read_journal(journal_path);
}

// A second host's job, resuming from `journal`.
JobOptions resume_from(const JournalRecord& journal) {
  JobOptions resume;
  resume.first_command = journal.resume_command;
  resume.recover_from = journal.state_at_resume;
  return resume;
}

// The farthest X and Y and the highest Z the commands `executed[from..]` sent the nozzle to,
// from `state`, read by the interpreter the simulated printer moves by, mm.
printer::AxisPosition farthest_reached(const std::vector<std::string>& executed, std::size_t from,
                                       printer::GcodeState state) {
  const double none = -std::numeric_limits<double>::infinity();
  printer::AxisPosition far{none, none, none, none};
  for (std::size_t i = from; i < executed.size(); ++i) {
    const printer::GcodeStep step = printer::interpret(state, parse_gcode_line(executed[i]));
    for (const printer::Motion& move : step.moves()) {
      far.x = std::max(far.x, move.to.x);
      far.y = std::max(far.y, move.to.y);
      far.z = std::max(far.z, move.to.z);
    }
  }
  return far;
}

}  // namespace

TEST_CASE("faulty_link_prints_every_command_once") {
  const GcodeFile file = parse_gcode(test_support::ring_program(60, 120), "ring.gcode");
  const Printed clean = print(file, sim::Config{});
  CHECK(job_part(clean.executed) == commands_of(file));

  for (const bool ok_after_resend : {true, false}) {
    CAPTURE(ok_after_resend);
    sim::Config noisy;
    noisy.ok_after_resend = ok_after_resend;
    noisy.faults = sim::parse_fault_spec("corrupt=0.01,drop-ok=0.01,resend=0.01,dup-ok=0.005,seed=7");
    const Printed faulty = print(file, noisy);
    CHECK(job_part(faulty.executed) == commands_of(file));
    CHECK(same_moves(faulty.deposition, clean.deposition));
    CHECK(faulty.stats.resend_requests > 20);
    CHECK(faulty.stats.probes > 10);
  }
}

TEST_CASE("faulty_link_with_a_window_prints_every_command_once") {
  const GcodeFile file = parse_gcode(test_support::ring_program(60, 120), "ring.gcode");
  const Printed clean = print(file, sim::Config{});
  sim::Config noisy;
  noisy.advanced_ok = true;
  noisy.faults = sim::parse_fault_spec("corrupt=0.01,drop-ok=0.01,resend=0.01,dup-ok=0.005,seed=11");
  ProtocolOptions window;
  window.window = 4;
  const Printed faulty = print(file, noisy, {}, window);
  CHECK(job_part(faulty.executed) == commands_of(file));
  CHECK(same_moves(faulty.deposition, clean.deposition));
  MESSAGE("resends " << faulty.stats.resend_requests << " stale " << faulty.stats.stale_resends
                     << " probes " << faulty.stats.probes << " dup " << faulty.stats.duplicate_oks
                     << " resent " << faulty.stats.lines_resent);
}

TEST_CASE("pause_and_resume_at_20_layers_deposit_the_same_part") {
  const GcodeFile file = parse_gcode(test_support::ring_program(60, 80), "ring.gcode");
  const Printed plain = print(file, sim::Config{});
  JobOptions options;
  for (int layer = 2; layer <= 59; layer += 3) options.pause_at_layers.push_back(layer);
  REQUIRE(options.pause_at_layers.size() == 20);
  int paused_ticks = 0;
  const Printed paused = print(file, sim::Config{}, options, {}, [&](Job& job) {
    if (job.progress().state == JobState::paused && ++paused_ticks % 5 == 0) {
      job.request(JobRequest::resume);  // after half a second of pause on the sim clock
    }
  });
  CHECK(paused.result.state == JobState::completed);
  CHECK(paused.result.pauses == 20);
  // The park moves extrude nothing and the return restores X, Y, Z, E and F exactly, so the
  // printer laid down the very same moves.
  CHECK(paused.deposition.moves.size() == plain.deposition.moves.size());
  CHECK(same_moves(paused.deposition, plain.deposition));
  // And the file's own commands all ran, once, in order, between the pause sequences.
  std::vector<std::string> mine = job_part(paused.executed);
  std::vector<std::string> file_commands = commands_of(file);
  std::size_t matched = 0;
  for (const std::string& c : mine) {
    if (matched < file_commands.size() && c == file_commands[matched]) ++matched;
  }
  CHECK(matched == file_commands.size());
}

TEST_CASE("resume_restores_z_and_e_after_a_pause_in_relative_e_mode") {
  std::string text = test_support::ring_program(12, 40);
  // The same part written with relative E: the resume must restore M83, not just E.
  GcodeFile absolute = parse_gcode(text, "abs.gcode");
  const Printed plain = print(absolute, sim::Config{});
  JobOptions options;
  options.pause_at_layers = {5, 9};
  const Printed paused = print(absolute, sim::Config{}, options, {}, [](Job& job) {
    if (job.progress().state == JobState::paused) job.request(JobRequest::resume);
  });
  CHECK(same_moves(paused.deposition, plain.deposition));
}

TEST_CASE("a_pause_in_an_inch_file_lifts_parks_and_returns_in_millimetres") {
  // The host's own moves are in mm; the printer reads the file's G20 until told G21. The
  // pause's lift and park and the resume's return go between G21 and G20, and the pause asks
  // Repetier where it is after G21 (it reports M114 in inches after G20).
  for (const sim::Dialect dialect : {sim::Dialect::teacup, sim::Dialect::repetier}) {
    CAPTURE(sim::to_string(dialect));
    const GcodeFile file = inch_ring(dialect, 12, 40);
    const sim::Config config = speaking(dialect);
    const Printed plain = print(file, config);
    sim::SimLink link(config);
    LineProtocol protocol(link);
    protocol.connect();
    JobOptions options;
    options.pause_at_layers = {5, 9};
    Job job(protocol, file, options);
    std::vector<sim::Printer::Position> parked;  // at the first tick of each pause
    std::vector<std::string> events;
    job.on_event = [&](const std::string& e) { events.push_back(e); };
    JobState before = JobState::printing;
    job.on_tick = [&](Job& j) {
      const JobState now = j.progress().state;
      if (now == JobState::paused && before != JobState::paused) {
        parked.push_back(link.printer().position());
        j.request(JobRequest::resume);
      }
      before = now;
    };
    CHECK(job.run().state == JobState::completed);
    CHECK(protocol.refused().empty());
    link.printer().finish();
    // Paused before layer 5 at layer 4's Z (0.8 mm) and before layer 9 at 1.6 mm: parked at
    // X5 Y5 (PauseOptions), 5 mm higher.
    REQUIRE(parked.size() == 2);
    const double paused_at[] = {0.8, 1.6};
    for (std::size_t i = 0; i < 2; ++i) {
      CHECK(parked[i].x == doctest::Approx(5));
      CHECK(parked[i].y == doctest::Approx(5));
      CHECK(parked[i].z == doctest::Approx(paused_at[i] + 5));
    }
    CHECK(std::count_if(events.begin(), events.end(), [](const std::string& e) {
            return e.find(" Z0.80; nozzle parked at Z5.80") != std::string::npos;
          }) == 1);
    CHECK(same_moves(link.printer().deposition(), plain.deposition));
    // Nowhere higher than the end G-code's lift 10 mm above the top layer, nor farther out
    // than the ring (X and Y at most 125 mm).
    printer::GcodeState power_on;
    power_on.rules = sim::gcode_rules(dialect);
    const printer::AxisPosition far = farthest_reached(link.printer().executed_commands(), 0, power_on);
    CHECK(far.z <= 12 * 0.2 + 10 + 1e-3);
    CHECK(far.x <= 125 + 1e-3);
    CHECK(far.y <= 125 + 1e-3);
  }
}

TEST_CASE("a_cancel_in_an_inch_file_lifts_and_parks_in_millimetres_and_leaves_them") {
  for (const sim::Dialect dialect : {sim::Dialect::teacup, sim::Dialect::repetier}) {
    CAPTURE(sim::to_string(dialect));
    const GcodeFile file = inch_ring(dialect, 30, 60);
    const sim::Config config = speaking(dialect);
    sim::SimLink link(config);
    LineProtocol protocol(link);
    protocol.connect();
    Job job(protocol, file, {});
    job.on_tick = [](Job& j) {
      if (j.progress().layer == 10) j.request(JobRequest::cancel);
    };
    CHECK(job.run().state == JobState::cancelled);
    const sim::Printer::Position at = link.printer().position();
    CHECK(at.x == doctest::Approx(5));
    CHECK(at.y == doctest::Approx(5));
    CHECK(at.z > 1.8 + 9.99);  // layer 10 at 1.8 or 2.0 mm, lifted 10 mm
    CHECK(at.z < 2.0 + 10.01);
    // Left in mm, the units a printer powers on in, for whatever file comes next.
    const std::vector<std::string>& executed = link.printer().executed_commands();
    const auto last_g21 = std::find(executed.rbegin(), executed.rend(), "G21");
    CHECK(last_g21 != executed.rend());
    CHECK(std::find(executed.rbegin(), last_g21, "G20") == last_g21);
  }
}

TEST_CASE("cancel_ends_with_heaters_off_lifted_and_motors_off") {
  const GcodeFile file = parse_gcode(test_support::ring_program(30, 60), "ring.gcode");
  sim::SimLink link{sim::Config{}};
  LineProtocol protocol(link);
  protocol.connect();
  Job job(protocol, file, {});
  job.on_tick = [](Job& j) {
    if (j.progress().layer == 10) j.request(JobRequest::cancel);
  };
  const JobResult result = job.run();
  CHECK(result.state == JobState::cancelled);
  CHECK(result.reason == "cancelled at layer 10/30");
  CHECK(result.commands_done < file.size());
  const auto& executed = link.printer().executed_commands();
  CHECK(executed.back() == "M84");
  CHECK(link.printer().hotend_target() == 0);
  CHECK(link.printer().bed_target() == 0);
  CHECK(link.printer().position().z > 1.8 + 9.99);  // layer 10 at 1.8 or 2.0 mm, lifted 10 mm
}

TEST_CASE("emergency_stop_halts_the_printer_at_once") {
  const GcodeFile file = parse_gcode(test_support::ring_program(30, 60), "ring.gcode");
  sim::SimLink link{sim::Config{}};
  LineProtocol protocol(link);
  protocol.connect();
  Job job(protocol, file, {});
  job.on_tick = [](Job& j) {
    if (j.progress().layer == 5) j.request(JobRequest::stop);
  };
  const JobResult result = job.run();
  CHECK(result.state == JobState::stopped);
  CHECK(result.reason.starts_with("emergency stop (M112) at layer 5/30: the printer halted"));
  CHECK(link.printer().state() == sim::PrinterState::halted);
  CHECK(link.printer().executed_commands().back() == "M112");
}

TEST_CASE("halt_fault_ends_the_job_with_the_reason_and_a_journal") {
  const std::string dir = test_support::scratch_dir("halt_fault");
  const GcodeFile file = parse_gcode(test_support::ring_program(30, 60), "ring.gcode");
  sim::Config config;
  config.faults = sim::parse_fault_spec("halt-at-line=900");
  sim::SimLink link(config);
  LineProtocol protocol(link);
  protocol.connect();
  JobOptions options;
  options.journal_path = dir + "/job.journal";
  Job job(protocol, file, options);
  std::string message;
  try {
    job.run();
  } catch (const PrinterError& e) {
    message = e.what();
  }
  CHECK(message.starts_with("simulated printer: the printer stopped: Error:Printer halted. kill() called!"));
  CHECK(message.find("mahost resume " + options.journal_path) != std::string::npos);
  CHECK(message.find('\n') == std::string::npos);
  const JournalRecord journal = read_journal(options.journal_path);
  CHECK(journal.state == printer::JobState::failed);
  CHECK(journal.layer_index >= 0);
  CHECK(journal.resume_command == file.layers[static_cast<std::size_t>(journal.layer_index)].first_command);
}

TEST_CASE("disconnect_then_resume_reprints_only_the_interrupted_layer") {
  // In each firmware: the recovery heats as it does (Teacup: M104/M140 and M116, it has no
  // M109 or M190), after the board reset on the reconnect and cooled.
  for (const sim::Dialect dialect : {sim::Dialect::marlin, sim::Dialect::teacup, sim::Dialect::repetier}) {
    CAPTURE(sim::to_string(dialect));
    const std::string dir = test_support::scratch_dir(fmt::format("disconnect_resume_{}", sim::to_string(dialect)));
    const GcodeFile file = parse_gcode(ring_program_for(dialect, 30, 60), "ring.gcode");
    sim::Config config;
    config.dialect = dialect;
    const Printed clean = print(file, config);
    config.faults = sim::parse_fault_spec("disconnect-at-line=1234");
    sim::SimLink link(config);
    JobOptions options;
    options.journal_path = dir + "/job.journal";
    {
      LineProtocol protocol(link);
      protocol.connect();
      Job job(protocol, file, options);
      std::string message;
      try {
        job.run();
      } catch (const LinkError& e) {
        message = e.what();
      }
      CHECK(message.starts_with("simulated printer: the link is gone"));
      CHECK(message.find("; the link is gone before the heaters could be turned off: check that they "
                         "are off; to finish the part: mahost resume ") != std::string::npos);
      CHECK(message.find('\n') == std::string::npos);
    }
    const JournalRecord journal = read_journal(options.journal_path);
    REQUIRE(journal.state == printer::JobState::failed);
    const std::size_t before = link.printer().deposition().moves.size();

    link.reconnect();
    LineProtocol protocol(link);
    protocol.connect();
    CHECK(protocol.restart_seen());
    JobOptions resume;
    resume.journal_path = options.journal_path;
    resume.first_command = journal.resume_command;
    resume.recover_from = journal.state_at_resume;
    Job job(protocol, file, resume);
    CHECK(job.run().state == JobState::completed);
    CHECK(protocol.refused().empty());

    // What was printed: the clean print's moves up to the failure, then again from the start
    // of the interrupted layer: that layer's printed part once more, nothing else.
    const auto& moves = link.printer().deposition().moves;
    const auto& reference = clean.deposition.moves;
    std::size_t layer_start = 0;
    const double layer_z = journal.state_at_resume.z + 0.2;
    while (layer_start < reference.size() && reference[layer_start].z < layer_z - 1e-6) ++layer_start;
    REQUIRE(before >= layer_start);
    REQUIRE(moves.size() == before + (reference.size() - layer_start));
    sim::DepositionRecord head, tail, reference_head, reference_tail;
    for (std::size_t i = 0; i < before; ++i) head.moves.push_back(moves[i]);
    for (std::size_t i = before; i < moves.size(); ++i) tail.moves.push_back(moves[i]);
    for (std::size_t i = 0; i < before; ++i) reference_head.moves.push_back(reference[i]);
    for (std::size_t i = layer_start; i < reference.size(); ++i) reference_tail.moves.push_back(reference[i]);
    CHECK(same_moves(head, reference_head));
    CHECK(same_moves(tail, reference_tail));
    CHECK(before - layer_start < 61);  // less than one layer was printed twice
  }
}

TEST_CASE("a_resume_asks_the_printer_where_z_is_and_sets_it_only_where_it_was_lost") {
  // The host dies at layer 10 (the job is abandoned from its tick); a second host resumes
  // from the journal on the same printer. Not reset, it kept Z (M114 reports the layer's Z):
  // no G92 Z. Reset, it reports 0: Z comes from the journal. Either way the part comes out as
  // the clean print's moves, the interrupted layer's printed part once more.
  const std::string dir = test_support::scratch_dir("resume_asks_for_z");
  const GcodeFile file = parse_gcode(test_support::ring_program(20, 40), "ring.gcode");
  const Printed clean = print(file, sim::Config{});
  for (const bool reset : {false, true}) {
    CAPTURE(reset);
    sim::SimLink link{sim::Config{}};
    const JournalRecord journal =
        host_dies_in_layer_10(link, file, dir + fmt::format("/job{}.journal", reset), reset);
    REQUIRE(journal.layer_index == 9);
    LineProtocol protocol(link);
    protocol.connect();
    Job job(protocol, file, resume_from(journal));
    std::vector<std::string> events;
    job.on_event = [&](const std::string& e) { events.push_back(e); };
    CHECK(job.run().state == JobState::completed);
    REQUIRE(!events.empty());
    const std::vector<std::string>& executed = link.printer().executed_commands();
    const bool set_z = std::find_if(executed.begin(), executed.end(), [](const std::string& c) {
                         return c.starts_with("G92 Z");
                       }) != executed.end();
    CHECK(set_z == reset);
    CHECK(events.front().find(reset ? "setting Z from the journal (the printer reports Z 0.00"
                                    : "(the printer kept Z: it reports 2.00)") != std::string::npos);
    // Every move after the resume at the clean print's heights.
    const auto& moves = link.printer().deposition().moves;
    const double top = clean.deposition.moves.back().z;
    CHECK(moves.back().z == doctest::Approx(top));
    for (const sim::DepositedMove& m : moves) CHECK(m.z <= top + 1e-9);
  }
}

TEST_CASE("a_resume_of_an_inch_file_lifts_and_returns_in_millimetres_on_a_printer_that_kept_g20_or_reset") {
  // The host dies mid-layer; a second host resumes from the journal, whose units are inches.
  // A printer that was not reset still reads inches, one that was reads mm: both are sent G21
  // before the position query (Repetier reports M114 in inches after G20), the lift and the
  // return, and G20 before the file goes on.
  const std::string dir = test_support::scratch_dir("resume_in_inches");
  for (const sim::Dialect dialect : {sim::Dialect::teacup, sim::Dialect::repetier}) {
    const GcodeFile file = inch_ring(dialect, 20, 40);
    const sim::Config config = speaking(dialect);
    const Printed clean = print(file, config);
    for (const bool reset : {false, true}) {
      CAPTURE(sim::to_string(dialect));
      CAPTURE(reset);
      sim::SimLink link(config);
      const JournalRecord journal = host_dies_in_layer_10(
          link, file, dir + fmt::format("/{}{}.journal", sim::to_string(dialect), reset), reset);
      REQUIRE(journal.state_at_resume.unit == 25.4);
      const std::size_t resumed_from = link.printer().executed_commands().size();
      printer::GcodeState before;  // the printer's state as the second host finds it
      before.rules = sim::gcode_rules(dialect);
      const sim::Printer::Position at = link.printer().position();
      before.x = at.x;
      before.y = at.y;
      before.z = at.z;
      before.e = at.e;
      before.unit = reset ? 1 : 25.4;
      LineProtocol protocol(link);
      protocol.connect();
      Job job(protocol, file, resume_from(journal));
      CHECK(job.run().state == JobState::completed);
      CHECK(protocol.refused().empty());
      link.printer().finish();
      const std::vector<std::string>& executed = link.printer().executed_commands();
      const auto recovery = executed.begin() + static_cast<std::ptrdiff_t>(resumed_from);
      const bool set_z = std::find_if(recovery, executed.end(), [](const std::string& c) {
                           return c.starts_with("G92 Z");
                         }) != executed.end();
      CHECK(set_z == reset);
      const double top = clean.deposition.moves.back().z;
      const printer::AxisPosition far = farthest_reached(executed, resumed_from, before);
      CHECK(far.z <= top + 10 + 1e-3);  // the end G-code's lift
      CHECK(far.x <= 125 + 1e-3);
      CHECK(far.y <= 125 + 1e-3);
      const auto& moves = link.printer().deposition().moves;
      CHECK(moves.back().z == doctest::Approx(top));
      for (const sim::DepositedMove& m : moves) CHECK(m.z <= top + 1e-9);
    }
  }
}

TEST_CASE("pause_at_layer_n_pauses_before_the_files_layer_n_minus_1") {
  // Users count layers from 1 (the progress line's "layer n/N", --pause-at-layer); the file's
  // ;LAYER:n comments count from 0.
  const GcodeFile file = parse_gcode(test_support::ring_program(5, 10), "ring.gcode");
  REQUIRE(file.layers[2].number == 2);
  JobOptions options;
  options.pause_at_layers = {3};
  std::vector<std::string> events;
  std::optional<JobProgress> at_pause;
  sim::SimLink link{sim::Config{}};
  LineProtocol protocol(link);
  protocol.connect();
  Job job(protocol, file, options);
  job.on_event = [&](const std::string& e) { events.push_back(e); };
  job.on_tick = [&](Job& j) {
    if (j.progress().state != JobState::paused) return;
    if (!at_pause) at_pause = j.progress();
    j.request(JobRequest::resume);
  };
  CHECK(job.run().pauses == 1);
  REQUIRE(at_pause);
  CHECK(at_pause->layer == 3);
  CHECK(at_pause->layers == 5);
  CHECK(at_pause->commands_done == file.layers[2].first_command);
  REQUIRE(!events.empty());
  CHECK(events.front().starts_with("pausing before layer 3/5:"));
}

TEST_CASE("a_link_lost_while_recovering_keeps_the_journals_resume_point") {
  // `mahost resume` whose link dies again while it heats and homes, before the interrupted
  // layer restarts: the journal must still say where that layer starts and what the printer
  // held there, so that the next resume can finish the part.
  const std::string dir = test_support::scratch_dir("lost_while_recovering");
  const GcodeFile file = parse_gcode(test_support::ring_program(30, 60), "ring.gcode");
  const std::size_t start = file.layers[10].first_command;
  PrintState at;
  for (std::size_t i = 0; i < start; ++i) apply(at, file.command(i));
  REQUIRE(at.z > 1.9);
  REQUIRE(at.hotend_target == 210);

  sim::Config config;
  config.faults = sim::parse_fault_spec("disconnect-at-line=6");  // M110, M115, M105, M140, ...
  sim::SimLink link(config);
  LineProtocol protocol(link);
  protocol.connect();
  JobOptions resume;
  resume.journal_path = dir + "/job.journal";
  resume.first_command = start;
  resume.recover_from = at;
  Job job(protocol, file, resume);
  CHECK_THROWS_AS(job.run(), LinkError);

  const JournalRecord journal = read_journal(resume.journal_path);
  CHECK(journal.state == printer::JobState::failed);
  CHECK(journal.layer_index == 10);
  CHECK(journal.resume_command == start);
  CHECK(journal.state_at_resume.x == at.x);
  CHECK(journal.state_at_resume.z == at.z);
  CHECK(journal.state_at_resume.e == at.e);
  CHECK(journal.state_at_resume.hotend_target == at.hotend_target);
  CHECK(journal.state_at_resume.bed_target == at.bed_target);
}

namespace {

// A ring whose first layer is printed hotter, as slicers do: 250/105 °C, then 245/100 °C from
// the second layer on.
std::string hotter_first_layer_program(int layers) {
  std::string g = test_support::ring_program(layers, 40);
  const std::string heat = "M140 S60\nM104 S210\nM190 S60\nM109 S210\n";
  g.replace(g.find(heat), heat.size(), "M140 S105\nM104 S250\nM190 S105\nM109 S250\n");
  g.replace(g.find(";LAYER:1\n"), 9, ";LAYER:1\nM104 S245\nM140 S100\n");
  return g;
}

}  // namespace

TEST_CASE("status_while_paused_shows_the_targets_the_file_set_last_and_a_fresh_report") {
  const GcodeFile file = parse_gcode(hotter_first_layer_program(6), "ring.gcode");
  JobOptions options;
  options.pause_at_layers = {4};
  std::optional<JobProgress> after_5s;
  int ticks = 0;
  sim::SimLink link{sim::Config{}};
  LineProtocol protocol(link);
  protocol.connect();
  Job job(protocol, file, options);
  job.on_tick = [&](Job& j) {
    if (j.progress().state != JobState::paused) return;
    if (++ticks == 50) {  // 5 s of pause on the sim clock
      after_5s = j.progress();
      j.request(JobRequest::resume);
    }
  };
  CHECK(job.run().state == JobState::completed);
  REQUIRE(after_5s);
  REQUIRE(after_5s->temperatures);
  const Temperatures& t = *after_5s->temperatures;
  CHECK(t.hotend_target == 245.0);
  CHECK(t.bed_target == 100.0);
  // The current temperatures come from a report made while paused, not the first layer's
  // last one (250/105 °C): the heaters have cooled to their new targets since.
  REQUIRE(t.hotend);
  REQUIRE(t.bed);
  CHECK(*t.hotend < 249.0);
  CHECK(*t.bed < 104.0);
}

TEST_CASE("a_pause_leaves_the_print_time_as_unpaused_and_the_clock_runs_as_paused_wait_says") {
  const GcodeFile file = parse_gcode(test_support::ring_program(12, 60), "ring.gcode");
  sim::SimLink plain_link{sim::Config{}};
  LineProtocol plain_protocol(plain_link);
  plain_protocol.connect();
  const JobResult plain = Job(plain_protocol, file, {}).run();
  CHECK(plain.pauses == 0);
  CHECK(plain.paused.count() == 0);

  // A dry run's host waits real time while paused and lets the simulated clock run that long:
  // here 300 waits of 10 ms, 3 s, where one tick each (100 ms) would have made 30 s.
  JobOptions options;
  options.pause_at_layers = {6};
  int waits = 0;
  options.paused_wait = [&waits] {
    ++waits;
    return std::chrono::milliseconds(10);
  };
  sim::SimLink link{sim::Config{}};
  LineProtocol protocol(link);
  protocol.connect();
  Job job(protocol, file, options);
  job.on_tick = [&](Job& j) {
    if (j.progress().state == JobState::paused && waits >= 300) j.request(JobRequest::resume);
  };
  const JobResult paused = job.run();
  CHECK(paused.state == JobState::completed);
  CHECK(paused.pauses == 1);
  CHECK(waits >= 300);
  CHECK(waits <= 310);  // the resume takes effect at the next look
  const double stood = std::chrono::duration<double>(paused.paused).count();
  // 3 s of waiting, plus parking, the M105 exchanges and the way back: well under 30 s.
  CHECK(stood >= 3.0);
  CHECK(stood < 10.0);
  // Less the pause, the print took what the unpaused one did, to the few seconds of the
  // moves back to the part (not counted as paused: the printer runs them after the resume).
  const double plain_seconds = std::chrono::duration<double>(plain.elapsed).count();
  const double paused_seconds = std::chrono::duration<double>(paused.elapsed).count() - stood;
  CHECK(paused_seconds >= plain_seconds - 0.5);
  CHECK(paused_seconds < plain_seconds + 5.0);
}

TEST_CASE("a_pause_the_job_is_cancelled_in_counts_as_a_pause") {
  const GcodeFile file = parse_gcode(test_support::ring_program(8, 40), "ring.gcode");
  JobOptions options;
  options.pause_at_layers = {3};
  int paused_ticks = 0;
  const Printed cancelled = print(file, sim::Config{}, options, {}, [&](Job& job) {
    if (job.progress().state == JobState::paused && ++paused_ticks == 20) {
      job.request(JobRequest::cancel);
    }
  });
  CHECK(cancelled.result.state == JobState::cancelled);
  CHECK(cancelled.result.pauses == 1);
  // It stood paused the 2 s until the cancel (20 ticks of 100 ms), and a little more.
  const double stood = std::chrono::duration<double>(cancelled.result.paused).count();
  CHECK(stood >= 2.0);
  CHECK(stood < 5.0);
}

TEST_CASE("a_resumed_jobs_estimate_is_that_of_the_layers_it_prints") {
  const GcodeFile file = parse_gcode(test_support::ring_program(30, 60), "ring.gcode");
  const std::size_t start = file.layers[20].first_command;
  PrintState at;
  for (std::size_t i = 0; i < start; ++i) apply(at, file.command(i));
  JobOptions resume;
  resume.first_command = start;
  resume.recover_from = at;
  sim::SimLink link{sim::Config{}};
  LineProtocol protocol(link);
  protocol.connect();
  Job job(protocol, file, resume);
  PrintEta eta(file, MotionLimits{});
  eta.finish(0);
  const double whole = *eta.total();
  CHECK(job.run().state == JobState::completed);
  link.printer().finish();
  // The last 10 layers of 30 ring layers of about the same size: about a third of the whole.
  CHECK(job.estimated_seconds() > 0.25 * whole);
  CHECK(job.estimated_seconds() < 0.40 * whole);
  // And like with like: the simulated printer's motion for the resume (the 10 layers, the
  // lift, homing X and Y and the way back) is that estimate and a few seconds.
  const double motion = link.printer().motion_time();
  CHECK(motion >= 0.98 * job.estimated_seconds());
  CHECK(motion < job.estimated_seconds() + 15.0);
}

// ---- cancel and stop on a stalled link, refusals, temperatures ----------------------------

TEST_CASE("cancel_on_a_stalled_link_ends_within_ten_seconds_and_sends_m112") {
  const std::string dir = test_support::scratch_dir("cancel_stalled");
  const GcodeFile file = parse_gcode(test_support::ring_program(20, 40), "ring.gcode");
  test_support::ScriptedFirmware firmware;
  firmware.silent_after = 300;  // the printer stops answering anything, M112 included
  LineProtocol protocol(firmware);
  protocol.connect();
  JobOptions options;
  options.journal_path = dir + "/job.journal";
  Job job(protocol, file, options);
  std::optional<std::chrono::nanoseconds> asked;
  job.on_tick = [&](Job& j) {
    if (!asked && protocol.stats().probes > 0) {  // the printer fell silent: the job probes
      asked = firmware.now();
      j.request(JobRequest::cancel);
    }
  };
  const JobResult result = job.run();
  REQUIRE(asked);
  CHECK(result.state == JobState::cancelled);
  CHECK(firmware.now() - *asked <= std::chrono::seconds(10) + std::chrono::milliseconds(200));
  CHECK(result.reason.starts_with("cancelled at layer "));
  CHECK(result.reason.find("the printer did not confirm the cancel within 10 s: sent M112, which "
                           "turns the heaters off if it reaches the printer: check they are off") !=
        std::string::npos);
  CHECK(firmware.received.back() == "M112");
  CHECK(read_journal(options.journal_path).state == JobState::cancelled);
}

TEST_CASE("cancel_on_a_frozen_link_ends_within_ten_seconds_in_every_dialect") {
  // The simulated printer of each dialect stops reading and answering at line 400 (fault
  // freeze-at-line), the port left open; the job is cancelled as soon as it probes.
  for (const sim::Dialect dialect : {sim::Dialect::marlin, sim::Dialect::teacup, sim::Dialect::repetier}) {
    CAPTURE(sim::to_string(dialect));
    const std::string dir = test_support::scratch_dir(fmt::format("cancel_frozen_{}", sim::to_string(dialect)));
    std::string text = test_support::ring_program(20, 40);
    if (dialect == sim::Dialect::teacup) text.replace(text.find("M190 S60\nM109 S210\n"), 19, "M116\n");
    const GcodeFile file = parse_gcode(text, "ring.gcode");
    sim::Config config;
    config.dialect = dialect;
    config.faults = sim::parse_fault_spec("freeze-at-line=400");
    sim::SimLink link(config);
    LineProtocol protocol(link);
    protocol.connect();
    JobOptions options;
    options.journal_path = dir + "/job.journal";
    Job job(protocol, file, options);
    std::optional<std::chrono::nanoseconds> asked;
    job.on_tick = [&](Job& j) {
      if (!asked && protocol.stats().probes > 0 && link.printer().counters().lines >= 400) {
        asked = link.now();
        j.request(JobRequest::cancel);
      }
    };
    const JobResult result = job.run();
    REQUIRE(asked);
    CHECK(result.state == JobState::cancelled);
    CHECK(link.now() - *asked <= std::chrono::seconds(10) + std::chrono::milliseconds(200));
    CHECK(result.reason.find("the printer did not confirm the cancel within 10 s") != std::string::npos);
    CHECK(read_journal(options.journal_path).state == JobState::cancelled);
    CHECK(link.printer().counters().lines == 400);  // nothing was read after the freeze
  }
}

namespace {

// A ring printed on the simulated Teacup until the firmware refuses a line: the refusal's
// message and what the printer was left with.
struct TeacupRefusal {
  std::string message;
  bool extruded = false;
  double hotend_target = 0;
  JobState state = JobState::printing;
};

TeacupRefusal print_on_teacup(const std::string& text) {
  const GcodeFile file = parse_gcode(text, "ring.gcode");
  sim::Config config;
  config.dialect = sim::Dialect::teacup;
  sim::SimLink link(config);
  LineProtocol protocol(link);
  protocol.connect();
  Job job(protocol, file, {});
  TeacupRefusal refusal;
  try {
    job.run();
  } catch (const CommandRefused& e) {
    refusal.message = e.what();
  }
  refusal.extruded = !link.printer().deposition().moves.empty();
  refusal.hotend_target = link.printer().hotend_target();
  refusal.state = job.result().state;
  return refusal;
}

}  // namespace

TEST_CASE("a_refused_m109_stops_the_job_before_anything_is_extruded") {
  // Only the nozzle is waited for (no M190): Teacup refuses M109 as it refuses M190.
  std::string text = test_support::ring_program(10, 40);
  text.erase(text.find("M190 S60\n"), 9);
  const TeacupRefusal r = print_on_teacup(text);
  CHECK(r.message.starts_with("simulated printer: the printer refused M109 S210 (\"E: Bad M-code 109\"), so the "
                              "print stopped before anything was extruded"));
  CHECK_FALSE(r.extruded);
  CHECK(r.hotend_target == 0);
  CHECK(r.state == JobState::failed);
}

TEST_CASE("a_refusal_mid_print_says_at_which_layer_the_print_stopped") {
  // A temperature change the firmware refuses inside the file (Teacup has no M109): the part is
  // half printed, and the message says so rather than "before anything was extruded".
  std::string text = test_support::ring_program(10, 40);
  text.erase(text.find("M190 S60\nM109 S210\n"), 19);
  text.insert(text.find(";LAYER:5\n"), "M109 S215\n");
  text.replace(text.find("M107\n"), 5, "M106 S0\n");
  const TeacupRefusal r = print_on_teacup(text);
  // Teacup answers a line as it reads it: its refusal of the last line of layer 5 comes once
  // the job has begun layer 6.
  CHECK(r.message.starts_with("simulated printer: the printer refused M109 S215 (\"E: Bad M-code 109\"), so the "
                              "print stopped at layer 6/10, the part printed so far left on the bed: "));
  CHECK(r.extruded);
  CHECK(r.hotend_target == 0);
  CHECK(r.state == JobState::failed);
}

TEST_CASE("cancel_right_after_a_lost_ok_ends_at_once_with_the_heaters_off") {
  const GcodeFile file = parse_gcode(test_support::ring_program(20, 60), "ring.gcode");
  sim::Config config;
  config.faults = sim::parse_fault_spec("drop-ok=0.05,seed=3");
  sim::SimLink link(config);
  LineProtocol protocol(link);
  protocol.connect();
  Job job(protocol, file, {});
  std::optional<std::chrono::nanoseconds> asked;
  job.on_tick = [&](Job& j) {
    // The first moment the host waits for a lost ok on layer 5 or later.
    if (!asked && j.progress().layer >= 5 && protocol.lines_in_flight() > 0 &&
        link.printer().idle()) {
      asked = link.now();
      j.request(JobRequest::cancel);
    }
  };
  const JobResult result = job.run();
  REQUIRE(asked);
  CHECK(result.state == JobState::cancelled);
  CHECK(link.now() - *asked < std::chrono::seconds(10));
  CHECK(link.printer().state() == sim::PrinterState::running);  // ended without M112
  CHECK(link.printer().hotend_target() == 0);
  CHECK(link.printer().bed_target() == 0);
  // Motors off last; a probe for a lost ok of the cancel's own lines may follow.
  const auto& executed = link.printer().executed_commands();
  CHECK(std::find(executed.end() - std::min<std::ptrdiff_t>(3, executed.size()), executed.end(), "M84") !=
        executed.end());
}

TEST_CASE("cancel_during_the_heat_up_breaks_the_wait_at_once") {
  const GcodeFile file = parse_gcode(test_support::ring_program(5, 40), "ring.gcode");
  sim::SimLink link{sim::Config{}};
  LineProtocol protocol(link);
  protocol.connect();
  Job job(protocol, file, {});
  std::optional<std::chrono::nanoseconds> asked;
  job.on_tick = [&](Job& j) {
    if (!asked && link.now() > std::chrono::seconds(20)) {  // the bed heats for ~75 s
      asked = link.now();
      j.request(JobRequest::cancel);
    }
  };
  const JobResult result = job.run();
  REQUIRE(asked);
  CHECK(result.state == JobState::cancelled);
  CHECK(link.now() - *asked < std::chrono::seconds(2));
  CHECK(link.printer().bed_target() == 0);
  CHECK(link.printer().deposition().moves.empty());
}

TEST_CASE("a_refused_m190_stops_the_job_before_anything_is_extruded") {
  const std::string dir = test_support::scratch_dir("refused_m190");
  // G-code written for Marlin (M190/M109), sent to a Teacup firmware.
  const GcodeFile file = parse_gcode(test_support::ring_program(10, 40), "ring.gcode");
  sim::Config config;
  config.dialect = sim::Dialect::teacup;
  sim::SimLink link(config);
  LineProtocol protocol(link);
  protocol.connect();
  JobOptions options;
  options.journal_path = dir + "/job.journal";
  Job job(protocol, file, options);
  std::string message;
  try {
    job.run();
  } catch (const CommandRefused& e) {
    message = e.what();
  }
  CHECK(message ==
        "simulated printer: the printer refused M190 S60 (\"E: Bad M-code 190\"), so the print "
        "stopped before anything was extruded: Teacup has no M190: it waits for temperatures with "
        "M116; set firmware = \"teacup\" in the printer profile (or --set firmware=teacup) and "
        "slice again, so the G-code heats with M104/M140 and waits with M116");
  CHECK(link.printer().deposition().moves.empty());
  CHECK(link.printer().hotend_target() == 0);  // M104 S210 had been sent: turned off again
  CHECK(link.printer().bed_target() == 0);
  CHECK(job.result().state == JobState::failed);
  CHECK(read_journal(options.journal_path).state == JobState::failed);
}

TEST_CASE("temperatures_on_the_progress_line_follow_the_printer_while_printing") {
  // The nozzle target rises to 240 C at layer 5: the progress line must see it climb, from
  // auto-reports (Marlin's M155) or from M105s between layers and every few seconds (Teacup).
  std::string program = test_support::ring_program(30, 120);
  program.insert(program.find(";LAYER:5\n"), "M104 S240\n");
  for (const sim::Dialect dialect : {sim::Dialect::marlin, sim::Dialect::teacup}) {
    CAPTURE(sim::to_string(dialect));
    std::string text = program;
    if (dialect == sim::Dialect::teacup) {  // the heat-up as Teacup takes it
      text.replace(text.find("M190 S60\nM109 S210\n"), 19, "M116\n");
    }
    const GcodeFile file = parse_gcode(text, "ring.gcode");
    sim::Config config;
    config.dialect = dialect;
    sim::SimLink link(config);
    LineProtocol protocol(link);
    protocol.connect();
    Job job(protocol, file, {});
    double worst = 0;
    int checked = 0;
    job.on_tick = [&](Job& j) {
      const JobProgress p = j.progress();
      if (p.layer < 6 || !p.temperatures || !p.temperatures->hotend) return;
      worst = std::max(worst, std::abs(*p.temperatures->hotend - link.printer().hotend_temperature()));
      ++checked;
    };
    REQUIRE(job.run().state == JobState::completed);
    CHECK(checked > 100);
    // Heating at up to 4 C/s, a report at most 5 s old is within 20 C; a stale one from the
    // first layer's heat-up would be 30 C off.
    CHECK(worst < 20);
    CHECK(job.progress().temperatures->hotend.value() > 235);
    MESSAGE(sim::to_string(dialect) << ": the progress line's hotend at most " << worst
                                    << " C from the printer's over " << checked << " ticks");
  }
}

// ---- every way a job stops turns the heaters off -----------------------------------------

namespace {

struct Stopped {
  JobState state = JobState::printing;
  std::string message;  // what run() threw, or the result's reason
  std::vector<std::string> executed;
  double hotend_target = -1, bed_target = -1;
  std::size_t deposited = 0;
  std::string read;  // every byte the host read
  long probes = 0;   // the host's probes for lost oks (there are none to lose)
};

// A job over the simulated printer whose replies are cut at byte `cut` (test_support::SplitLink).
Stopped run_cut(const GcodeFile& file, const sim::Config& config, std::size_t cut,
                const std::function<void(Job&)>& on_tick = {}) {
  sim::SimLink sim(config);
  test_support::SplitLink link(sim, cut);
  LineProtocol protocol(link);
  protocol.connect();
  Job job(protocol, file, {});
  job.on_tick = on_tick;
  Stopped stopped;
  try {
    const JobResult result = job.run();
    stopped.state = result.state;
    stopped.message = result.reason;
  } catch (const std::exception& e) {
    stopped.state = job.result().state;
    stopped.message = e.what();
  }
  sim.printer().run_until(sim.printer().now() + 60);
  stopped.executed = sim.printer().executed_commands();
  stopped.hotend_target = sim.printer().hotend_target();
  stopped.bed_target = sim.printer().bed_target();
  stopped.deposited = sim.printer().deposition().moves.size();
  stopped.read = link.log();
  stopped.probes = protocol.stats().probes;
  return stopped;
}

std::size_t count_of(const std::vector<std::string>& executed, std::string_view command) {
  return static_cast<std::size_t>(std::count(executed.begin(), executed.end(), command));
}

}  // namespace

TEST_CASE("a_refusal_cut_across_reads_at_every_byte_ends_with_the_heaters_off") {
  // Each firmware refusing a command the print needs, in its own words: Marlin has no M116
  // (an echo line, then ok), Teacup no M190 ("E: Bad M-code 190", then ok), Repetier no M191
  // (its ok first, then "Unknown command:"). Wherever the reply is cut, the ok in it is handled,
  // the refused command is not sent again, and M104 S0 and M140 S0 follow.
  struct Refusal {
    sim::Dialect dialect;
    std::string refused, reply;
  };
  for (const Refusal& r : {Refusal{sim::Dialect::marlin, "M116", "echo:Unknown command: \"M116\""},
                           Refusal{sim::Dialect::teacup, "M190 S60", "E: Bad M-code 190"},
                           Refusal{sim::Dialect::repetier, "M191 S40", "Unknown command:N"}}) {
    CAPTURE(r.refused);
    std::string program = test_support::ring_program(3, 10);
    program.insert(program.find("M190 S60\n"), r.refused + "\n");
    const GcodeFile file = parse_gcode(program, "ring.gcode");
    sim::Config config;
    config.dialect = r.dialect;
    const Stopped whole = run_cut(file, config, std::string::npos);
    REQUIRE(whole.message.find("the printer refused " + r.refused) != std::string::npos);
    const std::size_t at = whole.read.find(r.reply);
    REQUIRE(at != std::string::npos);
    const std::size_t ok = whole.read.find("ok", at > 8 ? at - 8 : 0);
    const std::size_t from = std::min(at, ok) - 1, to = std::max(at + r.reply.size(), ok + 3) + 1;
    for (std::size_t cut = from; cut <= to; ++cut) {
      CAPTURE(cut);
      const Stopped s = run_cut(file, config, cut);
      CHECK(s.state == JobState::failed);
      CHECK(s.message.find("the printer refused " + r.refused) != std::string::npos);
      CHECK(s.message.find("M112") == std::string::npos);  // the heaters went off, confirmed
      CHECK(count_of(s.executed, r.refused) == 1);
      CHECK(count_of(s.executed, "M104 S0") == 1);
      CHECK(count_of(s.executed, "M140 S0") == 1);
      CHECK(s.hotend_target == 0);
      CHECK(s.bed_target == 0);
      CHECK(s.deposited == 0);
      CHECK(s.probes == 0);  // the ok was in hand: nothing to wait for
    }
  }
}

TEST_CASE("a_cancel_cut_across_reads_at_every_byte_ends_with_the_heaters_off_and_runs_nothing_twice") {
  const GcodeFile file = parse_gcode(test_support::ring_program(4, 12), "ring.gcode");
  std::vector<std::string> commands;
  for (std::size_t i = 0; i < file.size(); ++i) commands.emplace_back(file.command(i));
  for (const sim::Dialect dialect : {sim::Dialect::marlin, sim::Dialect::teacup, sim::Dialect::repetier}) {
    CAPTURE(sim::to_string(dialect));
    std::string program = test_support::ring_program(4, 12);
    if (dialect == sim::Dialect::teacup) program.replace(program.find("M190 S60\nM109 S210\n"), 19, "M116\n");
    const GcodeFile file = parse_gcode(program, "ring.gcode");
    sim::Config config;
    config.dialect = dialect;
    const auto cancel_at_layer_3 = [](Job& j) {
      if (j.progress().layer == 3) j.request(JobRequest::cancel);
    };
    const Stopped whole = run_cut(file, config, std::string::npos, cancel_at_layer_3);
    REQUIRE(whole.state == JobState::cancelled);
    // Cut every byte of the replies to the cancel's lines (after the last move's ok).
    const std::size_t from = whole.read.size() - 120;
    for (std::size_t cut = from; cut < whole.read.size(); ++cut) {
      CAPTURE(cut);
      const Stopped s = run_cut(file, config, cut, cancel_at_layer_3);
      CHECK(s.state == JobState::cancelled);
      CHECK(s.message.find("M112") == std::string::npos);
      CHECK(s.hotend_target == 0);
      CHECK(s.bed_target == 0);
      // The file's commands ran once each, in order, up to where the cancel came.
      std::size_t matched = 0;
      for (const std::string& c : job_part(s.executed)) {
        if (matched < file.size() && c == file.command(matched)) ++matched;
      }
      CHECK(count_of(s.executed, "M104 S0") == 1);
      CHECK(matched > 0);
      CHECK(s.probes == whole.probes);  // no ok in hand left to look lost
    }
  }
}

TEST_CASE("a_link_that_only_asks_again_ends_the_job_with_m112") {
  // Every numbered line refused from line 20 on (fault resend=1): the job gives up on the
  // link, and M104 S0 and M140 S0 are refused too; M112 turns the heaters off.
  const GcodeFile file = parse_gcode(test_support::ring_program(4, 12), "ring.gcode");
  sim::Config config;
  config.faults = sim::parse_fault_spec("resend=1,from-line=20");
  const Stopped s = run_cut(file, config, std::string::npos);
  CHECK(s.state == JobState::failed);
  CHECK(s.message.find("asked for line") != std::string::npos);
  CHECK(s.message.find("; the printer did not confirm the heaters off: sent M112") != std::string::npos);
  CHECK(s.executed.back() == "M112");
  CHECK(s.hotend_target == 0);
  CHECK(s.bed_target == 0);
}

// ---- a file streamed from disk a block at a time ------------------------------------------

namespace {

// `text` written to a scratch file and read back as a job reads it, in blocks of `block`
// commands (64 here, so that a small program spans many blocks).
struct OnDisk {
  std::string path;
  GcodeFile file;
};
OnDisk on_disk(const std::string& test, const std::string& text, std::size_t block = 64) {
  OnDisk d;
  d.path = test_support::scratch_dir(test) + "/ring.gcode";
  std::ofstream(d.path, std::ios::binary) << text;
  d.file = read_gcode_file(d.path, {}, block);
  return d;
}

}  // namespace

TEST_CASE("a_file_streamed_a_block_at_a_time_prints_what_the_file_held_whole_prints_through_faults") {
  const std::string text = test_support::ring_program(12, 60);
  const GcodeFile held = parse_gcode(text, "ring.gcode");
  const OnDisk streamed = on_disk("job_streamed", text);
  REQUIRE(streamed.file.blocks().size() > 10);
  sim::Config noisy;
  noisy.faults = sim::parse_fault_spec("corrupt=0.01,drop-ok=0.02,resend=0.01,dup-ok=0.005,seed=5");
  // Held in memory while it prints: the block being sent and the model's two, never more.
  std::size_t most_held = 0;
  const Printed faulty = print(streamed.file, noisy, {}, {}, [&](Job& job) {
    most_held = std::max(most_held, job.commands_held());
  });
  CHECK(job_part(faulty.executed) == commands_of(held));
  CHECK(faulty.stats.resend_requests > 5);
  CHECK(faulty.stats.probes > 5);
  CHECK(most_held > 0);
  CHECK(most_held <= 3 * 64);
  // Resends across a block boundary: the job read on into the next block while the line the
  // printer asked again for was in the block before (the protocol keeps the lines in flight).
  CHECK(same_moves(faulty.deposition, print(held, sim::Config{}).deposition));
}

TEST_CASE("a_streamed_resume_starts_mid_block_as_the_file_held_whole_resumes") {
  const std::string text = test_support::ring_program(12, 60);
  const GcodeFile held = parse_gcode(text, "ring.gcode");
  const OnDisk streamed = on_disk("job_streamed_resume", text);
  const std::size_t start = held.layers[7].first_command;
  REQUIRE(start % 64 != 0);  // inside a block
  PrintState at;
  for (std::size_t i = 0; i < start; ++i) apply(at, held.command(i));
  JobOptions resume;
  resume.first_command = start;
  resume.recover_from = at;
  double held_estimate = 0, streamed_estimate = 0;
  const auto resumed = [&](const GcodeFile& file, double& estimate) {
    sim::SimLink link{sim::Config{}};
    LineProtocol protocol(link);
    protocol.connect();
    Job job(protocol, file, resume);
    REQUIRE(job.run().state == JobState::completed);
    estimate = job.estimated_seconds();
    return link.printer().executed_commands();
  };
  const std::vector<std::string> from_held = resumed(held, held_estimate);
  const std::vector<std::string> from_disk = resumed(streamed.file, streamed_estimate);
  CHECK(from_disk == from_held);
  const std::vector<std::string> file = commands_of(held);
  const std::vector<std::string> tail(file.begin() + static_cast<std::ptrdiff_t>(start), file.end());
  const std::vector<std::string> printed = job_part(from_disk);
  REQUIRE(printed.size() > tail.size());
  CHECK(std::vector<std::string>(printed.end() - static_cast<std::ptrdiff_t>(tail.size()), printed.end()) == tail);
  CHECK(streamed_estimate == held_estimate);
  CHECK(streamed_estimate > 0);
}

TEST_CASE("a_file_changed_on_disk_under_its_job_stops_it_before_the_changed_block_heaters_off") {
  const std::string text = test_support::ring_program(12, 60);
  const GcodeFile held = parse_gcode(text, "ring.gcode");
  const OnDisk streamed = on_disk("job_streamed_changed", text);
  // Rewritten in place (an editor saving over it) while layer 3 prints: layer 9's first
  // extrusion pushes 5 mm more.
  std::string changed = text;
  const std::size_t layer9 = changed.find(";LAYER:9\n");
  const std::size_t e = changed.find("G1 E1.00000", layer9);
  REQUIRE(e != std::string::npos);
  changed.replace(e, 11, "G1 E6.00000");
  bool rewritten = false;
  sim::SimLink link{sim::Config{}};
  LineProtocol protocol(link);
  protocol.connect();
  Job job(protocol, streamed.file, {});
  job.on_tick = [&](Job& j) {
    if (rewritten || j.progress().layer < 4) return;
    std::ofstream(streamed.path, std::ios::binary | std::ios::in | std::ios::out) << changed;
    rewritten = true;
  };
  std::string message;
  try {
    job.run();
  } catch (const GcodeFileChanged& e) {
    message = e.what();
  }
  REQUIRE(rewritten);
  CHECK(message.starts_with(streamed.path + ": the file changed on disk while it printed (commands "));
  CHECK(message.find('\n') == std::string::npos);
  CHECK(job.result().state == JobState::failed);
  // What ran is the file as checked, up to a block before layer 9, then the heaters off.
  const std::vector<std::string> printed = job_part(link.printer().executed_commands());
  const std::vector<std::string> file = commands_of(held);
  REQUIRE(printed.size() >= 2);
  const std::vector<std::string> ran(printed.begin(), printed.end() - 2);
  CHECK(std::vector<std::string>(printed.end() - 2, printed.end()) ==
        std::vector<std::string>{"M104 S0", "M140 S0"});
  std::size_t changed_command = held.layers[9].first_command;
  while (held.command(changed_command) != "G1 E1.00000 F1800") ++changed_command;
  CHECK(ran.size() <= changed_command);
  CHECK(ran.size() % 64 == 0);  // up to the changed block's start
  CHECK(ran.size() > held.layers[4].first_command);
  CHECK(ran == std::vector<std::string>(file.begin(), file.begin() + static_cast<std::ptrdiff_t>(ran.size())));
}

TEST_CASE("the_models_time_read_a_block_at_a_time_is_the_whole_files_command_by_command") {
  const std::string text = test_support::ring_program(12, 60);
  const GcodeFile held = parse_gcode(text, "ring.gcode");
  const OnDisk streamed = on_disk("eta_streamed", text);
  MotionLimits limits;
  PrintEta whole(held, limits), blocks(streamed.file, limits);
  whole.finish(0);
  // A step too small for the whole file: still estimating after it, with no time left given.
  blocks.work(0, 100);
  CHECK_FALSE(blocks.total());
  CHECK_FALSE(blocks.remaining(0, 0, 0));
  bool same = true;
  for (std::size_t i = 0; i <= held.size(); ++i) {
    blocks.command_done(i, 0);
    blocks.work(i);
    same = same && blocks.at(i) && *blocks.at(i) == *whole.at(i);
  }
  CHECK(same);
  CHECK(blocks.total() == whole.total());
  CHECK(blocks.commands_held() <= 2 * 64);
}

}  // namespace job_test
