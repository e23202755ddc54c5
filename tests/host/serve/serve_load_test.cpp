// mahost serve under load it must outlast: 70 clients polling on kept-alive connections and 60
// clients trickling their requests a byte at a time, while the printer's controls (pause,
// resume, cancel) are still answered. Nothing here asserts a speed: each wait has a generous
// bound that only keeps a hang from running for ever.
#include <atomic>
#include <mutex>

#include <doctest/doctest.h>
#include <fmt/core.h>

#include "serve_fixture.h"

namespace serve_load_test {

using namespace serve_test;

namespace {

constexpr auto kHangGuard = 60s;

std::string get_job_request() {
  return "GET /api/job HTTP/1.1\r\nHost: 127.0.0.1\r\nX-Api-Key: " + std::string(kKey) + "\r\n\r\n";
}

std::string post_job_request(const json& body) {
  const std::string text = body.dump();
  return "POST /api/job HTTP/1.1\r\nHost: 127.0.0.1\r\nX-Api-Key: " + std::string(kKey) +
         "\r\nContent-Type: application/json\r\nContent-Length: " + std::to_string(text.size()) + "\r\n\r\n" + text;
}

// Clients that poll GET /api/job at 10 Hz, each on one kept-alive connection from its address
// (a new one when the server closes it), and clients that send a request's head a byte at a
// time from theirs and start again when the server gives up on them.
class Load {
 public:
  Load(int port, std::vector<std::string> poller_addresses, std::vector<std::string> slow_addresses)
      : port_(port), answers_(poller_addresses.size(), 0) {
    for (std::size_t i = 0; i < poller_addresses.size(); ++i) {
      threads_.emplace_back([this, i, from = poller_addresses[i]] { poll(i, from); });
    }
    slow_bytes_.resize(slow_addresses.size());
    cut_off_.resize(slow_addresses.size());
    for (std::size_t i = 0; i < slow_addresses.size(); ++i) {
      threads_.emplace_back([this, i, from = slow_addresses[i]] { trickle(i, from); });
    }
  }
  ~Load() { stop(); }

  // Every poller has had `n` answers (or was refused) and every slow client has sent `n` bytes.
  bool established(int n) {
    std::lock_guard lock(mutex_);
    const bool polled = std::all_of(answers_.begin(), answers_.end(), [&](int a) { return a >= n || a < 0; });
    const bool trickled = std::all_of(slow_bytes_.begin(), slow_bytes_.end(), [&](int b) { return b >= n; });
    return polled && trickled;
  }
  void stop() {
    done_.store(true);
    for (std::thread& t : threads_) t.join();
    threads_.clear();
  }
  std::map<int, int> statuses() {
    std::lock_guard lock(mutex_);
    return statuses_;
  }
  // Pollers whose every answer was 200, and those refused (503) at their first request.
  int served() {
    std::lock_guard lock(mutex_);
    return static_cast<int>(std::count_if(answers_.begin(), answers_.end(), [](int a) { return a > 0; }));
  }
  int refused() {
    std::lock_guard lock(mutex_);
    return static_cast<int>(std::count(answers_.begin(), answers_.end(), -1));
  }
  // Every slow client was cut off by the server at least once.
  bool all_cut_off() {
    std::lock_guard lock(mutex_);
    return std::all_of(cut_off_.begin(), cut_off_.end(), [](int n) { return n > 0; });
  }
  std::string refusal() {
    std::lock_guard lock(mutex_);
    return refusal_;
  }

 private:
  void poll(std::size_t i, const std::string& from) {
    while (!done_.load()) {
      RawConnection raw(port_, from);
      std::string pending;
      while (!done_.load()) {
        if (!raw.send(get_job_request())) break;
        const RawResponse r = read_response(raw, pending, kHangGuard);
        {
          std::lock_guard lock(mutex_);
          ++statuses_[r.status];
          if (r.status == 200 && answers_[i] >= 0) ++answers_[i];
          if (r.status == 503) {
            answers_[i] = -1;
            refusal_ = r.body;
          }
        }
        if (r.status == 503) return;  // beyond its address's share: it stays away
        if (r.status != 200 || r.closes()) break;
        std::this_thread::sleep_for(100ms);
      }
    }
  }

  void trickle(std::size_t i, const std::string& from) {
    const std::string head = get_job_request();
    while (!done_.load()) {
      RawConnection raw(port_, from);
      for (std::size_t at = 0; at + 2 < head.size() && !done_.load(); ++at) {  // never the last line end
        if (!raw.send(head.substr(at, 1))) {
          std::lock_guard lock(mutex_);
          ++cut_off_[i];
          break;
        }
        {
          std::lock_guard lock(mutex_);
          ++slow_bytes_[i];
        }
        for (int t = 0; t < 10 && !done_.load(); ++t) std::this_thread::sleep_for(100ms);  // a byte a second
      }
    }
  }

  int port_;
  std::atomic<bool> done_{false};
  std::mutex mutex_;
  std::vector<int> answers_;  // per poller: 200s so far, -1 once refused
  std::vector<int> slow_bytes_;
  std::vector<int> cut_off_;  // per slow client: how often the server closed on it
  std::map<int, int> statuses_;
  std::string refusal_;
  std::vector<std::thread> threads_;
};

std::vector<std::string> addresses(int count, int first, int spread) {
  std::vector<std::string> out;
  for (int i = 0; i < count; ++i) out.push_back(fmt::format("127.0.0.{}", first + i % spread));
  return out;
}

// A control request on a connection of its own from `from`: its status.
int control(int port, const std::string& from, const json& body) {
  RawConnection raw(port, from);
  REQUIRE(raw.send(post_job_request(body)));
  std::string pending;
  return read_response(raw, pending, kHangGuard).status;
}

}  // namespace

TEST_CASE("seventy_polling_and_sixty_trickling_clients_leave_pause_resume_and_cancel_answered") {
  ServeDirs dirs("serve_load");
  Serve serve(dirs, {"--time-scale", "5"});
  REQUIRE(serve.upload("ring.gcode", ring_gcode(400), {{"print", "true"}})->status == 201);
  REQUIRE(serve.wait_state("Printing", kHangGuard));
  // 70 pollers from ten addresses (7 each, within an address's share) and 60 trickling clients
  // from six, beside the one that pauses and cancels.
  Load load(serve.port, addresses(70, 2, 10), addresses(60, 20, 6));
  REQUIRE(wait_for([&] { return load.established(3); }, kHangGuard));
  CHECK(control(serve.port, "127.0.0.1", {{"command", "pause"}, {"action", "pause"}}) == 204);
  REQUIRE(serve.wait_state("Paused", kHangGuard));
  CHECK(control(serve.port, "127.0.0.1", {{"command", "pause"}, {"action", "resume"}}) == 204);
  REQUIRE(serve.wait_state("Printing", kHangGuard));
  CHECK(control(serve.port, "127.0.0.1", {{"command", "cancel"}}) == 204);
  REQUIRE(wait_for([&] { return serve.get_json("/api/job")["mahost"]["jobState"] == "cancelled"; }, kHangGuard));
  // The trickling clients are cut off after the head time (10 s), however long they keep on.
  CHECK(wait_for([&] { return load.all_cut_off(); }, kHangGuard));
  load.stop();
  // Every poll was answered, and answered 200.
  const std::map<int, int> statuses = load.statuses();
  CHECK(statuses.size() == 1);
  CHECK(statuses.count(200) == 1);
  CHECK(load.served() == 70);
  // Each cut off with 408 and a log line.
  CHECK(serve.log().find("(no request) -> 408: the request's line and headers did not arrive within 10 s") !=
        std::string::npos);
  CHECK(serve.stop() == 0);
}

TEST_CASE("one_address_beyond_its_share_of_connections_is_refused_but_its_pause_and_cancel_are_served") {
  ServeDirs dirs("serve_share");
  Serve serve(dirs, {"--time-scale", "5"});
  REQUIRE(serve.upload("ring.gcode", ring_gcode(400), {{"print", "true"}})->status == 201);
  REQUIRE(serve.wait_state("Printing", kHangGuard));
  // 70 pollers from one address: its share (ConnectionLimits::per_address, 24) is served, the
  // rest refused; the pollers served keep their connections open.
  Load load(serve.port, addresses(70, 2, 1), {});
  REQUIRE(wait_for([&] { return load.established(3); }, kHangGuard));
  CHECK(load.served() == 24);
  CHECK(load.refused() == 70 - 24);
  CHECK(load.refusal().find("127.0.0.2 has 24 connections open to this server already") != std::string::npos);
  // From that address, beyond its share: the job's controls are served, a poll is not.
  CHECK(control(serve.port, "127.0.0.2", {{"command", "pause"}, {"action", "pause"}}) == 204);
  REQUIRE(serve.wait_state("Paused", kHangGuard));
  RawConnection raw(serve.port, "127.0.0.2");
  REQUIRE(raw.send(get_job_request()));
  std::string pending;
  CHECK(read_response(raw, pending, kHangGuard).status == 503);
  CHECK(control(serve.port, "127.0.0.2", {{"command", "cancel"}}) == 204);
  REQUIRE(wait_for([&] { return serve.get_json("/api/job")["mahost"]["jobState"] == "cancelled"; }, kHangGuard));
  load.stop();
  CHECK(serve.stop() == 0);
}

}  // namespace serve_load_test
