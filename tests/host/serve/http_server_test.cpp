// HttpServer's time bounds, in-process with limits short enough to reach at once: a head that
// never ends is cut off with 408, a kept-alive connection left idle is closed. Each asserts what
// the client reads, never how long it took. (The share per address: serve_load_test.cpp.)
#include "host/serve/http_server.h"

#include <doctest/doctest.h>

#include "serve_fixture.h"

namespace http_server_test {

using namespace serve_test;

namespace {

// A server on a free loopback port with `limits`, answering GET /ok.
class TestServer {
 public:
  explicit TestServer(host::serve::ConnectionLimits limits) : server(limits) {
    server.Get("/ok", [](const httplib::Request&, httplib::Response& res) { res.set_content("ok", "text/plain"); });
    // As HttpApi: httplib answers a head cut off within its headers 400; the server says why.
    server.set_error_handler(httplib::Server::HandlerWithResponse([](const httplib::Request&, httplib::Response& res) {
      if (!host::serve::HttpServer::head_timed_out()) return httplib::Server::HandlerResponse::Unhandled;
      res.status = 408;
      res.set_content(host::serve::HttpServer::head_timeout_message(), "text/plain");
      return httplib::Server::HandlerResponse::Handled;
    }));
    server.set_post_routing_handler(
        [](const httplib::Request& req, httplib::Response& res) { host::serve::HttpServer::close_if_unread(req, res); });
    port = server.bind_to_any_port("127.0.0.1");
    REQUIRE(port > 0);
    // Bound and listening already: a connection waits in the backlog until the loop takes it.
    thread = std::thread([this] { server.listen_after_bind(); });
  }
  ~TestServer() {
    server.stop();
    thread.join();
  }

  host::serve::HttpServer server;
  int port = -1;
  std::thread thread;
};

}  // namespace

TEST_CASE("a_request_head_that_never_ends_is_cut_off_with_408_and_the_server_goes_on") {
  TestServer t(host::serve::ConnectionLimits{.head_time = std::chrono::milliseconds(200)});
  // Half a request line, and half a head: however slow this machine, neither ever completes.
  for (const std::string half : {"GET /ok HT", "GET /ok HTTP/1.1\r\nHost: 127.0.0.1\r\n"}) {
    CAPTURE(half);
    RawConnection raw(t.port);
    REQUIRE(raw.send(half));
    std::string pending;
    const RawResponse r = read_response(raw, pending, 60s);
    CHECK(r.status == 408);
    CHECK(r.closes());
    CHECK(r.body.find("the request's line and headers did not arrive within 0.2 s") != std::string::npos);
    CHECK(raw.closed_by_server(60s));
  }
  const RawResponse after = send_raw(t.port, "GET /ok HTTP/1.1\r\nHost: x\r\n\r\n");
  CHECK(after.status == 200);
}

TEST_CASE("a_kept_alive_connection_left_idle_is_closed_by_the_server") {
  TestServer t(host::serve::ConnectionLimits{.idle = std::chrono::milliseconds(200)});
  RawConnection raw(t.port);
  REQUIRE(raw.send("GET /ok HTTP/1.1\r\nHost: x\r\n\r\n"));
  std::string pending;
  const RawResponse r = read_response(raw, pending, 60s);
  CHECK(r.status == 200);
  CHECK_FALSE(r.closes());
  // Nothing more sent: the server, not the test, ends the connection.
  CHECK(raw.closed_by_server(60s));
}

}  // namespace http_server_test
