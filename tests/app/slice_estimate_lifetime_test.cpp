// app::slice called in-process: a slice that fails after planning (a serve slice cancelled
// at shutdown) leaves no background estimate writing into the unwound call. Built as its own
// executable (tests/CMakeLists.txt) with the linker's --wrap on app::sample_layers, so the test decides when the estimate at about the plan's layer count
// starts and when it returns; run under ASan (scripts/build asan) it reports the write of a
// sample into a destroyed result as stack-use-after-scope.
#include <atomic>
#include <cmath>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include <doctest/doctest.h>
#include <tbb/global_control.h>
#include <tbb/task_arena.h>
#include <tbb/task_group.h>

#include "geometry/mesh/stl_io.h"
#include "app/layer_choice.h"
#include "app/slice.h"
#include "app/uniform_estimate.h"
#include "printer/profile.h"
#include "support/run_command.h"
#include "support/solids.h"

namespace slice_estimate_lifetime_test {

namespace {

// The estimate samples (app/uniform_estimate.h) started so far, and whether the one at about
// the plan's count (any layer thickness but the thinnest) has started.
std::atomic<int> samples_started{0};
std::atomic<bool> same_count_started{false};
double thinnest_layer = 0;  // mm, set before the slice starts

}  // namespace

}  // namespace slice_estimate_lifetime_test

// The real app::sample_layers, and the wrapper every call from app/slice.cpp reaches
// (-Wl,--wrap=<its mangled name>, tests/CMakeLists.txt).
app::LayerSample real_sample_layers(const geometry::LayerStack& index,
                                     const std::vector<geometry::Layer>& layers,
                                     const printer::Profiles& profiles)
    __asm__("__real__ZN3app13sample_layersERKN8geometry10LayerStackERKSt6vectorINS0_"
            "5LayerESaIS5_EERKN7printer8ProfilesE");
app::LayerSample wrapped_sample_layers(const geometry::LayerStack& index,
                                        const std::vector<geometry::Layer>& layers,
                                        const printer::Profiles& profiles)
    __asm__("__wrap__ZN3app13sample_layersERKN8geometry10LayerStackERKSt6vectorINS0_"
            "5LayerESaIS5_EERKN7printer8ProfilesE");

app::LayerSample wrapped_sample_layers(const geometry::LayerStack& index,
                                        const std::vector<geometry::Layer>& layers,
                                        const printer::Profiles& profiles) {
  using namespace slice_estimate_lifetime_test;
  ++samples_started;
  const bool same_count =
      layers.size() > 1 && std::abs(layers[1].thickness() - thinnest_layer) > 1e-9;
  if (same_count) {
    same_count_started = true;
    same_count_started.notify_all();
  }
  app::LayerSample sample = real_sample_layers(index, layers, profiles);
  // The sample at about the plan's count returns only once the slice has given up on it
  // (its task group cancelled, on the way out of the failed slice): its result is written
  // while the slice unwinds.
  while (same_count && !tbb::is_current_task_group_canceling()) std::this_thread::yield();
  return sample;
}

namespace slice_estimate_lifetime_test {

TEST_CASE("slice_failing_after_planning_joins_its_estimates_before_their_results_go") {
  const std::string dir = test_support::scratch_dir("slice_failing_after_planning");
  // A cone: the adaptive plan mixes thicknesses, so both uniform samples are taken.
  const std::string model = dir + "/cone.stl";
  geometry::write_stl_binary(model, solids::cone(15, 20, 48).mesh);

  app::SliceOptions options;
  options.model.path = model;
  options.adaptive.adaptive = true;
  options.contour = "mid";
  const printer::PrinterProfile machine = printer::load_printer_profile(
      options.printer, printer::config_directory(MAHOST_SOURCE_DIR "/configs"));
  thinnest_layer = app::allowed_thicknesses(machine).thinnest();
  REQUIRE(thinnest_layer > 0);

  // Two threads whatever the machine: the slice's and one for the estimates beside it.
  tbb::global_control threads(tbb::global_control::max_allowed_parallelism, 2);
  tbb::task_arena arena(2);
  app::SliceEvents fail_after_planning;
  fail_after_planning.progress = [](app::SliceStage stage, std::size_t done, std::size_t) {
    if (stage != app::SliceStage::contours || done != 0) return;
    // The plan is made and the second sample started beside it: the slice fails here.
    same_count_started.wait(false);
    throw std::runtime_error("cancelled after planning");
  };
  arena.execute([&] {
    CHECK_THROWS_WITH_AS(app::slice(options, dir + "/cone.gcode", fail_after_planning),
                         "cancelled after planning", std::runtime_error);
  });
  CHECK(samples_started == 2);
}

}  // namespace slice_estimate_lifetime_test
