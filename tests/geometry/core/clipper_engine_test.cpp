// The thread's reused Clipper engine (clipper_engine.h): empty and with default options on the
// way in, whatever the last use left, and another engine for a boolean inside a boolean.
#include <doctest/doctest.h>

#include <stdexcept>

#include "geometry/core/clipper_engine.h"

namespace clipper_engine_test {

using geometry::clipper::ReusedEngine;
using Paths = ClipperLib::Paths;

namespace {

const ClipperLib::Path kSquare{{0, 0}, {10, 0}, {10, 10}, {0, 10}};  // CCW
const ClipperLib::Path kShifted{{5, 0}, {15, 0}, {15, 10}, {5, 10}};

Paths union_of(ReusedEngine& engine, const Paths& paths) {
  engine->AddPaths(paths, ClipperLib::ptSubject, true);
  Paths result;
  engine->Execute(ClipperLib::ctUnion, result, ClipperLib::pftNonZero, ClipperLib::pftNonZero);
  return result;
}

}  // namespace

TEST_CASE("reused_engine_starts_empty_with_default_options") {
  {
    ReusedEngine engine;
    engine->AddPath(kShifted, ClipperLib::ptSubject, true);
    engine->ReverseSolution(true);
    engine->StrictlySimple(true);
    engine->PreserveCollinear(true);
  }
  ReusedEngine engine;
  CHECK(!engine->ReverseSolution());
  CHECK(!engine->StrictlySimple());
  CHECK(!engine->PreserveCollinear());
  const Paths result = union_of(engine, {kSquare});
  REQUIRE(result.size() == 1);
  CHECK(ClipperLib::Area(result[0]) == 100);
}

TEST_CASE("reused_engine_inside_another_is_an_engine_of_its_own") {
  ReusedEngine outer;
  outer->AddPath(kSquare, ClipperLib::ptSubject, true);
  {
    ReusedEngine inner;
    CHECK(&*inner != &*outer);
    const Paths result = union_of(inner, {kShifted});
    REQUIRE(result.size() == 1);
    CHECK(ClipperLib::Area(result[0]) == 100);
  }
  const Paths result = union_of(outer, {});
  REQUIRE(result.size() == 1);
  CHECK(ClipperLib::Area(result[0]) == 100);
  const ClipperLib::IntRect box = outer->GetBounds();
  CHECK(box.left == 0);
  CHECK(box.right == 10);
}

TEST_CASE("reused_engine_left_by_an_exception_starts_anew") {
  try {
    ReusedEngine engine;
    engine->AddPath(kShifted, ClipperLib::ptSubject, true);
    throw std::runtime_error("out of the boolean");
  } catch (const std::runtime_error&) {
  }
  ReusedEngine engine;
  const Paths result = union_of(engine, {kSquare});
  REQUIRE(result.size() == 1);
  CHECK(ClipperLib::Area(result[0]) == 100);
}

}  // namespace clipper_engine_test
