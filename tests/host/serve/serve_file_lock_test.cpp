// What mahost serve never loses: the file a job prints and the file of an interrupted job are
// never replaced or deleted, two uploads of one name never both print, "upload and print"
// while a job runs or an interrupted job waits stores the file and says it did not print it,
// and nothing prints over an interrupted part until it is finished or discarded. The slicers'
// uploads are sent byte for byte as PrusaSlicer and Cura send them (serve_fixture.h).
#include <set>

#include <doctest/doctest.h>
#include <fmt/core.h>

#include "serve_fixture.h"

namespace serve_file_lock_test {

using namespace serve_test;

namespace {

// A ring print that tells which upload it came from: its first command is "M117 <tag>", which
// the simulated printer records as it runs it.
std::string tagged_ring(const std::string& tag, int layers = 4) { return "M117 " + tag + "\n" + ring_gcode(layers); }

int count_of(const std::vector<std::string>& commands, const std::string& command) {
  return static_cast<int>(std::count(commands.begin(), commands.end(), command));
}

json body_of(const RawResponse& r) { return json::parse(r.body, nullptr, false); }

}  // namespace

TEST_CASE("two_uploads_of_one_name_at_once_never_both_print_and_the_printed_one_is_on_disk_50_times") {
  ServeDirs dirs("serve_upload_race");
  Serve serve(dirs, {"--time-scale", "max"});
  std::vector<std::string> printed_tags, refused_tags;
  for (int round = 0; round < 50; ++round) {
    CAPTURE(round);
    // The job pauses before its second layer and waits there: whichever upload comes second
    // meets a running job, however the two are scheduled.
    REQUIRE(serve.post_json("/api/mahost/pause-at", {{"layers", {2}}}) == 204);
    const std::string tags[2] = {fmt::format("race {} a", round), fmt::format("race {} b", round)};
    RawResponse replies[2];
    std::thread second([&] { replies[1] = send_raw(serve.port, prusaslicer_upload("race.gcode", tagged_ring(tags[1]), true)); });
    replies[0] = send_raw(serve.port, prusaslicer_upload("race.gcode", tagged_ring(tags[0]), true));
    second.join();
    int winner = -1;
    for (int i = 0; i < 2; ++i) {
      INFO(replies[i].head << replies[i].body);
      if (replies[i].status == 201) {
        CHECK(body_of(replies[i])["effectivePrint"] == true);
        CHECK(winner == -1);
        winner = i;
      } else {
        CHECK(replies[i].status == 409);
        CHECK(body_of(replies[i])["error"].get<std::string>().find("race.gcode is being printed") != std::string::npos);
      }
    }
    REQUIRE(winner >= 0);
    printed_tags.push_back(tags[winner]);
    refused_tags.push_back(tags[1 - winner]);
    // The file on disk is the one printing.
    CHECK(read_text(dirs.files + "/race.gcode") == tagged_ring(tags[winner]));
    REQUIRE(serve.wait_state("Paused", 60s));
    REQUIRE(serve.post_json("/api/job", {{"command", "cancel"}}) == 204);
    REQUIRE(wait_for([&] { return serve.get_json("/api/job")["mahost"]["jobState"] == "cancelled"; }, 60s));
  }
  CHECK(serve.stop() == 0);
  // The printer ran each round's winner once and never a refused upload.
  const std::vector<std::string> printed = printed_commands(json::parse(read_text(dirs.record)));
  for (const std::string& tag : printed_tags) CHECK(count_of(printed, "M117 " + tag) == 1);
  for (const std::string& tag : refused_tags) CHECK(count_of(printed, "M117 " + tag) == 0);
}

TEST_CASE("after_a_crash_the_slicers_upload_and_print_store_the_file_and_print_nothing_over_the_part") {
  ServeDirs dirs("serve_crash_then_upload");
  const std::string ring = tagged_ring("the interrupted part", 12);
  {
    Serve serve(dirs, {"--time-scale", "20"});
    REQUIRE(serve.upload("ring.gcode", ring, {{"print", "true"}})->status == 201);
    REQUIRE(wait_for([&] { return serve.get_json("/api/job")["mahost"].value("layer", 0) >= 3; }, 120s));
    serve.kill_now();  // the host dies mid-print; the part stays on the bed
  }
  Serve serve(dirs, {"--time-scale", "max"});
  REQUIRE(wait_for([&] { return !serve.get_json("/api/mahost/status")["interrupted"].is_null(); }, 30s));

  // PrusaSlicer sends the part again under its name: the interrupted job's file is not
  // replaced (a resume reprints from it).
  RawResponse r = send_raw(serve.port, prusaslicer_upload("ring.gcode", tagged_ring("a new ring"), true));
  INFO(r.body);
  CHECK(r.status == 409);
  CHECK(body_of(r)["error"].get<std::string>().find("interrupted job") != std::string::npos);
  CHECK(read_text(dirs.files + "/ring.gcode") == ring);
  // Under another name, from PrusaSlicer and from Cura: stored, not printed, and the answer
  // says why in OctoPrint's terms (effectivePrint false) and mahost's.
  for (const auto& [name, request] :
       {std::pair{std::string("prusa.gcode"), prusaslicer_upload("prusa.gcode", tagged_ring("from prusaslicer"), true)},
        std::pair{std::string("cura.gcode"), cura_upload("cura.gcode", tagged_ring("from cura"), true)}}) {
    CAPTURE(name);
    r = send_raw(serve.port, request);
    INFO(r.body);
    REQUIRE(r.status == 201);
    const json reply = body_of(r);
    CHECK(reply["effectivePrint"] == false);
    CHECK(reply["mahost"]["notPrinted"].get<std::string>().find("an interrupted job waits (ring.gcode at layer ") !=
          std::string::npos);
    CHECK(fs::exists(dirs.files + "/" + name));
  }
  // Nor does anything else start a print over the part, and its file is not deleted.
  CHECK(serve.get_json("/api/job")["state"] == "Operational");
  CHECK(serve.post_json("/api/files/local/cura.gcode", {{"command", "select"}, {"print", true}}) == 409);
  CHECK(serve.post_json("/api/job", {{"command", "start"}}) == 409);
  CHECK(serve.client().Delete("/api/files/local/ring.gcode")->status == 409);
  const json status = serve.get_json("/api/mahost/status");
  CHECK(status["job"]["file"]["name"] == "cura.gcode");  // selected, as Cura asked
  CHECK(status["mahost"]["jobState"] == "none");
  const std::string events = status["events"].dump();
  CHECK(events.find("stored cura.gcode; not printed: an interrupted job waits") != std::string::npos);

  // Discarded: the journal and the dead job's control socket go, and prints start again.
  const std::string journal = status["interrupted"]["journal"];
  const std::string socket = fs::path(journal).replace_extension(".sock").string();
  REQUIRE(fs::exists(socket));
  CHECK(serve.post_json("/api/mahost/interrupted", {{"command", "discard"}}) == 204);
  CHECK_FALSE(fs::exists(journal));
  CHECK_FALSE(fs::exists(socket));
  r = send_raw(serve.port, prusaslicer_upload("prusa.gcode", tagged_ring("printed after the discard"), true));
  REQUIRE(r.status == 201);
  CHECK(body_of(r)["effectivePrint"] == true);
  REQUIRE(wait_for([&] { return serve.get_json("/api/job")["mahost"]["jobState"] == "completed"; }, 60s));
  CHECK(serve.stop() == 0);
  const std::vector<std::string> printed = printed_commands(json::parse(read_text(dirs.record)));
  CHECK(count_of(printed, "M117 printed after the discard") == 1);
  for (const char* never : {"M117 a new ring", "M117 from prusaslicer", "M117 from cura"}) {
    CHECK(count_of(printed, never) == 0);
  }
}

TEST_CASE("upload_and_print_while_a_job_runs_stores_the_file_and_says_it_did_not_print") {
  ServeDirs dirs("serve_upload_while_printing");
  Serve serve(dirs, {"--time-scale", "max"});
  REQUIRE(serve.post_json("/api/mahost/pause-at", {{"layers", {2}}}) == 204);
  REQUIRE(serve.upload("first.gcode", tagged_ring("first"), {{"print", "true"}})->status == 201);
  RawResponse r = send_raw(serve.port, cura_upload("second.gcode", tagged_ring("second"), true));
  INFO(r.body);
  REQUIRE(r.status == 201);
  CHECK(body_of(r)["effectivePrint"] == false);
  CHECK(body_of(r)["effectiveSelect"] == false);
  CHECK(body_of(r)["mahost"]["notPrinted"] == "a job is running: select a file once it has ended");
  CHECK(read_text(dirs.files + "/second.gcode") == tagged_ring("second"));
  // The running job's file is neither replaced nor deleted; its job goes on with it.
  r = send_raw(serve.port, cura_upload("first.gcode", tagged_ring("replacement"), false));
  CHECK(r.status == 409);
  CHECK(serve.client().Delete("/api/files/local/first.gcode")->status == 409);
  CHECK(read_text(dirs.files + "/first.gcode") == tagged_ring("first"));
  REQUIRE(serve.wait_state("Paused", 60s));
  CHECK(serve.get_json("/api/job")["job"]["file"]["name"] == "first.gcode");
  REQUIRE(serve.post_json("/api/job", {{"command", "cancel"}}) == 204);
  REQUIRE(wait_for([&] { return serve.get_json("/api/job")["mahost"]["jobState"] == "cancelled"; }, 60s));
  // Once it has ended, the file may go.
  CHECK(serve.client().Delete("/api/files/local/first.gcode")->status == 204);
  CHECK(serve.stop() == 0);
  CHECK(count_of(printed_commands(json::parse(read_text(dirs.record))), "M117 second") == 0);
}

TEST_CASE("an_stl_that_fails_to_slice_for_a_print_says_why_in_the_job_without_the_servers_folder") {
  ServeDirs dirs("serve_broken_stl");
  Serve serve(dirs, {"--time-scale", "max"});
  // One facet: readable as STL, but no solid to slice.
  const std::string facet =
      "solid broken\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 10 0 0\nvertex 0 10 0\nendloop\n"
      "endfacet\nendsolid broken\n";
  auto r = serve.upload("broken.stl", facet, {{"print", "true"}});
  REQUIRE(r);
  REQUIRE(r->status == 201);
  CHECK(json::parse(r->body)["done"] == false);  // slicing in the background
  REQUIRE(wait_for([&] { return serve.get_json("/api/mahost/status")["slicing"]["stage"] == "failed"; }, 120s));
  const json job = serve.get_json("/api/job");
  INFO(job.dump());
  CHECK(job["mahost"]["jobState"] == "failed");
  const std::string error = job["error"];
  CHECK(error.rfind("slicing broken.stl failed: ", 0) == 0);
  const std::string folder = fs::canonical(dirs.files).string();
  CHECK(error.find(folder) == std::string::npos);
  CHECK(serve.get_json("/api/mahost/status")["slicing"]["error"].get<std::string>().find(folder) == std::string::npos);
  CHECK(serve.stop() == 0);
}

}  // namespace serve_file_lock_test
