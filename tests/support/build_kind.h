// Which build the tests run in, for the few tests too slow for the sanitizer build.
//
// A test that takes more than about 30 s in the release build would take many minutes under
// ASan/UBSan (scripts/test runs ctest in both builds, on 2 cores, within 30 minutes in all), so
// it runs in the release build only:
//   TEST_CASE("bunny_prints_..." * test_support::release_build_only()) { ... }
// In the sanitizer build (CMake option MAHOST_SANITIZE, which defines MAHOST_SANITIZED_BUILD
// for the tests) doctest skips it; ctest still lists it and reports it passed, with doctest's
// "1 skipped" in its output.
#pragma once

#include <doctest/doctest.h>

namespace test_support {

#ifdef MAHOST_SANITIZED_BUILD
inline constexpr bool kSanitizedBuild = true;
#else
inline constexpr bool kSanitizedBuild = false;
#endif

inline doctest::skip release_build_only() { return doctest::skip(kSanitizedBuild); }

}  // namespace test_support
