// The benchmarks' common entry: `--help` (or -h) points at the usage comment at the top of
// the benchmark's source file, and an exception ends the run with its message and exit code
// 2 instead of std::terminate. Each benchmark defines `static int run_bench(int argc, char**
// argv)` and ends with
//   int main(int argc, char** argv) { return bench::main(argc, argv, run_bench); }
#pragma once

#include <cstdio>
#include <exception>
#include <filesystem>
#include <string_view>

namespace bench {

template <class Run>
int main(int argc, char** argv, Run run) {
  const std::string name = std::filesystem::path(argc > 0 ? argv[0] : "bench").filename().string();
  for (int i = 1; i < argc; ++i) {
    const std::string_view arg = argv[i];
    if (arg == "--help" || arg == "-h") {
      std::printf("%s: a benchmark, run by hand; its usage is the comment at the top of "
                  "tests/bench/%s.cpp\n",
                  name.c_str(), name.c_str());
      return 0;
    }
  }
  try {
    return run(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: %s\n", name.c_str(), e.what());
    return 2;
  }
}

}  // namespace bench
