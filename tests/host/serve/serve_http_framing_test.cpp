// How mahost serve frames its answers on a connection: a request refused before its body was
// read (401, 403, 413) is answered once and the connection closed, so the unread body is never
// taken for requests; Expect: 100-continue is answered before the client sends its body;
// lengths that are not a number or disagree, and a line break in an uploaded file's name, get
// a refusal that says what is wrong (a head that never ends: http_server_test.cpp).
#include <doctest/doctest.h>
#include <fmt/core.h>

#include "serve_fixture.h"

namespace serve_http_framing_test {

using namespace serve_test;

namespace {

std::string upload_head(std::uint64_t length, const std::string& key, const std::string& extra = {}) {
  return "POST /api/files/local HTTP/1.1\r\nHost: 127.0.0.1\r\n" + (key.empty() ? "" : "X-Api-Key: " + key + "\r\n") +
         "Content-Type: multipart/form-data; boundary=BOUNDARY\r\nContent-Length: " + std::to_string(length) +
         "\r\n" + extra + "\r\n";
}

std::string upload_body(const std::string& filename, const std::string& content) {
  return "--BOUNDARY\r\nContent-Disposition: form-data; name=\"file\"; filename=\"" + filename +
         "\"\r\nContent-Type: application/octet-stream\r\n\r\n" + content + "\r\n--BOUNDARY--\r\n";
}

std::string error_of(const RawResponse& r) {
  const json body = json::parse(r.body, nullptr, false);
  return body.is_object() && body.contains("error") ? body["error"].get<std::string>() : r.body;
}

std::size_t count(const std::string& text, const std::string& part) {
  std::size_t n = 0;
  for (std::size_t at = text.find(part); at != std::string::npos; at = text.find(part, at + 1)) ++n;
  return n;
}

}  // namespace

TEST_CASE("a_refused_2_mb_upload_on_a_kept_alive_connection_is_answered_once_and_the_connection_closed") {
  ServeDirs dirs("serve_refused_body");
  Serve serve(dirs, {"--time-scale", "max"});
  // 2 MB of G-code as a client sends it, without waiting (no Expect), then its next request on
  // the same connection, as a kept-alive client (Cura's poll) would.
  const std::string body = upload_body("big.gcode", std::string(2 << 20, ';'));
  struct Case {
    std::string key;
    std::string extra;
    int status;
    std::string error;
  };
  for (const Case& k : {Case{"0123456789abcdef0123456789abcdef", "", 403, "wrong API key"},
                        Case{"", "", 401, "no API key"}}) {
    CAPTURE(k.status);
    RawConnection raw(serve.port);
    REQUIRE(raw.send(upload_head(body.size(), k.key) + body));
    raw.send("GET /api/version HTTP/1.1\r\nHost: 127.0.0.1\r\nX-Api-Key: " + std::string(kKey) + "\r\n\r\n");
    std::string pending;
    const RawResponse r = read_response(raw, pending, 60s);
    INFO(r.head << r.body);
    CHECK(r.status == k.status);
    CHECK(error_of(r).rfind(k.error, 0) == 0);
    CHECK(r.closes());
    CHECK(r.head.find("Keep-Alive") == std::string::npos);
    // Nothing follows the one answer: the body was not read as requests, and the request after
    // it is the client's to send again on a new connection.
    CHECK(raw.closed_by_server(60s));
    CHECK(pending.empty());
  }
  {
    // Announced larger than the server takes, its body started: 413, then closed.
    RawConnection raw(serve.port);
    REQUIRE(raw.send(upload_head(3ull << 30, kKey) + body.substr(0, 100000)));
    std::string pending;
    const RawResponse r = read_response(raw, pending, 60s);
    CHECK(r.status == 413);
    CHECK(r.closes());
    CHECK(raw.closed_by_server(60s));
  }
  // One log line for each refusal, none for bytes of a body taken as requests.
  const std::string log = serve.log();
  INFO(log);
  CHECK(count(log, "POST /api/files/local -> 403") == 1);
  CHECK(count(log, "POST /api/files/local -> 401") == 1);
  CHECK(count(log, "-> 413") == 1);
  CHECK(count(log, "-> 400") == 0);
  // A fresh connection is served as ever.
  CHECK(serve.get_json("/api/version")["api"] == "0.1");
  CHECK(fs::is_empty(dirs.files));
  CHECK(serve.stop() == 0);
}

TEST_CASE("expect_100_continue_is_answered_before_the_client_sends_its_body") {
  ServeDirs dirs("serve_expect");
  Serve serve(dirs, {"--time-scale", "max"});
  const std::string body = upload_body("ring.gcode", ring_gcode(2));
  {
    // Refused: the answer comes with no byte of the body sent, and the connection closes.
    RawConnection raw(serve.port);
    REQUIRE(raw.send(upload_head(body.size(), "wrong-key-0123456789", "Expect: 100-continue\r\n")));
    std::string pending;
    const RawResponse r = read_response(raw, pending, 60s);
    CHECK(r.status == 403);
    CHECK(r.closes());
    CHECK(raw.closed_by_server(60s));
  }
  {
    // Accepted: "100 Continue" first, then the body, then the answer on the same connection.
    RawConnection raw(serve.port);
    REQUIRE(raw.send(upload_head(body.size(), kKey, "Expect: 100-continue\r\n")));
    std::string pending;
    const RawResponse go_on = read_response(raw, pending, 60s);
    CHECK(go_on.status == 100);
    REQUIRE(raw.send(body));
    const RawResponse r = read_response(raw, pending, 60s);
    CHECK(r.status == 201);
    CHECK_FALSE(r.closes());
    // Still open for the next request.
    REQUIRE(raw.send("GET /api/version HTTP/1.1\r\nHost: x\r\nX-Api-Key: " + std::string(kKey) + "\r\n\r\n"));
    CHECK(read_response(raw, pending, 60s).status == 200);
  }
  CHECK(serve.stop() == 0);
}

TEST_CASE("lengths_that_are_no_number_or_disagree_and_a_line_break_in_a_file_name_are_refused_for_what_they_are") {
  ServeDirs dirs("serve_framing_refusals");
  Serve serve(dirs, {"--time-scale", "max"});
  const std::string key = "X-Api-Key: " + std::string(kKey) + "\r\n";
  const std::string json_post = "POST /api/job HTTP/1.1\r\nHost: x\r\n" + key + "Content-Type: application/json\r\n";
  struct Case {
    std::string request;
    std::string error;
  };
  for (const Case& k : {
           Case{json_post + "Content-Length: -1\r\n\r\n{}", "Content-Length '-1' is not a number of bytes"},
           Case{json_post + "Content-Length: 12abc\r\n\r\n{}", "Content-Length '12abc' is not a number of bytes"},
           Case{json_post + "Content-Length: 2\r\nContent-Length: 20\r\n\r\n{}",
                "the request has two Content-Length headers that disagree (2 and 20): send one"},
           Case{json_post + "Content-Length: 2\r\nTransfer-Encoding: chunked\r\n\r\n{}",
                "the request has both Content-Length and Transfer-Encoding: send one"},
       }) {
    CAPTURE(k.request);
    RawConnection raw(serve.port);
    REQUIRE(raw.send(k.request));
    std::string pending;
    const RawResponse r = read_response(raw, pending, 60s);
    CHECK(r.status == 400);
    CHECK(error_of(r) == k.error);
    CHECK(r.closes());
  }
  // A line break in the file name breaks the part's Content-Disposition line.
  const std::string body = upload_body("bad\r\nname.gcode", ring_gcode(1));
  const RawResponse r = send_raw(serve.port, upload_head(body.size(), kKey) + body);
  CHECK(r.status == 400);
  CHECK(error_of(r).find("its Content-Disposition is broken (a line break or a quote in the file name?)") !=
        std::string::npos);
  CHECK(fs::is_empty(dirs.files));
  CHECK(serve.stop() == 0);
}

TEST_CASE("requests_sent_back_to_back_on_one_connection_are_all_answered_in_order") {
  ServeDirs dirs("serve_pipelined");
  Serve serve(dirs, {"--time-scale", "max"});
  RawConnection raw(serve.port);
  std::string requests;
  for (const char* path : {"/api/version", "/api/job", "/api/printer", "/api/no/such"}) {
    requests += fmt::format("GET {} HTTP/1.1\r\nHost: x\r\nX-Api-Key: {}\r\n\r\n", path, kKey);
  }
  REQUIRE(raw.send(requests));
  std::string pending;
  std::vector<int> statuses;
  for (int i = 0; i < 4; ++i) statuses.push_back(read_response(raw, pending, 60s).status);
  CHECK(statuses == std::vector<int>{200, 200, 200, 404});
  CHECK(serve.stop() == 0);
}

}  // namespace serve_http_framing_test
