#include "sim/wire.h"

#include <algorithm>
#include <cmath>

namespace sim {

namespace {
constexpr double kInfinity = std::numeric_limits<double>::infinity();
}  // namespace

HostWire::HostWire(double baud) : byte_time_(baud > 0 ? 10.0 / baud : 0.0) {}

void HostWire::send(double now, std::string bytes, bool emergency_parser) {
  if (bytes.empty()) return;
  Chunk chunk;
  chunk.start = std::max(now, free_at_);
  chunk.bytes = std::move(bytes);
  if (emergency_parser) {
    for (std::size_t k = 0; k < chunk.bytes.size(); ++k) {
      const Emergency e = emergency_parser_.update(chunk.bytes[k]);
      if (e != Emergency::none) emergencies_.push_back({arrival(chunk, k), bytes_sent_ + k, e});
    }
  }
  free_at_ = chunk.start + byte_time_ * static_cast<double>(chunk.bytes.size());
  bytes_sent_ += chunk.bytes.size();
  chunks_.push_back(std::move(chunk));
}

void HostWire::clear(double now) {
  chunks_.clear();
  emergencies_.clear();
  emergency_parser_ = EmergencyParser{};
  bytes_taken_ = bytes_sent_;
  free_at_ = now;
  ++clears_;
}

std::optional<HostWire::Arrived> HostWire::peek(double now) const {
  if (chunks_.empty()) return std::nullopt;
  const Chunk& chunk = chunks_.front();
  // The same arithmetic as next_line_end(): the firmware's clock, set to a byte's arrival
  // time, finds that byte arrived (dividing by the byte time instead would round it away
  // after hours of sim time, and the sim would wait for it for ever).
  if (chunk.next >= chunk.bytes.size() || arrival(chunk, chunk.next) > now) return std::nullopt;
  Arrived arrived{chunk.bytes[chunk.next], Emergency::none};
  if (!emergencies_.empty() && emergencies_.front().byte == bytes_taken_) {
    arrived.emergency = emergencies_.front().kind;
  }
  return arrived;
}

void HostWire::pop() {
  if (chunks_.empty()) return;
  if (!emergencies_.empty() && emergencies_.front().byte == bytes_taken_) emergencies_.pop_front();
  ++bytes_taken_;
  Chunk& chunk = chunks_.front();
  if (++chunk.next >= chunk.bytes.size()) chunks_.pop_front();
}

double HostWire::next_line_end() const {
  for (const Chunk& chunk : chunks_) {
    for (std::size_t k = chunk.next; k < chunk.bytes.size(); ++k) {
      if (is_line_end(chunk.bytes[k])) return arrival(chunk, k);
    }
  }
  return kInfinity;
}

double HostWire::next_emergency() const {
  return emergencies_.empty() ? kInfinity : emergencies_.front().at;
}

ReplyWire::ReplyWire(double baud) : byte_time_(baud > 0 ? 10.0 / baud : 0.0) {}

std::size_t ReplyWire::send(double at, std::string text) {
  text += '\n';
  if (byte_time_ > 0) at = std::max(at, free_at_) + byte_time_ * static_cast<double>(text.size());
  if (!replies_.empty()) at = std::max(at, replies_.back().at);
  free_at_ = at;
  const std::size_t size = text.size();
  replies_.push_back(Reply{at, std::move(text)});
  return size;
}

std::string ReplyWire::take(double now) {
  std::string text;
  while (ready(now)) {
    text += replies_.front().text;
    replies_.pop_front();
  }
  return text;
}

double ReplyWire::next_arrival() const {
  return replies_.empty() ? kInfinity : replies_.front().at;
}

void ReplyWire::clear(double now) {
  replies_.clear();
  free_at_ = now;
}

}  // namespace sim
