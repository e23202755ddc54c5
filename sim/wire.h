// The serial wire of the simulated printer, both ways (sim/printer.h): bytes take 10 bits each
// at the baud rate, so a reply or a line arrives when its last byte does.
//
// HostWire: the bytes the host sent, on their way to the firmware. Byte k of a write sent at t
// arrives at max(t, the wire's end) + (k + 1) * byte_time. With Marlin's EMERGENCY_PARSER the
// serial interrupt sees every byte as it arrives, before any buffer; the wire notes which byte
// completes an M108, M112 or M410, so the firmware acts on it the moment it arrives.
// ReplyWire: the firmware's replies on their way to the host, in order, each line arriving
// when its last byte does (never before the one ahead of it).
// Times are sim seconds; baud 0 makes bytes take no time.
#pragma once

#include <cstddef>
#include <cstdint>
#include <deque>
#include <limits>
#include <optional>
#include <string>

#include "sim/serial_line.h"

namespace sim {

class HostWire {
 public:
  explicit HostWire(double baud = 0);

  double byte_time() const { return byte_time_; }
  // Puts bytes on the wire at `now`, after those still on it. With `emergency_parser` the
  // bytes are watched for M108, M112 and M410.
  void send(double now, std::string bytes, bool emergency_parser);
  // Everything on the wire is lost (a reset, a disconnect); `now` is where the wire restarts.
  void clear(double now);
  // Counts clear() calls: a byte's delivery can end the link, and the caller must then stop.
  std::uint64_t clears() const { return clears_; }

  // The next byte that has arrived by `now`, if any, without taking it; `emergency` is what
  // that byte completes (Emergency::none for nearly all).
  struct Arrived {
    char byte = 0;
    Emergency emergency = Emergency::none;
  };
  std::optional<Arrived> peek(double now) const;
  // Takes the byte peek() showed.
  void pop();

  bool empty() const { return chunks_.empty(); }
  // When the next line end arrives (the firmware reads a line then); +infinity for none.
  double next_line_end() const;
  // When the next emergency command completes; +infinity for none.
  double next_emergency() const;

 private:
  struct Chunk {
    double start = 0;
    std::string bytes;
    std::size_t next = 0;
  };
  struct PendingEmergency {
    double at = 0;
    std::uint64_t byte = 0;  // sequence number of the byte that completes it
    Emergency kind = Emergency::none;
  };
  double arrival(const Chunk& chunk, std::size_t k) const {
    return chunk.start + byte_time_ * static_cast<double>(k + 1);
  }

  double byte_time_ = 0;
  std::deque<Chunk> chunks_;
  std::deque<PendingEmergency> emergencies_;
  EmergencyParser emergency_parser_;
  double free_at_ = 0;  // when the last byte sent so far arrives
  std::uint64_t bytes_sent_ = 0, bytes_taken_ = 0;  // sequence numbers
  std::uint64_t clears_ = 0;
};

class ReplyWire {
 public:
  explicit ReplyWire(double baud = 0);

  // A reply line (without its line end) leaving at `at`; returns the bytes it took, line end
  // included.
  std::size_t send(double at, std::string text);
  // Whether a reply has reached the host by `now`.
  bool ready(double now) const { return !replies_.empty() && replies_.front().at <= now; }
  // The replies that reached the host by `now`, oldest first.
  std::string take(double now);
  // When the next reply reaches the host; +infinity for none.
  double next_arrival() const;
  void clear(double now);

 private:
  struct Reply {
    double at = 0;  // when its last byte reaches the host
    std::string text;
  };
  double byte_time_ = 0;
  std::deque<Reply> replies_;
  double free_at_ = 0;
};

}  // namespace sim
