// SimLink (sim/sim_link.h): a printer::Link whose time is the simulator's, so host timeouts
// are deterministic and instant.
#include <doctest/doctest.h>

#include <chrono>
#include <string>

#include "printer/error.h"
#include "sim/faults.h"
#include "sim/sim_link.h"

namespace sim_link_test {

using namespace std::chrono_literals;

TEST_CASE("simlink_says_start_on_power_on") {
  sim::SimLink link;
  CHECK(link.name() == "simulated printer");
  CHECK(link.read(1000ms).starts_with("start\n"));
  CHECK(link.now() == 0ns);
}

TEST_CASE("read_runs_the_sim_clock_exactly_to_the_timeout_or_the_reply") {
  sim::SimLink link;
  link.read(10ms);
  const auto start = link.now();
  CHECK(link.read(250ms).empty());
  CHECK(link.now() - start == 250ms);
  link.write("G4 S30\n");
  CHECK(link.read(10s) == "echo:busy: processing\n");
  CHECK(link.now() - start == 2250ms);
  std::string said;
  for (int i = 0; i < 20 && said.find("ok") == std::string::npos; ++i) said += link.read(60s);
  CHECK(said.ends_with("ok\n"));
  CHECK(link.now() - start == 30250ms);
}

TEST_CASE("disconnect_fault_throws_link_error_until_reconnect") {
  sim::Config config;
  config.faults = sim::parse_fault_spec("disconnect-at-line=2");
  sim::SimLink link(config);
  link.read(10ms);
  link.write("M105\n");
  CHECK(link.read(1s).starts_with("ok T:"));
  link.write("M105\n");
  CHECK_THROWS_WITH_AS(link.read(1s),
                       "simulated printer: the link is gone: disconnected at line 2 (fault "
                       "disconnect-at-line); reconnect the printer",
                       printer::LinkError);
  CHECK_THROWS_AS(link.write("M105\n"), printer::LinkError);
  link.reconnect();
  CHECK(link.read(1s).starts_with("start\n"));
}

TEST_CASE("same_seed_same_bytes_at_the_same_sim_times") {
  const auto run = [] {
    sim::Config config;
    config.faults = sim::parse_fault_spec("drop-ok=0.2,dup-ok=0.2,delay=20ms,seed=9");
    sim::SimLink link(config);
    std::string log;
    for (int i = 0; i < 100; ++i) {
      link.write("G92 X" + std::to_string(i) + "\n");
      log += link.read(100ms) + "@" + std::to_string(link.now().count()) + "\n";
    }
    return log;
  };
  CHECK(run() == run());
}

}  // namespace sim_link_test
