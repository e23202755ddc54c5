// The simulated firmware's command queue (Marlin's ring buffer of BUFSIZE commands,
// Marlin/src/gcode/queue.h): lines accepted from serial wait here; the front one is the
// command executing. While it is full the firmware reads no more serial input.
#pragma once

#include <cstdint>
#include <deque>
#include <optional>
#include <string>

namespace sim {

struct QueuedCommand {
  std::string text;                 // what the parser sees: "G1 X10 Y5"
  std::optional<long> line_number;  // the host's N, for ADVANCED_OK's "ok N<n>"
  std::uint64_t index = 0;          // 1-based count of accepted lines, for *-at-line faults
};

class CommandQueue {
 public:
  explicit CommandQueue(int depth) : depth_(depth < 1 ? 1 : depth) {}

  bool full() const { return static_cast<int>(commands_.size()) >= depth_; }
  bool empty() const { return commands_.empty(); }
  // Free slots, ADVANCED_OK's B.
  int free() const { return depth_ - static_cast<int>(commands_.size()); }

  void push(QueuedCommand command) { commands_.push_back(std::move(command)); }
  QueuedCommand& front() { return commands_.front(); }
  void pop() { commands_.pop_front(); }
  void clear() { commands_.clear(); }

 private:
  int depth_;
  std::deque<QueuedCommand> commands_;
};

}  // namespace sim
