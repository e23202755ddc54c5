// Jobs against the simulated printer (sim::SimLink): what the printer executed and deposited,
// with faults, pauses, cancels and stops (DESIGN.md §4).
#include "printer/job.h"

#include <filesystem>

#include <doctest/doctest.h>

#include "printer/error.h"
#include "printer/gcode_line.h"
#include "printer/test_program.h"
#include "sim/faults.h"
#include "sim/sim_link.h"
#include "support/run_command.h"

using namespace printer;

namespace {

// What the printer executed of the job: without the host's own M110, M115 and M105 queries.
std::vector<std::string> job_part(const std::vector<std::string>& executed) {
  std::vector<std::string> out;
  for (const std::string& c : executed) {
    const GcodeCommand parsed = parse_gcode_line(c);
    if (parsed.is('M', 110) || parsed.is('M', 115) || parsed.is('M', 105)) continue;
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
