// mahost serve against OctoPrint's documented requests and replies (docs.octoprint.org, REST
// API: version, files, job, printer; the examples' requests sent as written, the replies
// checked field by field), as PrusaSlicer's and Cura's OctoPrint clients read them.
#include <doctest/doctest.h>

#include "geometry/mesh/stl_io.h"
#include "serve_fixture.h"
#include "support/solids.h"

namespace octoprint_api_test {

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

// A T, one closed mesh: a 10 x 10 x 20 mm stem under a 10 x 50 x 5 mm bar whose wings overhang
// 20 mm on each side: standing as given it needs support under both wings; resting on its bar
// or on a T-shaped end it needs none.
std::string tee_stl(const std::string& dir) {
  const std::string path = dir + "/tee.stl";
  geometry::write_stl_binary(path, solids::lying_prism({{-5, 0}, {5, 0}, {5, 20}, {25, 20}, {25, 25},
                                                        {-25, 25}, {-25, 20}, {-5, 20}},
                                                       -5, 5).mesh);
  return read_text(path);
}

// POST /api/files/local/<model> {"command": "slice", ...}: the status, and once the slice is
// done the G-code it wrote ("" when refused or failed; the failure in the INFO).
struct Sliced {
  int status = 0;
  std::string error;  // the refusal's "error"
  std::string gcode;
};

Sliced slice_command(const Serve& serve, const ServeDirs& dirs, const std::string& model, json body) {
  body["command"] = "slice";
  auto c = serve.client();
  auto r = c.Post("/api/files/local/" + model, body.dump(), "application/json");
  REQUIRE(r);
  Sliced out;
  out.status = r->status;
  if (r->status != 202) {
    const json reply = json::parse(r->body, nullptr, false);
    if (reply.is_object() && reply.contains("error")) out.error = reply["error"].get<std::string>();
    return out;
  }
  const std::string gcode = json::parse(r->body)["name"].get<std::string>();
  REQUIRE(wait_for([&] {
    const json s = serve.get_json("/api/mahost/status")["slicing"];
    return !s.is_null() && s["gcode"] == gcode && (s["stage"] == "done" || s["stage"] == "failed");
  }, 120s));
  const json s = serve.get_json("/api/mahost/status")["slicing"];
  INFO(s.dump());
  REQUIRE(s["stage"] == "done");
  out.gcode = read_text(dirs.files + "/" + gcode);
  return out;
}

bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

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

// The slice command of the docs ("Issue a file command", slice: gcode, printerProfile, profile.*
// overrides, select, print), with mahost's fields for supports, brim, raft, adaptive layers and
// the orientation; each left out is the printer profile's (the UP Plus 2: support everywhere,
// on a raft, no brim, 0.3 mm layers).
TEST_CASE("the_slice_command_carries_supports_brim_raft_adaptive_layers_and_orientation") {
  ServeDirs dirs("serve_slice_fields");
  Serve serve(dirs, {"--time-scale", "max"});
  REQUIRE(serve.upload("tee.stl", tee_stl(dirs.root))->status == 201);

  // The profile's own: support under the wings, on a raft, no brim.
  const Sliced plain = slice_command(serve, dirs, "tee.stl", {{"gcode", "plain.gcode"}});
  CHECK(has(plain.gcode, ";TYPE:SUPPORT"));
  CHECK(has(plain.gcode, ";TYPE:RAFT"));
  CHECK_FALSE(has(plain.gcode, ";TYPE:BRIM"));

  // No support, a 5 mm brim, no raft: none of either, the brim there.
  const Sliced bare = slice_command(serve, dirs, "tee.stl",
                                    {{"gcode", "bare.gcode"}, {"support", "none"}, {"brim", 5}, {"raft", false}});
  CHECK(bare.status == 202);
  CHECK_FALSE(has(bare.gcode, ";TYPE:SUPPORT"));
  CHECK_FALSE(has(bare.gcode, ";TYPE:RAFT"));
  CHECK(has(bare.gcode, ";TYPE:BRIM"));
  CHECK(has(bare.gcode, "\n; brim: 5 mm\n"));

  // OctoPrint's names: the slicer, slicing profile and position it sends are taken as given
  // (there is one slicer, and the part is centred), printerProfile "_default" is the server's
  // printer, and profile.<field> is mahost's field (form values are strings).
  const Sliced octo = slice_command(serve, dirs, "tee.stl",
                                    {{"slicer", "cura"}, {"gcode", "octo.gcode"}, {"printerProfile", "_default"},
                                     {"profile", "high_quality"}, {"profile.support", "buildplate"},
                                     {"profile.raft", "false"}, {"profile.brim", "2.5"},
                                     {"position", {{"x", 100}, {"y", 100}}}});
  CHECK(octo.status == 202);
  CHECK(has(octo.gcode, ";TYPE:SUPPORT"));  // the wings' columns stand on the bed
  CHECK(has(octo.gcode, "\n; support: buildplate, "));
  CHECK(has(octo.gcode, "\n; brim: 2.5 mm\n"));
  CHECK_FALSE(has(octo.gcode, ";TYPE:RAFT"));

  // Adaptive layers within 0.25 mm: the plan's header line says so.
  const Sliced adaptive = slice_command(serve, dirs, "tee.stl",
                                        {{"gcode", "adaptive.gcode"}, {"adaptive", true}, {"tolerance", 0.25},
                                         {"support", "none"}, {"raft", false}});
  CHECK(adaptive.status == 202);
  CHECK(has(adaptive.gcode, "(adaptive, D within 0.25 mm)"));
  // At most 80 layers: 25 mm needs 63 at the thickest (0.3 mm first, then 0.4 mm).
  const Sliced budget = slice_command(serve, dirs, "tee.stl",
                                      {{"gcode", "budget.gcode"}, {"maxLayers", 80}, {"raft", false}});
  CHECK(budget.status == 202);
  const int layers = serve.get_json("/api/files/local/budget.gcode")["mahost"]["layers"];
  CHECK(layers <= 80);
  CHECK(layers >= 1 + static_cast<int>(std::ceil((25 - 0.3) / 0.4 - 1e-9)));

  // Turned for least support: the T rests on its bar or on an end, and needs none, though
  // support is asked for everywhere.
  const Sliced turned = slice_command(serve, dirs, "tee.stl",
                                      {{"gcode", "turned.gcode"}, {"orient", "auto"}, {"support", "everywhere"}});
  CHECK(turned.status == 202);
  CHECK_FALSE(has(turned.gcode, ";TYPE:SUPPORT"));
  CHECK(has(turned.gcode, "\n; support: everywhere, "));
  CHECK(serve.stop() == 0);
}

// Values out of range, unknown names and contradictions: 400 with OctoPrint's {"error": ...},
// one line naming the field, for the slice command and for an upload's form fields alike (the
// upload then stores nothing); the server serves on.
TEST_CASE("bad_slice_fields_are_refused_in_one_line_naming_the_field") {
  ServeDirs dirs("serve_slice_refusals");
  Serve serve(dirs, {"--time-scale", "max"});
  const std::string tee = tee_stl(dirs.root);
  REQUIRE(serve.upload("tee.stl", tee)->status == 201);
  const std::vector<std::pair<json, std::string>> refused{
      {{{"brim", -1}}, "brim"},
      {{{"brim", "wide"}}, "brim"},
      {{{"brim", 51}}, "brim"},
      {{{"tolerance", 0}}, "tolerance"},
      {{{"tolerance", -0.2}}, "tolerance"},
      {{{"support", "sometimes"}}, "support"},
      {{{"support", 3}}, "support"},
      {{{"tolerance", 0.3}, {"maxLayers", 100}}, "not two"},
      {{{"maxLayers", 100}, {"maxTime", "1h"}}, "not two"},
      {{{"maxLayers", 2.5}}, "maxLayers"},
      {{{"maxLayers", 0}}, "maxLayers"},
      {{{"maxTime", "90"}}, "maxTime"},
      {{{"raft", "maybe"}}, "raft"},
      {{{"adaptive", "perhaps"}}, "adaptive"},
      {{{"orient", "upside-down"}}, "orient"},
      {{{"adaptive", true}, {"layer", 0.3}}, "layer and adaptive"},
      {{{"profile.fill_density", 15}}, "profile.fill_density"},
      {{{"profile.brim", 5}, {"brim", 3}}, "disagree"},
  };
  for (const auto& [body, named] : refused) {
    const Sliced s = slice_command(serve, dirs, "tee.stl", body);
    INFO(body.dump() << " -> " << s.status << " " << s.error);
    CHECK(s.status == 400);
    CHECK(has(s.error, named));
    CHECK_FALSE(has(s.error, "\n"));
  }
  // The same as an upload's form fields: 400, and the model is not stored.
  for (const std::vector<std::pair<std::string, std::string>>& fields :
       {std::vector<std::pair<std::string, std::string>>{{"slice", "true"}, {"brim", "-1"}},
        {{"slice", "true"}, {"adaptive", "true"}, {"tolerance", "0.3"}, {"maxLayers", "50"}},
        {{"select", "true"}, {"support", "sometimes"}}}) {
    auto r = serve.upload("other.stl", tee, fields);
    REQUIRE(r);
    INFO(r->body);
    CHECK(r->status == 400);
    const json reply = json::parse(r->body);
    CHECK(reply["error"].is_string());
    CHECK_FALSE(has(reply["error"].get<std::string>(), "\n"));
    auto c = serve.client();
    CHECK(c.Get("/api/files/local/other.stl")->status == 404);
  }
  // Nothing was sliced, and the server still answers.
  CHECK(serve.get_json("/api/mahost/status")["slicing"].is_null());
  CHECK(serve.get_json("/api/version")["api"] == "0.1");
  CHECK(serve.stop() == 0);
}

}  // namespace octoprint_api_test
