// mahost serve against OctoPrint's documented requests and replies (docs.octoprint.org, REST
// API: version, files, job, printer; the examples' requests sent as written, the replies
// checked field by field), as PrusaSlicer's and Cura's OctoPrint clients read them.
#include <doctest/doctest.h>

#include "serve_fixture.h"

using namespace serve_test;

namespace {

const std::string kWhistle = "M109 T0 S220.000000\nT0\nG21\nG90\n";

// OctoPrint's file upload example, as the docs write it (to "local": there is no SD card).
std::string docs_upload_body(const std::string& boundary) {
  return "--" + boundary + "\r\n"
         "Content-Disposition: form-data; name=\"file\"; filename=\"whistle_v2.gcode\"\r\n"
         "Content-Type: application/octet-stream\r\n\r\n"
         + kWhistle + "\r\n"
         "--" + boundary + "\r\n"
         "Content-Disposition: form-data; name=\"select\"\r\n\r\n"
         "true\r\n"
         "--" + boundary + "\r\n"
         "Content-Disposition: form-data; name=\"print\"\r\n\r\n"
         "true\r\n"
         "--" + boundary + "--\r\n";
}

}  // namespace

TEST_CASE("version_answers_with_the_octoprint_text_the_slicers_check") {
  ServeDirs dirs("serve_version");
  Serve serve(dirs, {"--time-scale", "max"});
  const json v = serve.get_json("/api/version");
  CHECK(v["api"] == "0.1");                                      // PrusaSlicer requires "api"
  CHECK(v["text"].get<std::string>().rfind("OctoPrint", 0) == 0);  // and a text starting so
  CHECK(v["server"].is_string());                                // Cura reads "server"
  CHECK(v["mahost"].is_string());
  CHECK(serve.get_json("/api/server")["version"].is_string());
  const json user = serve.post_json("/api/login", {{"passive", true}}) == 200
                        ? serve.get_json("/api/currentuser")
                        : json();
  CHECK(user["name"] == "_api");
  const json settings = serve.get_json("/api/settings");
  CHECK(settings["feature"]["sdSupport"] == false);
  CHECK(settings["webcam"]["streamUrl"] == "");
  const json profiles = serve.get_json("/api/printerprofiles");
  CHECK(profiles["profiles"]["_default"]["current"] == true);
  CHECK(profiles["profiles"]["_default"]["volume"]["width"].get<double>() > 0);
  CHECK(serve.get_json("/api/connection")["current"]["state"] == "Operational");
  CHECK(serve.stop() == 0);
}

TEST_CASE("an_idle_printer_answers_job_printer_and_files_as_octoprint_documents") {
  ServeDirs dirs("serve_idle");
  Serve serve(dirs, {"--time-scale", "max"});
  // GET /api/job with nothing selected: the fields there, null.
  const json job = serve.get_json("/api/job");
  CHECK(job["state"] == "Operational");
  for (const char* key : {"name", "origin", "size", "date"}) CHECK(job["job"]["file"][key].is_null());
  CHECK(job["job"]["estimatedPrintTime"].is_null());
  for (const char* key : {"completion", "filepos", "printTime", "printTimeLeft"}) CHECK(job["progress"][key].is_null());

  // GET /api/printer: temperature (tool0, bed: actual, target, offset), sd, state and its flags.
  const json printer = serve.get_json("/api/printer");
  for (const char* heater : {"tool0", "bed"}) {
    CHECK(printer["temperature"][heater]["actual"].is_number());
    CHECK(printer["temperature"][heater].contains("target"));
    CHECK(printer["temperature"][heater]["offset"] == 0);
  }
  CHECK(printer["sd"]["ready"] == false);
  CHECK(printer["state"]["text"] == "Operational");
  const json flags = printer["state"]["flags"];
  CHECK(flags["operational"] == true);
  CHECK(flags["ready"] == true);
  for (const char* flag : {"paused", "printing", "cancelling", "pausing", "sdReady", "error", "closedOrError"}) {
    CHECK(flags[flag] == false);
  }
  // Example 2: GET /api/printer?exclude=temperature,sd has the state only.
  const json state_only = serve.get_json("/api/printer?exclude=temperature,sd");
  CHECK(state_only.size() == 1);
  CHECK(state_only.contains("state"));
  // Example 1: history=true&limit=2: at most two points, newest first, each with a time.
  REQUIRE(wait_for([&] { return serve.get_json("/api/printer?history=true&limit=2")["temperature"]["history"].size() == 2; }, 30s));
  const json history = serve.get_json("/api/printer?history=true&limit=2")["temperature"]["history"];
  CHECK(history[0]["time"].get<long>() >= history[1]["time"].get<long>());
  CHECK(history[0]["tool0"]["actual"].is_number());
  CHECK(serve.get_json("/api/printer/tool")["tool0"]["actual"].is_number());
  CHECK(serve.get_json("/api/printer/bed")["bed"]["actual"].is_number());

  // GET /api/files: an empty list and the free space.
  const json files = serve.get_json("/api/files");
  CHECK(files["files"].empty());
  CHECK(files["free"].get<std::uint64_t>() > 0);
  CHECK(serve.get_json("/api/files/local")["files"].empty());
  auto c = serve.client();
  CHECK(c.Get("/api/files/sdcard")->status == 404);  // no SD card

  // POST /api/job without a job: 409 for each command, 400 for an unknown one.
  CHECK(serve.post_json("/api/job", {{"command", "start"}}) == 409);  // nothing selected
  CHECK(serve.post_json("/api/job", {{"command", "cancel"}}) == 409);
  CHECK(serve.post_json("/api/job", {{"command", "pause"}, {"action", "pause"}}) == 409);
  CHECK(serve.post_json("/api/job", {{"command", "restart"}}) == 409);
  CHECK(serve.post_json("/api/job", {{"command", "explode"}}) == 400);
  CHECK(serve.post_json("/api/job", {{"command", "pause"}, {"action", "sideways"}}) == 400);
  CHECK(serve.stop() == 0);
}

TEST_CASE("the_docs_upload_example_stores_selects_and_prints_the_file") {
  ServeDirs dirs("serve_docs_upload");
  Serve serve(dirs, {"--time-scale", "max"});
  const std::string boundary = "----WebKitFormBoundaryDeC2E3iWbTv1PwMC";
  const std::string body = docs_upload_body(boundary);
  RawConnection raw(serve.port);
  REQUIRE(raw.send("POST /api/files/local HTTP/1.1\r\nHost: example.com\r\nX-Api-Key: " + std::string(kKey) +
                   "\r\nContent-Type: multipart/form-data; boundary=" + boundary +
                   "\r\nContent-Length: " + std::to_string(body.size()) + "\r\nConnection: close\r\n\r\n" + body));
  const std::string response = raw.receive(30s);
  INFO(response);
  CHECK(status_of(response) == 201);
  CHECK(response.find("Location: http://example.com/api/files/local/whistle_v2.gcode\r\n") != std::string::npos);
  const json reply = json::parse(response.substr(response.find("\r\n\r\n") + 4));
  const json local = reply["files"]["local"];
  CHECK(local["name"] == "whistle_v2.gcode");
  CHECK(local["path"] == "whistle_v2.gcode");
  CHECK(local["origin"] == "local");
  CHECK(local["refs"]["resource"] == "http://example.com/api/files/local/whistle_v2.gcode");
  CHECK(local["refs"]["download"] == "http://example.com/downloads/files/local/whistle_v2.gcode");
  CHECK(reply["done"] == true);
  CHECK(reply["effectiveSelect"] == true);
  CHECK(reply["effectivePrint"] == true);
  CHECK(read_text(dirs.files + "/whistle_v2.gcode") == kWhistle);

  // The job follows it to the end: Operational again, completion 100, the file still selected.
  REQUIRE(wait_for([&] {
    const json job = serve.get_json("/api/job");
    return job["state"] == "Operational" && job["mahost"]["jobState"] == "completed";
  }, 120s));
  const json job = serve.get_json("/api/job");
  CHECK(job["job"]["file"]["name"] == "whistle_v2.gcode");
  CHECK(job["job"]["file"]["origin"] == "local");
  CHECK(job["job"]["file"]["size"] == kWhistle.size());
  CHECK(job["progress"]["completion"] == 100.0);
  CHECK(job["progress"]["filepos"] == kWhistle.size());
  CHECK(job["progress"]["printTimeLeft"] == 0);
  // It heated the hotend to 220 (M109 waits until there): the printer says so.
  const json printer = serve.get_json("/api/printer");
  CHECK(printer["temperature"]["tool0"]["target"] == 220.0);
  CHECK(printer["temperature"]["tool0"]["actual"].get<double>() > 215);

  // GET /api/files/local/whistle_v2.gcode and the listing: the file with its analysis.
  const json info = serve.get_json("/api/files/local/whistle_v2.gcode");
  CHECK(info["name"] == "whistle_v2.gcode");
  CHECK(info["type"] == "machinecode");
  CHECK(info["typePath"] == json::array({"machinecode", "gcode"}));
  CHECK(info["size"] == kWhistle.size());
  CHECK(info["gcodeAnalysis"]["estimatedPrintTime"].is_number());
  CHECK(serve.get_json("/api/files")["files"].size() == 1);
  auto c = serve.client();
  auto download = c.Get("/downloads/files/local/whistle_v2.gcode");
  REQUIRE(download);
  CHECK(download->status == 200);
  CHECK(download->body == kWhistle);

  // DELETE /api/files/local/whistle_v2.gcode: 204, then 404.
  CHECK(c.Delete("/api/files/local/whistle_v2.gcode")->status == 204);
  CHECK(c.Delete("/api/files/local/whistle_v2.gcode")->status == 404);
  CHECK(c.Get("/api/files/local/whistle_v2.gcode")->status == 404);
  CHECK_FALSE(fs::exists(dirs.files + "/whistle_v2.gcode"));
  CHECK(serve.stop() == 0);
}

TEST_CASE("select_and_start_as_in_the_docs_and_a_second_start_conflicts") {
  ServeDirs dirs("serve_select_start");
  Serve serve(dirs, {"--time-scale", "20"});
  auto r = serve.upload("ring.gcode", ring_gcode(6));
  REQUIRE(r);
  CHECK(r->status == 201);
  CHECK(json::parse(r->body)["effectiveSelect"] == false);  // not asked for
  // POST /api/files/local/ring.gcode {"command": "select"}: 204, the job names the file.
  CHECK(serve.post_json("/api/files/local/ring.gcode", {{"command", "select"}}) == 204);
  CHECK(serve.get_json("/api/job")["job"]["file"]["name"] == "ring.gcode");
  CHECK(serve.post_json("/api/files/local/nothing.gcode", {{"command", "select"}}) == 404);
  CHECK(serve.post_json("/api/files/local/ring.gcode", {{"command", "frobnicate"}}) == 400);
  // {"command": "start"}: 204; again while it runs: 409, as a select is.
  CHECK(serve.post_json("/api/job", {{"command", "start"}}) == 204);
  CHECK(serve.post_json("/api/job", {{"command", "start"}}) == 409);
  CHECK(serve.post_json("/api/files/local/ring.gcode", {{"command", "select"}}) == 409);
  auto c = serve.client();
  CHECK(c.Delete("/api/files/local/ring.gcode")->status == 409);  // being printed
  CHECK(serve.upload("ring.gcode", ring_gcode(2))->status == 409);  // nor replaced
  REQUIRE(serve.wait_state("Printing", 60s));
  // {"command": "cancel"}: 204, and the printer is Operational again, the job cancelled.
  CHECK(serve.post_json("/api/job", {{"command", "cancel"}}) == 204);
  REQUIRE(wait_for([&] { return serve.get_json("/api/job")["mahost"]["jobState"] == "cancelled"; }, 60s));
  CHECK(serve.state() == "Operational");
  CHECK(serve.post_json("/api/job", {{"command", "cancel"}}) == 409);
  CHECK(serve.stop() == 0);
}
