// A Clipper engine for one boolean, this thread's reused from call to call: a fresh engine
// grows its vectors (local minima, edges, output records, intersections) again each time, and
// the slice runs tens of thousands of booleans. For clipper.cpp and clipper_offset.cpp.
#pragma once

#include <exception>
#include <optional>

#include <polyclipping/clipper.hpp>

namespace geometry::clipper {

// Empty and with Clipper's default options on the way in and out. The thread's engine where it
// is free, else (a boolean run while another holds it) one of its own; an exception on the way
// out leaves the thread's engine to be made anew, whatever state Clipper left it in.
class ReusedEngine {
 public:
  ReusedEngine() {
    if (busy_) {
      engine_ = &own_.emplace();
      return;
    }
    busy_ = true;
    if (!shared_) shared_.emplace();
    engine_ = &*shared_;
  }
  ~ReusedEngine() {
    if (own_) return;
    if (std::uncaught_exceptions() > exceptions_) {
      shared_.reset();
    } else {
      shared_->Clear();
      shared_->ReverseSolution(false);
      shared_->StrictlySimple(false);
      shared_->PreserveCollinear(false);
    }
    busy_ = false;
  }
  ReusedEngine(const ReusedEngine&) = delete;
  ReusedEngine& operator=(const ReusedEngine&) = delete;

  ClipperLib::Clipper& operator*() { return *engine_; }
  ClipperLib::Clipper* operator->() { return engine_; }

 private:
  static inline thread_local std::optional<ClipperLib::Clipper> shared_;
  static inline thread_local bool busy_ = false;
  std::optional<ClipperLib::Clipper> own_;
  ClipperLib::Clipper* engine_ = nullptr;
  int exceptions_ = std::uncaught_exceptions();
};

}  // namespace geometry::clipper
