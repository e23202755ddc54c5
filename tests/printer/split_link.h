// A printer::Link that cuts the replies of another at a chosen byte: everything up to the
// byte numbered `cut` (counted from the first byte the link ever read, from 0) comes in one
// read, the rest in the next. Tests run a job once for every cut around a reply, so that no
// reply is handled only when it happens to arrive whole, or together with the next one.
#pragma once

#include <string>
#include <utility>

#include "printer/link.h"

namespace test_support {

class SplitLink : public printer::Link {
 public:
  SplitLink(printer::Link& inner, std::size_t cut) : inner_(inner), cut_(cut) {}

  void write(std::string_view bytes) override { inner_.write(bytes); }
  std::string read(std::chrono::milliseconds timeout) override {
    std::string bytes = held_.empty() ? inner_.read(timeout) : std::exchange(held_, std::string());
    if (read_ < cut_ && read_ + bytes.size() > cut_) {
      held_ = bytes.substr(cut_ - read_);
      bytes.resize(cut_ - read_);
    }
    read_ += bytes.size();
    log_ += bytes;
    return bytes;
  }
  std::chrono::nanoseconds now() const override { return inner_.now(); }
  std::string name() const override { return inner_.name(); }

  // Every byte read so far, in order.
  const std::string& log() const { return log_; }

 private:
  printer::Link& inner_;
  std::size_t cut_;
  std::size_t read_ = 0;
  std::string held_;
  std::string log_;
};

}  // namespace test_support
