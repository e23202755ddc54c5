// mahost's own endpoints beside OctoPrint's: an STL upload sliced on the host and printed, the
// live-update stream the page reads, the profiles it offers, the layer drawing, restart.
#include <set>

#include <doctest/doctest.h>
#include <fmt/core.h>

#include "geometry/mesh/stl_io.h"
#include "printer/profile.h"
#include "serve_fixture.h"
#include "support/solids.h"

namespace serve_mahost_api_test {

using namespace serve_test;

TEST_CASE("an_stl_upload_is_sliced_on_the_host_with_the_pages_settings_and_printed") {
  ServeDirs dirs("serve_stl");
  Serve serve(dirs, {"--time-scale", "max"});
  const std::string stl_path = dirs.root + "/cube.stl";
  geometry::write_stl_binary(stl_path, solids::cube(8).mesh);
  const std::string stl = read_text(stl_path);

  // A layer the printer lacks: refused before the file is stored (400), and the answer says why.
  auto r = serve.upload("cube.stl", stl, {{"slice", "true"}, {"layer", "0.1"}});
  REQUIRE(r);
  CHECK(r->status == 400);
  json reply = json::parse(r->body);
  CHECK(reply["error"].get<std::string>().find("layer thickness 0.1 mm is not allowed") != std::string::npos);
  CHECK(serve.client().Get("/api/files/local/cube.stl")->status == 404);

  // The page's settings: sliced in the background (done false), then selected and printed.
  r = serve.upload("cube.stl", stl, {{"slice", "true"}, {"layer", "0.3"}, {"contour", "mid"},
                                     {"printer", "up-plus-2"}, {"material", "pla"}, {"print", "true"}});
  REQUIRE(r);
  CHECK(r->status == 201);
  reply = json::parse(r->body);
  CHECK(reply["done"] == false);
  REQUIRE(wait_for([&] {
    const json s = serve.get_json("/api/mahost/status");
    return !s["slicing"].is_null() && (s["slicing"]["stage"] == "done" || s["slicing"]["stage"] == "failed");
  }, 120s));
  const json slicing = serve.get_json("/api/mahost/status")["slicing"];
  CHECK(slicing["stage"] == "done");
  CHECK(slicing["gcode"] == "cube.gcode");
  CHECK(slicing["summary"].get<std::string>().find(" layers, estimated print time ") != std::string::npos);
  REQUIRE(wait_for([&] { return serve.get_json("/api/job")["mahost"]["jobState"] == "completed"; }, 120s));
  const json job = serve.get_json("/api/job");
  CHECK(job["job"]["file"]["name"] == "cube.gcode");
  CHECK(job["mahost"]["contour"] == "mid");
  const json info = serve.get_json("/api/files/local/cube.gcode");
  // 8 mm at 0.3 mm after the UP Plus 2's 0.3 mm first layer: ceil(8 / 0.3) layers, on the
  // raft the UP Plus 2 prints on by default (base, interface, two surface layers).
  CHECK(info["mahost"]["layers"] == 27 + 4);
  CHECK(read_text(dirs.files + "/cube.gcode").find("; material: PLA") != std::string::npos);

  // The slice command as OctoPrint names it, on the stored model: 202 and the target's file,
  // sliced with slice's default contour (best) where the request names none.
  auto c = serve.client();
  auto s = c.Post("/api/files/local/cube.stl", R"({"command":"slice","gcode":"cube-default.gcode"})", "application/json");
  REQUIRE(s);
  CHECK(s->status == 202);
  CHECK(json::parse(s->body)["name"] == "cube-default.gcode");
  REQUIRE(wait_for([&] { return serve.get_json("/api/mahost/status")["slicing"]["stage"] == "done"; }, 120s));
  CHECK(serve.get_json("/api/files/local/cube-default.gcode")["mahost"]["contour"] == "best");
  // Refused: slicing G-code, a model not there, a printer or material the server lacks.
  CHECK(c.Post("/api/files/local/cube.gcode", R"({"command":"slice"})", "application/json")->status == 415);
  CHECK(c.Post("/api/files/local/none.stl", R"({"command":"slice"})", "application/json")->status == 404);
  CHECK(c.Post("/api/files/local/cube.stl", R"({"command":"slice","printer":"/etc/passwd"})", "application/json")->status == 400);
  CHECK(c.Post("/api/files/local/cube.stl", R"({"command":"slice","material":"unobtainium"})", "application/json")->status == 400);
  CHECK(c.Post("/api/files/local/cube.stl", R"({"command":"slice","contour":"best-guess"})", "application/json")->status == 400);
  CHECK(c.Post("/api/files/local/cube.stl", R"({"command":"slice","gcode":"../x.gcode"})", "application/json")->status == 400);
  CHECK(serve.post_json("/api/files/local/cube.stl", {{"command", "select"}}) == 415);  // a model is not printed
  CHECK(serve.stop() == 0);
}

TEST_CASE("the_live_stream_sends_the_status_as_server_sent_events") {
  ServeDirs dirs("serve_stream");
  Serve serve(dirs, {"--time-scale", "40"});
  REQUIRE(serve.upload("ring.gcode", ring_gcode(10), {{"print", "true"}})->status == 201);
  std::vector<json> messages;
  std::string buffer;
  auto c = serve.client();
  std::string content_type;
  auto r = c.Get(
      "/api/mahost/events",
      [&](const httplib::Response& response) {
        content_type = response.get_header_value("Content-Type");
        return true;
      },
      [&](const char* data, std::size_t size) {
        buffer.append(data, size);
        for (std::size_t end; (end = buffer.find("\n\n")) != std::string::npos;) {
          const std::string message = buffer.substr(0, end);
          buffer.erase(0, end + 2);
          if (message.rfind("data: ", 0) == 0) messages.push_back(json::parse(message.substr(6)));
        }
        return messages.size() < 5;  // enough: the client hangs up
      });
  CHECK(content_type == "text/event-stream");
  REQUIRE(messages.size() == 5);
  for (std::size_t i = 1; i < messages.size(); ++i) {
    CHECK(messages[i]["version"].get<std::uint64_t>() > messages[i - 1]["version"].get<std::uint64_t>());
  }
  for (const json& m : messages) {
    CHECK(m["state"].is_string());
    CHECK(m["printer"]["flags"].is_object());
    CHECK(m["temperature"]["tool0"].is_object());
    CHECK(m["events"].is_array());
  }
  // Each event once: the stream sends only those after the last it sent.
  std::vector<std::uint64_t> ids;
  for (const json& m : messages) {
    for (const json& e : m["events"]) ids.push_back(e["id"]);
  }
  CHECK(std::adjacent_find(ids.begin(), ids.end(), [](auto a, auto b) { return b <= a; }) == ids.end());
  CHECK_FALSE(ids.empty());
  // The server is fine after the client left mid-stream.
  CHECK(serve.get_json("/api/version")["api"] == "0.1");
  CHECK(serve.stop() == 0);
}

TEST_CASE("profiles_layer_drawing_and_restart_serve_the_page") {
  ServeDirs dirs("serve_page_api");
  Serve serve(dirs, {"--time-scale", "20"});
  const json profiles = serve.get_json("/api/mahost/profiles");
  CHECK(profiles["serving"]["printer"] == "up-plus-2");
  bool up = false;
  for (const json& p : profiles["printers"]) {
    if (p["id"] == "up-plus-2") {
      up = true;
      CHECK(p["layers"] == json::array({0.15, 0.2, 0.25, 0.3, 0.35, 0.4}));
    }
    // What a slice leaves to the printer profile, as its file says.
    const printer::PrinterProfile profile =
        printer::load_printer_profile(p["id"].get<std::string>(), MAHOST_SOURCE_DIR "/configs");
    CHECK(p["defaults"]["support"] == profile.support.type);
    CHECK(p["defaults"]["brim"] == profile.brim_width);
    CHECK(p["defaults"]["raft"] == profile.raft.enabled);
    CHECK(p["defaults"]["adaptive"] == false);
  }
  CHECK(up);
  CHECK(profiles["supports"] == json::array({"none", "buildplate", "everywhere"}));
  // The slicer's table of strategies, as --contour takes them.
  std::set<std::string> contours;
  for (const json& c : profiles["contours"]) contours.insert(c.get<std::string>());
  for (const char* c : {"ma", "mid", "lower", "optimal-height"}) CHECK(contours.count(c) == 1);
  auto c = serve.client();
  CHECK(c.Get("/api/mahost/layer")->status == 404);  // nothing printed yet

  REQUIRE(serve.upload("ring.gcode", ring_gcode(12), {{"print", "true"}})->status == 201);
  REQUIRE(wait_for([&] { return serve.get_json("/api/job")["mahost"].value("layer", 0) >= 2; }, 60s));
  const json layer = serve.get_json("/api/mahost/layer?layer=1");
  CHECK(layer["layer"] == 1);
  CHECK(layer["layers"] == 12);
  CHECK(layer["z"] == 0.2);
  CHECK(layer["todo"] == "");  // layer 1 is printed
  CHECK(layer["bed"] == json::array({140.0, 140.0}));
  // The ring's widest layer (of 12) reaches 100 - r at r = 20 + 5 sin(1.1).
  CHECK(layer["bounds"][0].get<double>() == doctest::Approx(100 - (20 + 5 * std::sin(1.1))).epsilon(1e-4));
  const json last = serve.get_json("/api/mahost/layer?layer=12");
  CHECK(last["done"] == "");  // not yet
  CHECK(c.Get("/api/mahost/layer?layer=13")->status == 404);
  CHECK(c.Get("/api/mahost/layer?layer=x")->status == 400);

  // restart: only from a pause; it prints the file again from its start.
  CHECK(serve.post_json("/api/job", {{"command", "restart"}}) == 409);
  CHECK(serve.post_json("/api/job", {{"command", "pause"}, {"action", "pause"}}) == 204);
  REQUIRE(serve.wait_state("Paused", 60s));
  CHECK(serve.post_json("/api/job", {{"command", "restart"}}) == 204);
  REQUIRE(wait_for([&] {
    const json j = serve.get_json("/api/job");
    return j["mahost"]["jobState"] == "printing" && j["mahost"].value("layer", 99) <= 2;
  }, 60s));
  CHECK(serve.post_json("/api/job", {{"command", "cancel"}}) == 204);
  REQUIRE(wait_for([&] { return serve.get_json("/api/job")["mahost"]["jobState"] == "cancelled"; }, 60s));
  const std::string log = serve.log();
  CHECK(log.find("cancelled ring.gcode") != std::string::npos);
  CHECK(serve.stop() == 0);
}

TEST_CASE("planned_pauses_stop_before_their_layers_as_print_pause_at_layer_does") {
  ServeDirs dirs("serve_pause_at");
  Serve serve(dirs, {"--time-scale", "40"});
  CHECK(serve.post_json("/api/mahost/pause-at", {{"layers", {0}}}) == 400);
  CHECK(serve.post_json("/api/mahost/pause-at", {{"layers", "4"}}) == 400);
  CHECK(serve.post_json("/api/mahost/pause-at", {{"layers", {7, 4, 4}}}) == 204);
  CHECK(serve.get_json("/api/mahost/status")["pauseAt"] == json::array({4, 7}));
  REQUIRE(serve.upload("ring.gcode", ring_gcode(10), {{"print", "true"}})->status == 201);
  for (int layer : {4, 7}) {
    CAPTURE(layer);
    REQUIRE(serve.wait_state("Paused", 120s));
    CHECK(serve.get_json("/api/job")["mahost"]["layer"] == layer);  // stopped before it, not in it
    CHECK(serve.log().find(fmt::format("paused before layer {}/10", layer)) != std::string::npos);
    CHECK(serve.post_json("/api/job", {{"command", "pause"}, {"action", "resume"}}) == 204);
    REQUIRE(wait_for([&] { return serve.state() != "Paused"; }, 60s));
  }
  REQUIRE(wait_for([&] { return serve.get_json("/api/job")["mahost"]["jobState"] == "completed"; }, 120s));
  CHECK(serve.get_json("/api/mahost/status")["pauseAt"].empty());  // each taken once
  CHECK(serve.stop() == 0);
}

}  // namespace serve_mahost_api_test
