// The record file of a simulated print (sim/record.h).
#include <doctest/doctest.h>

#include <fstream>

#include <nlohmann/json.hpp>

#include "geometry/mesh/stl_io.h"
#include "printer/error.h"
#include "sim/record.h"
#include "support/run_command.h"

namespace record_test {

TEST_CASE("record_json_holds_the_log_counters_moves_and_beads") {
  sim::Config config;
  config.faults = sim::parse_fault_spec("dup-ok=0.5,seed=2");
  sim::Printer printer(config);
  printer.receive("G92 E0\nG1 Z0.2 F600\nG1 X10 E0.5 F1200\nG1 Y10 E1.0\nM9999 \"x\"\n");
  printer.run_until(10);
  const std::string dir = test_support::scratch_dir("record_json");
  sim::write_record_json(printer, dir + "/r.json");
  std::ifstream in(dir + "/r.json");
  const nlohmann::json r = nlohmann::json::parse(in);
  CHECK(r["commands"] == nlohmann::json::array({"G92 E0", "G1 Z0.2 F600", "G1 X10 E0.5 F1200",
                                                "G1 Y10 E1.0", "M9999 \"x\""}));
  CHECK(r["faults"] == "dup-ok=0.5,seed=2");
  CHECK(r["state"] == "running");
  CHECK(r["counters"]["commands"] == 5);
  CHECK(r["counters"]["unknown_commands"] == 1);
  CHECK(r["counters"]["faults_injected"] == printer.counters().faults_injected);
  REQUIRE(r["moves"].size() == 2);
  CHECK(r["moves"][1]["x0"] == 10);
  CHECK(r["moves"][1]["y1"] == 10);
  CHECK(r["moves"][1]["e"] == 0.5);
  CHECK(r["moves"][1]["f"] == 20);
  REQUIRE(r["layers"].size() == 1);
  CHECK(r["layers"][0]["z"] == 0.2);
  CHECK(r["layers"][0]["beads"].size() == 2);
  CHECK(r["layers"][0]["beads"][0].size() == 4);

  sim::write_printed_stl(printer, dir + "/part.stl");
  CHECK(geometry::read_stl(dir + "/part.stl").size() > 12);
}

TEST_CASE("record_to_an_unwritable_path_names_it") {
  sim::Printer printer;
  CHECK_THROWS_WITH_AS(sim::write_record_json(printer, "/nonexistent-dir/r.json"),
                       "cannot write the record /nonexistent-dir/r.json: No such file or "
                       "directory; check the folder exists and is writable",
                       printer::ConfigError);
}

}  // namespace record_test
