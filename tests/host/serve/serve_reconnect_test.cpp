// A printer unplugged and plugged back: mahost serve notices the link is gone, says so once
// (not once per try), tries again every 5 s, finds the printer again when it is back, and offers
// the job the unplugging interrupted. The printer is `mahost sim` on a pseudo-terminal, reached
// through a link that stands for the stable name udev gives a USB printer
// (/dev/serial/by-id/...): a printer plugged back gets a new terminal, as a board plugged
// back may come back as another /dev/ttyUSBn.
#include <doctest/doctest.h>

#include "serve_fixture.h"

namespace serve_reconnect_test {

using namespace serve_test;

namespace {

// Points `link` at `target`, replacing what it pointed at in one step.
void point(const std::string& link, const std::string& target) {
  const std::string next = link + ".next";
  fs::remove(next);
  fs::create_symlink(target, next);
  fs::rename(next, link);
}

std::size_t count(const std::string& text, const std::string& part) {
  std::size_t n = 0;
  for (std::size_t at = text.find(part); at != std::string::npos; at = text.find(part, at + 1)) ++n;
  return n;
}

}  // namespace

TEST_CASE("a_printer_unplugged_mid_print_and_plugged_back_is_found_again_and_its_job_offered") {
  ServeDirs dirs("serve_replug");
  const std::string link = dirs.root + "/printer";
  auto printer = std::make_unique<SimPrinter>(std::vector<std::string>{"--time-scale", "20"}, dirs.root + "/sim.log");
  REQUIRE(printer->port.rfind("/dev/pts/", 0) == 0);
  point(link, printer->port);
  Serve serve(dirs, {"--port", link});
  REQUIRE(serve.state() == "Operational");
  REQUIRE(serve.upload("ring.gcode", ring_gcode(30), {{"print", "true"}})->status == 201);
  REQUIRE(wait_for([&] { return serve.get_json("/api/job")["mahost"].value("layer", 0) >= 2; }, 120s));

  // Unplugged: the job fails with the link and its part is kept for a resume. udev takes the
  // stable name away with the device (and the terminal's number may soon be another's).
  printer->unplug();
  fs::remove(link);
  REQUIRE(wait_for([&] { return serve.get_json("/api/job")["mahost"]["jobState"] == "failed"; }, 60s));
  CHECK(serve.state().rfind("Offline", 0) == 0);
  CHECK(serve.client().Delete("/api/files/local/ring.gcode")->status == 409);
  // Tried again while the printer is away (the first try meets the link's failure, the next
  // ones the port missing): each try fails alike, and says so once.
  REQUIRE(wait_for([&] { return serve.get_json("/api/mahost/status")["connection"]["retries"].get<int>() >= 3; }, 60s));
  const std::string away = serve.get_json("/api/mahost/status")["connection"]["error"];
  CHECK(away.find(link + ": no such serial port") != std::string::npos);

  // Plugged back, on another terminal behind the same stable name: found again.
  printer = std::make_unique<SimPrinter>(std::vector<std::string>{"--time-scale", "max"}, dirs.root + "/sim.log");
  point(link, printer->port);
  REQUIRE(wait_for([&] {
    const json s = serve.get_json("/api/mahost/status");
    return s["state"] == "Operational" && !s["interrupted"].is_null();
  }, 60s));
  const json status = serve.get_json("/api/mahost/status");
  CHECK(status["connection"]["retries"] == 0);
  CHECK(status["interrupted"]["state"] == "failed");
  // One line for the failed tries, however many there were.
  const std::string log = serve.log();
  CHECK(count(log, "no such serial port") == 1);
  // The job is finished on the printer plugged back.
  CHECK(serve.post_json("/api/mahost/interrupted", {{"command", "resume"}}) == 204);
  REQUIRE(wait_for([&] { return serve.get_json("/api/job")["mahost"]["jobState"] == "completed"; }, 120s));
  CHECK(serve.stop() == 0);
}

}  // namespace serve_reconnect_test
