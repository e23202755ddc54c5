// Printing through mahost serve: an upload with print=true runs on the simulated printer and
// GET /api/job follows it to the end; pause and resume through the API lay the same part as
// an unpaused print; twenty pollers and a client dropping mid-upload change nothing the
// printer receives; a job interrupted by a crash is offered and finished; G-code lines go to
// an idle printer, and mid-job only the tunes (temperatures, fan, speed, flow, babystep).
#include <algorithm>
#include <atomic>
#include <set>

#include <doctest/doctest.h>

#include "serve_fixture.h"

namespace serve_print_test {

using namespace serve_test;

namespace {

// The deposition record's moves: what the printer laid, in order.
struct Move {
  int layer;
  double z, x0, y0, x1, y1, e;
  bool operator==(const Move&) const = default;
};

std::vector<Move> moves_of(const json& record) {
  std::vector<Move> out;
  for (const json& m : record["moves"]) {
    out.push_back({m["layer"], m["z"], m["x0"], m["y0"], m["x1"], m["y1"], m["e"]});
  }
  return out;
}

json print_and_record(const std::string& name, const std::string& gcode, const std::vector<std::string>& args,
                      const std::function<void(Serve&)>& during = {}) {
  ServeDirs dirs(name);
  Serve serve(dirs, args);
  auto r = serve.upload("part.gcode", gcode, {{"print", "true"}});
  REQUIRE(r);
  REQUIRE(r->status == 201);
  REQUIRE(json::parse(r->body)["effectivePrint"] == true);
  if (during) during(serve);
  REQUIRE(wait_for([&] { return serve.get_json("/api/job")["mahost"]["jobState"] == "completed"; }, 180s));
  CHECK(serve.stop() == 0);
  return json::parse(read_text(dirs.record));
}

}  // namespace

TEST_CASE("an_upload_with_print_true_prints_and_get_job_follows_it_to_completion") {
  ServeDirs dirs("serve_follow");
  Serve serve(dirs, {"--time-scale", "40"});
  const std::string gcode = ring_gcode(12);
  auto r = serve.upload("ring.gcode", gcode, {{"print", "true"}});
  REQUIRE(r);
  CHECK(r->status == 201);
  const json upload = json::parse(r->body);
  CHECK(upload["effectivePrint"] == true);
  CHECK(upload["done"] == true);

  // Followed to the end: the layer, completion and file position never go back, and the
  // states are the documented ones.
  std::set<std::string> states;
  int last_layer = 0;
  double last_completion = -1;
  std::uint64_t last_filepos = 0;
  bool monotone = true;
  REQUIRE(wait_for([&] {
    const json job = serve.get_json("/api/job");
    states.insert(job["state"].get<std::string>());
    if (job["progress"]["completion"].is_number()) {
      const double completion = job["progress"]["completion"];
      const std::uint64_t filepos = job["progress"]["filepos"];
      const int layer = job["mahost"]["layer"];
      monotone = monotone && completion >= last_completion && filepos >= last_filepos && layer >= last_layer;
      last_completion = completion;
      last_filepos = filepos;
      last_layer = layer;
    }
    return job["mahost"]["jobState"] == "completed";
  }, 180s));
  CHECK(monotone);
  CHECK(states.count("Printing") == 1);
  for (const std::string& s : states) CHECK((s == "Printing" || s == "Operational"));
  const json job = serve.get_json("/api/job");
  CHECK(job["state"] == "Operational");
  CHECK(job["progress"]["completion"] == 100.0);
  CHECK(job["progress"]["filepos"] == gcode.size());
  CHECK(job["mahost"]["layer"] == 12);
  CHECK(job["mahost"]["layers"] == 12);
  CHECK(job["mahost"]["commandsDone"] == job["mahost"]["commandsTotal"]);
  CHECK(job["progress"]["printTime"].get<long>() > 12 * 3);  // the sim's clock: ~4 s a layer
  // The page's drawing of the last layer: all of it done.
  const json layer = serve.get_json("/api/mahost/layer?layer=12");
  CHECK(layer["todo"] == "");
  CHECK(layer["done"].get<std::string>().rfind("M", 0) == 0);
  CHECK(layer["moves"] == 61);  // the travel to the ring, 60 segments
  // Completed: the journal is gone, nothing left to resume.
  CHECK(wait_for([&] { return fs::is_empty(dirs.runtime + "/mahost"); }, 30s));
  CHECK(serve.stop() == 0);
  // Exactly the file's commands reached the printer, once each, in order.
  CHECK(printed_commands(json::parse(read_text(dirs.record))) == file_commands(gcode));
}

TEST_CASE("pause_and_resume_through_the_api_deposit_the_same_part_as_an_unpaused_print") {
  const std::string gcode = ring_gcode(10);
  const json plain = print_and_record("serve_unpaused", gcode, {"--time-scale", "max"});
  int paused_layer = 0;
  const json paused = print_and_record("serve_paused", gcode, {"--time-scale", "20"}, [&](Serve& serve) {
    REQUIRE(wait_for([&] { return serve.get_json("/api/job")["mahost"].value("layer", 0) >= 3; }, 120s));
    CHECK(serve.post_json("/api/job", {{"command", "pause"}, {"action", "pause"}}) == 204);
    CHECK(serve.post_json("/api/job", {{"command", "pause"}, {"action", "pause"}}) == 204);  // no-op
    REQUIRE(serve.wait_state("Paused", 120s));
    paused_layer = serve.get_json("/api/job")["mahost"]["layer"];
    CHECK(serve.get_json("/api/printer")["state"]["flags"]["paused"] == true);
    // Paused means paused: the layer holds while the page and the slicers look.
    std::this_thread::sleep_for(500ms);
    CHECK(serve.get_json("/api/job")["mahost"]["layer"] == paused_layer);
    CHECK(serve.post_json("/api/job", {{"command", "pause"}, {"action", "resume"}}) == 204);
    REQUIRE(serve.wait_state("Printing", 60s));
    // Toggle pauses and resumes too.
    CHECK(serve.post_json("/api/job", {{"command", "pause"}}) == 204);
    REQUIRE(serve.wait_state("Paused", 120s));
    CHECK(serve.post_json("/api/job", {{"command", "pause"}, {"action", "toggle"}}) == 204);
    REQUIRE(serve.wait_state("Printing", 60s));
  });
  CHECK(paused_layer >= 4);
  // The pause parked the nozzle (more commands ran), yet the printer laid the same moves.
  CHECK(paused["commands"].size() > plain["commands"].size());
  const std::vector<Move> a = moves_of(plain), b = moves_of(paused);
  CHECK(a.size() > 500);
  CHECK(a == b);
}

TEST_CASE("twenty_pollers_and_a_client_dropping_mid_upload_lose_and_duplicate_no_printer_command") {
  ServeDirs dirs("serve_pollers");
  Serve serve(dirs, {"--time-scale", "40"});
  const std::string gcode = ring_gcode(30);
  auto r = serve.upload("ring.gcode", gcode, {{"print", "true"}});
  REQUIRE(r);
  REQUIRE(r->status == 201);
  REQUIRE(serve.wait_state("Printing", 60s));

  std::atomic<bool> done{false};
  std::atomic<int> failed{0};
  std::vector<std::atomic<int>> answered(20);
  std::vector<std::thread> pollers;
  for (int i = 0; i < 20; ++i) {
    pollers.emplace_back([&, i] {
      auto c = serve.client();
      do {
        auto reply = c.Get(i % 2 ? "/api/job" : "/api/printer");
        if (reply && reply->status == 200) ++answered[static_cast<std::size_t>(i)]; else ++failed;
        std::this_thread::sleep_for(100ms);  // 10 Hz
      } while (!done.load());
    });
  }
  // Mid-print, a client sends half an upload and vanishes.
  std::this_thread::sleep_for(500ms);
  {
    RawConnection raw(serve.port);
    const std::string boundary = "cut-short";
    const std::string part = "--" + boundary + "\r\nContent-Disposition: form-data; name=\"file\"; filename=\"half.gcode\"\r\n\r\n" +
                             ring_gcode(5);
    REQUIRE(raw.send("POST /api/files/local HTTP/1.1\r\nHost: x\r\nX-Api-Key: " + std::string(kKey) +
                     "\r\nContent-Type: multipart/form-data; boundary=" + boundary +
                     "\r\nContent-Length: " + std::to_string(part.size() * 2) + "\r\n\r\n" + part.substr(0, part.size() / 2)));
    std::this_thread::sleep_for(200ms);
    raw.drop();
  }
  REQUIRE(wait_for([&] { return serve.get_json("/api/job")["mahost"]["jobState"] == "completed"; }, 180s));
  done.store(true);
  for (std::thread& t : pollers) t.join();
  CHECK(failed.load() == 0);
  // Every poller was answered, however fast this machine polls.
  CHECK(std::all_of(answered.begin(), answered.end(), [](const std::atomic<int>& n) { return n.load() > 0; }));
  // Nothing of the dropped upload was kept.
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(dirs.files)) names.push_back(entry.path().filename().string());
  CHECK(names == std::vector<std::string>{"ring.gcode"});
  CHECK(serve.stop() == 0);
  CHECK(printed_commands(json::parse(read_text(dirs.record))) == file_commands(gcode));
}

TEST_CASE("a_job_interrupted_by_a_crash_is_offered_at_the_next_start_and_finished") {
  ServeDirs dirs("serve_crash");
  const std::string gcode = ring_gcode(12);
  {
    Serve serve(dirs, {"--time-scale", "20"});
    REQUIRE(serve.upload("ring.gcode", gcode, {{"print", "true"}})->status == 201);
    REQUIRE(wait_for([&] { return serve.get_json("/api/job")["mahost"].value("layer", 0) >= 4; }, 120s));
    serve.kill_now();  // the host dies mid-print; its journal stays
  }
  Serve serve(dirs, {"--time-scale", "max"});
  json status;
  REQUIRE(wait_for([&] {
    status = serve.get_json("/api/mahost/status");
    return !status["interrupted"].is_null();
  }, 30s));
  CHECK(status["interrupted"]["file"] == fs::canonical(dirs.files).string() + "/ring.gcode");
  CHECK(status["interrupted"]["layer"].get<int>() >= 4);
  CHECK(status["interrupted"]["layers"] == 12);
  CHECK(status["interrupted"]["state"] == "printing");
  CHECK(serve.post_json("/api/mahost/interrupted", {{"command", "resume"}}) == 204);
  REQUIRE(wait_for([&] { return serve.get_json("/api/job")["mahost"]["jobState"] == "completed"; }, 120s));
  CHECK(serve.get_json("/api/mahost/status")["interrupted"].is_null());
  CHECK(serve.post_json("/api/mahost/interrupted", {{"command", "resume"}}) == 409);  // nothing left
  CHECK(wait_for([&] { return fs::is_empty(dirs.runtime + "/mahost"); }, 30s));
  CHECK(serve.stop() == 0);
  // The resumed print reprinted the interrupted layer's commands to the end of the file.
  const std::vector<std::string> printed = printed_commands(json::parse(read_text(dirs.record)));
  const std::vector<std::string> file = file_commands(gcode);
  REQUIRE(printed.size() < file.size());
  CHECK(std::equal(printed.end() - 100, printed.end(), file.end() - 100));
}

TEST_CASE("tunes_sent_mid_print_reach_the_printer_between_the_files_lines_once_each") {
  ServeDirs dirs("serve_tunes");
  Serve serve(dirs, {"--time-scale", "20"});
  const std::string gcode = ring_gcode(16);
  REQUIRE(serve.upload("ring.gcode", gcode, {{"print", "true"}})->status == 201);
  REQUIRE(wait_for([&] { return serve.get_json("/api/job")["mahost"].value("layer", 0) >= 3; }, 120s));
  // As OctoPrint's tune controls and Cura send them: one line, or a list.
  const std::vector<std::string> tunes = {"M104 S205", "M140 S55", "M106 S128", "M220 S120",
                                          "M221 S95", "M290 Z0.05", "M117 Tuned mid-print", "M114"};
  CHECK(serve.post_json("/api/printer/command", {{"command", tunes[0]}}) == 204);
  CHECK(serve.post_json("/api/printer/command", {{"commands", std::vector<std::string>(tunes.begin() + 1, tunes.end())}}) == 204);
  // The tuned target is the job's: /api/printer reports it.
  CHECK(wait_for([&] { return serve.get_json("/api/printer")["temperature"]["tool0"]["target"] == 205.0; }, 60s));
  REQUIRE(wait_for([&] { return serve.get_json("/api/job")["mahost"]["jobState"] == "completed"; }, 180s));
  const json status = serve.get_json("/api/mahost/status?events_after=0");
  int told = 0;
  for (const json& e : status["events"]) told += e["text"].get<std::string>().rfind("tune: ", 0) == 0;
  CHECK(told == static_cast<int>(tunes.size()));
  CHECK(serve.stop() == 0);
  // The printer ran the file's commands once each and in order, and the tunes once each, in
  // the order sent, between two of the file's lines after layer 3 began.
  const std::vector<std::string> printed = printed_commands(json::parse(read_text(dirs.record)));
  const std::vector<std::string> file = file_commands(gcode);
  std::vector<std::string> rest;
  std::size_t next = 0, first_tune = 0;
  for (std::size_t i = 0; i < printed.size(); ++i) {
    if (next < tunes.size() && printed[i] == tunes[next]) {
      if (next++ == 0) first_tune = rest.size();
    } else {
      rest.push_back(printed[i]);
    }
  }
  CHECK(next == tunes.size());
  CHECK(rest == file);
  CHECK(printed.size() == file.size() + tunes.size());
  const printer::GcodeFile parsed = printer::parse_gcode(gcode, "ring.gcode");
  CHECK(first_tune > parsed.layers[2].first_command);
  CHECK(first_tune < file.size());
}

TEST_CASE("gcode_commands_reach_an_idle_printer_and_are_refused_while_a_job_runs") {
  ServeDirs dirs("serve_commands");
  Serve serve(dirs, {"--time-scale", "20"});
  CHECK(serve.post_json("/api/printer/command", {{"commands", {"M104 S200", "M140 S50"}}}) == 204);
  REQUIRE(wait_for([&] {
    const json t = serve.get_json("/api/printer")["temperature"];
    return t["tool0"]["target"] == 200.0 && t["bed"]["target"] == 50.0;
  }, 60s));
  CHECK(serve.post_json("/api/printer/command", {{"command", "M104 S0"}}) == 204);
  // Refused as written: numbered or checksummed lines, M110, user waits, non-text, both fields.
  CHECK(serve.post_json("/api/printer/command", {{"command", "N5 G28*12"}}) == 400);
  CHECK(serve.post_json("/api/printer/command", {{"command", "M110 N0"}}) == 400);
  CHECK(serve.post_json("/api/printer/command", {{"command", "M0"}}) == 400);
  CHECK(serve.post_json("/api/printer/command", {{"command", "G1 X\u0001"}}) == 400);
  CHECK(serve.post_json("/api/printer/command", {{"command", "G28"}, {"commands", {"G28"}}}) == 400);
  CHECK(serve.post_json("/api/printer/command", {{"commands", "G28"}}) == 400);
  CHECK(serve.post_json("/api/printer/command", json::object()) == 400);

  REQUIRE(serve.upload("ring.gcode", ring_gcode(20), {{"print", "true"}})->status == 201);
  REQUIRE(wait_for([&] { return serve.get_json("/api/job")["mahost"]["jobState"] == "printing"; }, 60s));
  // Mid-job, motion and waits are refused with the reason.
  auto c = serve.client();
  auto refused = c.Post("/api/printer/command", json{{"command", "G28"}}.dump(), "application/json");
  REQUIRE(refused);
  CHECK(refused->status == 409);
  CHECK(refused->body.find("G28 is not taken while a job prints") != std::string::npos);
  refused = c.Post("/api/printer/command", json{{"command", "M109 S200"}}.dump(), "application/json");
  REQUIRE(refused);
  CHECK(refused->status == 409);
  CHECK(refused->body.find("set the target with M104") != std::string::npos);
  // One refused line refuses the request: nothing of it is sent.
  CHECK(serve.post_json("/api/printer/command", {{"commands", {"M106 S255", "G1 X10"}}}) == 409);
  // M112 is the one line taken while printing: it stops the printer at once.
  CHECK(serve.post_json("/api/printer/command", {{"command", "M112"}}) == 204);
  REQUIRE(wait_for([&] { return serve.get_json("/api/job")["mahost"]["jobState"] == "stopped"; }, 60s));
  REQUIRE(wait_for([&] { return serve.state().rfind("Offline", 0) == 0; }, 30s));
  CHECK(serve.client().Get("/api/printer")->status == 409);  // not operational
  // A reconnect resets the printer; it takes commands again.
  CHECK(serve.post_json("/api/connection", {{"command", "connect"}}) == 204);
  REQUIRE(serve.wait_state("Operational", 60s));
  CHECK(serve.post_json("/api/printer/command", {{"command", "G28"}}) == 204);
  CHECK(serve.stop() == 0);
}

TEST_CASE("a_link_that_fails_mid_print_is_reopened_and_the_job_is_offered_to_finish") {
  ServeDirs dirs("serve_link_failure");
  Serve serve(dirs, {"--time-scale", "max", "--faults", "disconnect-at-line=400"});
  const std::string gcode = ring_gcode(12);
  REQUIRE(serve.upload("ring.gcode", gcode, {{"print", "true"}})->status == 201);
  // The job fails with the link; its journal stays; serve reopens the link by itself. The
  // failure and the link's loss are one change: the printer is never shown operational with
  // the job's link gone (a resume taken then would be dropped), only once the link is reopened.
  json failed;
  REQUIRE(wait_for([&] {
    failed = serve.get_json("/api/mahost/status?events_after=0");
    return failed["mahost"]["jobState"] == "failed";
  }, 60s));
  int connections = 0;
  for (const json& e : failed["events"]) connections += e["text"].get<std::string>().rfind("connected to ", 0) == 0;
  CHECK((failed["state"] == "Offline after error" || connections == 2));
  CHECK(failed["error"].get<std::string>().find("disconnected at line 400") != std::string::npos);
  // From the moment it failed, before the printer is back, its file is the interrupted job's:
  // not deleted, not replaced.
  CHECK(serve.client().Delete("/api/files/local/ring.gcode")->status == 409);
  CHECK(serve.upload("ring.gcode", ring_gcode(2))->status == 409);
  REQUIRE(wait_for([&] {
    const json s = serve.get_json("/api/mahost/status");
    return s["state"] == "Operational" && !s["interrupted"].is_null();
  }, 60s));
  const json status = serve.get_json("/api/mahost/status");
  CHECK(status["interrupted"]["state"] == "failed");
  CHECK(serve.post_json("/api/mahost/interrupted", {{"command", "resume"}}) == 204);
  REQUIRE(wait_for([&] { return serve.get_json("/api/job")["mahost"]["jobState"] == "completed"; }, 120s));
  CHECK(serve.stop() == 0);
  const std::vector<std::string> printed = printed_commands(json::parse(read_text(dirs.record)));
  const std::vector<std::string> file = file_commands(gcode);
  REQUIRE(printed.size() > file.size());  // the lines before the failure, then the rest again
  CHECK(std::equal(printed.end() - 200, printed.end(), file.end() - 200));
}

}  // namespace serve_print_test
