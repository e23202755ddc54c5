// mahost serve's defences: the API key on every endpoint, file names that would leave the
// files folder, an upload too large, a body cut short, garbage bytes, a key file others may
// read, and an address beyond this machine.
#include <sys/stat.h>

#include <doctest/doctest.h>
#include <fmt/core.h>

#include "serve_fixture.h"

namespace serve_security_test {

using namespace serve_test;

namespace {

// Every endpoint, as method and path (with a real file name where one is needed).
const std::vector<std::pair<std::string, std::string>> kEndpoints = {
    {"GET", "/api/version"},          {"GET", "/api/server"},
    {"GET", "/api/settings"},         {"POST", "/api/login"},
    {"GET", "/api/currentuser"},      {"GET", "/api/printerprofiles"},
    {"GET", "/api/connection"},       {"POST", "/api/connection"},
    {"GET", "/api/files"},            {"GET", "/api/files/local"},
    {"POST", "/api/files/local"},     {"GET", "/api/files/local/a.gcode"},
    {"POST", "/api/files/local/a.gcode"}, {"DELETE", "/api/files/local/a.gcode"},
    {"GET", "/downloads/files/local/a.gcode"},
    {"GET", "/api/job"},              {"POST", "/api/job"},
    {"GET", "/api/printer"},          {"GET", "/api/printer/tool"},
    {"GET", "/api/printer/bed"},      {"POST", "/api/printer/command"},
    {"GET", "/api/mahost/status"},    {"GET", "/api/mahost/events"},
    {"GET", "/api/mahost/layer"},     {"GET", "/api/mahost/profiles"},
    {"POST", "/api/mahost/interrupted"}, {"POST", "/api/mahost/stop"},
    {"POST", "/api/mahost/pause-at"},
    {"GET", "/api/no/such/endpoint"},
};

int request(const Serve& serve, const std::string& method, const std::string& path, const std::string& key) {
  RawConnection raw(serve.port);
  std::string head = method + " " + path + " HTTP/1.1\r\nHost: 127.0.0.1\r\nConnection: close\r\n";
  if (!key.empty()) head += "X-Api-Key: " + key + "\r\n";
  const std::string body = method == "GET" ? "" : R"({"command":"start"})";
  if (!body.empty()) head += "Content-Type: application/json\r\nContent-Length: " + std::to_string(body.size()) + "\r\n";
  REQUIRE(raw.send(head + "\r\n" + body));
  return status_of(raw.receive(10s));
}

std::string multipart(const std::string& boundary, const std::string& filename, const std::string& content) {
  return "--" + boundary + "\r\nContent-Disposition: form-data; name=\"file\"; filename=\"" + filename +
         "\"\r\nContent-Type: application/octet-stream\r\n\r\n" + content + "\r\n--" + boundary + "--\r\n";
}

std::string upload_head(std::size_t length, const std::string& boundary, const std::string& extra = {}) {
  return "POST /api/files/local HTTP/1.1\r\nHost: 127.0.0.1\r\nX-Api-Key: " + std::string(kKey) +
         "\r\nContent-Type: multipart/form-data; boundary=" + boundary + "\r\nContent-Length: " +
         std::to_string(length) + "\r\n" + extra + "\r\n";
}

// Every file below the test's folder, relative, sorted: what the server may have written.
std::vector<std::string> tree(const std::string& root) {
  std::vector<std::string> files;
  for (const auto& entry : fs::recursive_directory_iterator(root)) {
    const std::string path = fs::relative(entry.path(), root).string();
    if (path.rfind("serve.log", 0) == 0 || path.rfind("run", 0) == 0) continue;
    files.push_back(path);
  }
  std::sort(files.begin(), files.end());
  return files;
}

}  // namespace

TEST_CASE("every_endpoint_refuses_a_request_without_the_key_or_with_a_wrong_one") {
  ServeDirs dirs("serve_keys");
  Serve serve(dirs, {"--time-scale", "max"});
  for (const auto& [method, path] : kEndpoints) {
    CAPTURE(method);
    CAPTURE(path);
    CHECK(request(serve, method, path, "") == 401);
    CHECK(request(serve, method, path, "0123456789abcdef0123456789abcdef") == 403);
    CHECK(request(serve, method, path, std::string(kKey) + "x") == 403);
  }
  // The key goes in the header only: not as a query parameter, not as a cookie.
  RawConnection raw(serve.port);
  REQUIRE(raw.send("GET /api/job?apikey=" + std::string(kKey) + " HTTP/1.1\r\nHost: x\r\nCookie: X-Api-Key=" +
                   kKey + "\r\nConnection: close\r\n\r\n"));
  CHECK(status_of(raw.receive(10s)) == 401);
  // The page itself loads without the key (it asks for it), under a strict policy.
  auto c = serve.client(false);
  auto page = c.Get("/");
  REQUIRE(page);
  CHECK(page->status == 200);
  CHECK(page->get_header_value("Content-Type") == "text/html; charset=utf-8");
  CHECK(page->get_header_value("Content-Security-Policy").find("default-src 'self'") != std::string::npos);
  CHECK(page->body.find("X-Api-Key") == std::string::npos);  // the page holds no key
  CHECK(c.Get("/app.js")->status == 200);
  CHECK(c.Get("/style.css")->status == 200);
  CHECK(c.Get("/../../etc/passwd")->status != 200);
  CHECK(serve.stop() == 0);
}

TEST_CASE("names_that_would_leave_the_files_folder_are_refused_and_nothing_is_written") {
  ServeDirs dirs("serve_names");
  Serve serve(dirs, {"--time-scale", "max"});
  const std::vector<std::string> before = tree(dirs.root);
  const std::string gcode = ring_gcode(1);
  struct Case {
    std::string name;
    int status;
  };
  for (const Case& k : std::vector<Case>{{"../../etc/passwd", 400},
                                         {"../../etc/passwd.gcode", 400},
                                         {"/etc/passwd.gcode", 400},
                                         {"..\\..\\windows.gcode", 400},
                                         {"sub/dir.gcode", 400},
                                         {"..", 400},
                                         {".hidden.gcode", 400},
                                         {"bell\a.gcode", 400},
                                         {"passwd", 415},
                                         {"tool.exe", 415},
                                         {"", 400}}) {
    CAPTURE(k.name);
    auto r = serve.upload(k.name, gcode);
    REQUIRE(r);
    CHECK(r->status == k.status);
    CHECK(json::parse(r->body)["error"].is_string());
  }
  // A path field names a folder: refused, not created.
  auto r = serve.upload("ok.gcode", gcode, {{"path", "../../"}});
  CHECK(r->status == 400);
  CHECK(tree(dirs.root) == before);
  CHECK(serve.get_json("/api/files")["files"].empty());

  // Names in URLs, encoded or not, meet the same check.
  auto c = serve.client();
  for (const std::string path : {"/api/files/local/..%2F..%2Fetc%2Fpasswd", "/api/files/local/%2Fetc%2Fpasswd",
                                  "/api/files/local/../../etc/passwd"}) {
    CAPTURE(path);
    CHECK(c.Get(path)->status == 400);
    CHECK(c.Delete(path)->status == 400);
    CHECK(c.Post(path, R"({"command":"select"})", "application/json")->status == 400);
  }
  CHECK(c.Get("/downloads/files/local/..%2F..%2Fetc%2Fpasswd")->status == 400);
  CHECK(c.Get("/api/files/sdcard/a.gcode")->status == 404);
  // A link planted in the folder is neither listed nor served nor deleted.
  fs::create_symlink("/etc/passwd", dirs.files + "/link.gcode");
  CHECK(serve.get_json("/api/files")["files"].empty());
  CHECK(c.Get("/downloads/files/local/link.gcode")->status == 404);
  CHECK(c.Delete("/api/files/local/link.gcode")->status == 404);
  CHECK(fs::is_symlink(dirs.files + "/link.gcode"));
  // Odd characters are cleaned, not refused.
  r = serve.upload("my part (v2) ü.gcode", gcode);
  CHECK(r->status == 201);
  CHECK(json::parse(r->body)["files"]["local"]["name"] == "my_part_(v2)_.gcode");
  CHECK(serve.stop() == 0);
}

TEST_CASE("a_2_gib_upload_is_refused_from_its_announced_size_before_its_body") {
  ServeDirs dirs("serve_big");
  // A limit of 4 MiB: the third case below sends the whole body, and at 64 MiB reading it took
  // longer than the answer's wait on a machine at load 20.
  Serve serve(dirs, {"--time-scale", "max", "--max-upload", "4"});
  const std::uint64_t two_gib = 2ull << 30;
  {
    // Announced, then a start of the body: 413 at once, the rest never read.
    RawConnection raw(serve.port);
    REQUIRE(raw.send(upload_head(two_gib, "big") + multipart("big", "big.gcode", "G28\n").substr(0, 60)));
    const std::string reply = raw.receive(10s);
    CHECK(status_of(reply) == 413);
    CHECK(reply.find("4 MiB at most") != std::string::npos);
  }
  {
    // With Expect: 100-continue (curl's way): refused before the client sends a byte.
    RawConnection raw(serve.port);
    REQUIRE(raw.send(upload_head(two_gib, "big", "Expect: 100-continue\r\n")));
    CHECK(status_of(raw.receive(10s)) == 413);
  }
  {
    // Announced within the limit with its form's overhead, but the file itself is over: the
    // stream is cut where it passes the limit.
    RawConnection raw(serve.port);
    std::string body = multipart("big", "big.gcode", std::string((4u << 20) + 1000, 'G'));
    REQUIRE(raw.send(upload_head(body.size(), "big")));
    raw.send(body);  // the server may stop reading early
    CHECK(status_of(raw.receive(60s)) == 413);
  }
  CHECK(serve.get_json("/api/files")["files"].empty());
  CHECK(fs::is_empty(dirs.files));
  CHECK(serve.stop() == 0);
}

TEST_CASE("a_truncated_multipart_body_and_garbage_bytes_are_refused_and_the_server_goes_on") {
  ServeDirs dirs("serve_garbage");
  Serve serve(dirs, {"--time-scale", "max"});
  const std::string body = multipart("cut", "cut.gcode", ring_gcode(3));
  {
    // Content-Length says more than comes and the client stalls: refused once the server
    // stops waiting for the rest (its read timeout, 10 s).
    RawConnection raw(serve.port);
    REQUIRE(raw.send(upload_head(body.size(), "cut") + body.substr(0, body.size() / 2)));
    CHECK(status_of(raw.receive(60s)) == 400);
  }
  {
    // The client gives up half-way (closes its side): nothing is kept, whoever hears the answer.
    RawConnection raw(serve.port);
    REQUIRE(raw.send(upload_head(body.size(), "cut") + body.substr(0, body.size() / 2)));
    raw.finish_sending();
    raw.receive(30s);
  }
  {
    // All the bytes, but the closing boundary never comes.
    const std::string open = body.substr(0, body.rfind("--cut--"));
    RawConnection raw(serve.port);
    REQUIRE(raw.send(upload_head(open.size(), "cut") + open));
    CHECK(status_of(raw.receive(30s)) == 400);
  }
  {
    // A multipart body with no boundary in its type.
    RawConnection raw(serve.port);
    REQUIRE(raw.send("POST /api/files/local HTTP/1.1\r\nHost: x\r\nX-Api-Key: " + std::string(kKey) +
                     "\r\nContent-Type: multipart/form-data\r\nContent-Length: 4\r\n\r\nabcd"));
    CHECK(status_of(raw.receive(10s)) == 400);
  }
  // Garbage instead of HTTP, and garbage as a file.
  for (const std::string& junk : {std::string("\x00\xff\xfe garbage\r\n\r\n", 16), std::string("GET\r\n\r\n"),
                                  std::string(5000, '\x01') + "\r\n\r\n"}) {
    RawConnection raw(serve.port);
    raw.send(junk);
    raw.finish_sending();
    const int status = status_of(raw.receive(10s));
    CHECK((status == 400 || status == 414 || status == -1));
  }
  std::string binary;
  for (int i = 0; i < 4096; ++i) binary += static_cast<char>((i * 7919) & 0xff);
  auto r = serve.upload("noise.gcode", binary);
  CHECK(r->status == 415);
  r = serve.upload("noise.stl", binary);
  CHECK(r->status == 415);
  // G-code whose numbers no firmware holds is refused with the line, and what to do said
  // for an upload (there is no --force to give a browser).
  r = serve.upload("far.gcode", "G28\nG1 X1e999 Y5\n");
  CHECK(r->status == 415);
  CHECK(r->body.find("line 2 is not G-code (X1e999 is too large for a printer's numbers") !=
        std::string::npos);
  CHECK(r->body.find("fix the line, then upload the file again") != std::string::npos);
  CHECK(r->body.find("--force") == std::string::npos);
  auto c = serve.client();
  CHECK(c.Post("/api/job", "{not json", "application/json")->status == 400);
  CHECK(c.Post("/api/job", "[1,2,3]", "application/json")->status == 400);
  CHECK(c.Post("/api/job", std::string(70000, ' '), "application/json")->status == 413);
  {
    // A compressed body could unpack to any size: refused from its header.
    RawConnection raw(serve.port);
    REQUIRE(raw.send("POST /api/job HTTP/1.1\r\nHost: x\r\nX-Api-Key: " + std::string(kKey) +
                     "\r\nContent-Type: application/json\r\nContent-Encoding: gzip\r\nContent-Length: 4\r\n\r\n\x1f\x8b\x08\x00"));
    CHECK(status_of(raw.receive(10s)) == 415);
  }
  CHECK(fs::is_empty(dirs.files));
  // Still serving, and each refusal logged.
  CHECK(serve.get_json("/api/version")["api"] == "0.1");
  const std::string log = serve.log();
  CHECK(log.find("POST /api/files/local -> 400") != std::string::npos);
  CHECK(log.find("-> 415") != std::string::npos);
  CHECK(serve.stop() == 0);
}

TEST_CASE("the_api_key_is_made_once_with_mode_0600_and_a_readable_one_is_refused") {
  ServeDirs dirs("serve_key_file");
  const std::string key_file = dirs.root + "/config/mahost/api-key";
  std::string first;
  {
    Serve serve(dirs, {"--time-scale", "max"}, false);
    struct stat info {};
    REQUIRE(stat(key_file.c_str(), &info) == 0);
    CHECK((info.st_mode & 0777) == 0600);
    first = read_text(key_file);
    CHECK(first.size() == 33);  // 32 hex digits and a line end
    CHECK(serve.log().find("API key: " + first.substr(0, 32) + " (made now") != std::string::npos);
    auto c = serve.client(false);
    c.set_default_headers({{"X-Api-Key", first.substr(0, 32)}});
    CHECK(c.Get("/api/job")->status == 200);
    CHECK(serve.stop() == 0);
  }
  {
    Serve serve(dirs, {"--time-scale", "max"}, false);  // the same key again
    CHECK(read_text(key_file) == first);
    CHECK(serve.stop() == 0);
  }
  chmod(key_file.c_str(), 0644);
  const auto r = test_support::run_command(
      {"env", "-i", "HOME=" + dirs.root, "XDG_CONFIG_HOME=" + dirs.root + "/config", "XDG_RUNTIME_DIR=" + dirs.runtime,
       MAHOST_BINARY, "serve", "--dry-run", "--listen", "127.0.0.1:0", "--files", dirs.files}, {}, std::chrono::seconds(60));
  CHECK(r.exit_code == 2);
  CHECK(r.err.find("may be read by others (mode 644): chmod 600 it") != std::string::npos);
}

TEST_CASE("serve_invocations_that_cannot_work_say_so_in_one_line") {
  ServeDirs dirs("serve_cli");
  auto run = [&](std::vector<std::string> args) {
    std::vector<std::string> argv{"env", "MAHOST_API_KEY=" + std::string(kKey), "XDG_RUNTIME_DIR=" + dirs.runtime,
                                  MAHOST_BINARY, "serve"};
    argv.insert(argv.end(), args.begin(), args.end());
    return test_support::run_command(argv, {}, std::chrono::seconds(60));
  };
  auto r = run({"--files", dirs.files});
  CHECK(r.exit_code == 2);
  CHECK(r.err == "mahost: serve: give either --port PORT or --dry-run\n");
  r = run({"--dry-run", "--listen", "localhost:http", "--files", dirs.files});
  CHECK(r.exit_code == 2);
  CHECK(r.err.find("--listen localhost:http: give HOST:PORT") != std::string::npos);
  r = run({"--port", "/dev/ttyUSB0", "--time-scale", "10", "--files", dirs.files});
  CHECK(r.exit_code == 2);
  CHECK(r.err == "mahost: --time-scale: only a --dry-run printer's clock can be sped up\n");
  r = run({"--dry-run", "--time-scale", "fast", "--files", dirs.files});
  CHECK(r.exit_code == 2);
  CHECK(r.err.find("--time-scale fast: give a speed-up factor") != std::string::npos);
  r = run({"--port", "/dev/no-such-port", "--files", dirs.files});
  CHECK(r.exit_code == 3);
  // A port in use is an error, not a second server sharing it.
  {
    Serve first(dirs, {"--time-scale", "max"});
    r = run({"--dry-run", "--listen", fmt::format("127.0.0.1:{}", first.port), "--files", dirs.files});
    CHECK(r.exit_code == 2);
    CHECK(r.err.find("cannot listen there") != std::string::npos);
    CHECK(first.stop() == 0);
  }
  // Beyond this machine: served, with a warning.
  Serve wide(dirs, {"--time-scale", "max", "--listen", "0.0.0.0:0"});
  CHECK(wide.log().find("warning: listening on 0.0.0.0:") != std::string::npos);
  CHECK(wide.stop() == 0);
}

}  // namespace serve_security_test
