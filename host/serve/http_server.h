// cpp-httplib's Server with the connection handling `mahost serve` needs beyond what Debian 12's
// httplib (0.11) does by itself: it keeps httplib's request parsing, routing, handlers and
// response writing (process_request), and replaces the loop around them for each connection
// (process_and_close_socket, which httplib declares virtual for this), because that loop
//  - keeps a connection open after a refusal given before the body was read (401, 403, 413,
//    or after 100-continue): the unread body is then parsed as hundreds of requests, each a
//    "400 malformed request" the client reads as its next answers;
//  - times out each read, never a request: a client sending a byte a second holds its thread
//    for ever;
//  - runs in a fixed pool of threads, each held by a kept-alive connection for its whole life:
//    70 polling clients starve the 71st, pause and cancel included.
//
// Here every connection gets a thread of its own (up to `total`), so nothing waits for a
// worker; a request's line and headers must arrive whole within `head_time`; a body may not
// stall longer than `body_stall`; a kept-alive connection idles `idle` at most. A connection
// whose request is answered before its body was read is closed ("Connection: close"), after
// reading and dropping what the client still sends (`linger`, bounded in time and bytes), so
// the client reads the answer rather than a reset. One client address holds `per_address`
// connections; on those beyond, only the requests `always_served` names are served (pause,
// resume, cancel, emergency stop), the rest answered 503 and closed.
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <map>
#include <mutex>
#include <string>

#include <httplib.h>

namespace host::serve {

struct ConnectionLimits {
  int per_address = 24;                       // connections served in full from one address
  int total = 512;                            // connections open at once; beyond: 503 at once
  std::chrono::milliseconds head_time{10000};  // a request's line and headers, from their first byte
  std::chrono::milliseconds idle{5000};        // between requests on a kept-alive connection
  std::chrono::milliseconds body_stall{10000};  // the longest silence within a body
  std::chrono::milliseconds write_stall{10000};  // the longest wait for a client to take bytes
  std::chrono::milliseconds linger{2000};      // reading what follows a refusal, at most
  std::uint64_t linger_bytes = 16ull << 20;    // and this many bytes at most
};

class HttpServer : public httplib::Server {
 public:
  explicit HttpServer(ConnectionLimits limits);

  // The requests served on a connection beyond its address's share; set before listening.
  std::function<bool(const httplib::Request&)> always_served;

  const ConnectionLimits& limits() const { return limits_; }

  // About the connection of the request being handled, for the handlers and the pre- and
  // post-routing hooks (which httplib runs on the connection's thread):
  // When the connection is beyond its address's share and the request is not one that is
  // always served: why (the caller answers 503 with it), and the connection is marked to
  // close after the answer. "" otherwise.
  static std::string beyond_share_refusal(const httplib::Request& req);
  // Whether the request's line and headers timed out (httplib then answers 400: make it 408),
  // and the answer's text.
  static bool head_timed_out();
  static std::string head_timeout_message();
  // Sets "Connection: close" on the answer when the request's body was not read to its end
  // (a refusal before it, an upload cut off at its limit) or the caller asked for it; the
  // connection is then closed after the answer. Called last before the answer is written.
  static void close_if_unread(const httplib::Request& req, httplib::Response& res);

 private:
  bool process_and_close_socket(socket_t sock) override;

  struct Address {
    int open = 0;
  };
  // Counts the connection in; false when `total` are open already.
  bool admit(const std::string& address, bool& beyond_share);
  void leave(const std::string& address);

  ConnectionLimits limits_;
  std::mutex mutex_;
  std::map<std::string, Address> addresses_;
  int open_ = 0;
};

}  // namespace host::serve
