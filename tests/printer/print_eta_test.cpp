// The job's remaining time (print_eta.h) against the simulated printer's clock: it follows
// motion time rather than the share of lines sent, takes the pace the printer really keeps,
// and leaves heat-up, homing and pauses out. Everything runs on the sim clock, so it is exact and
// independent of the machine's speed.
#include "printer/print_eta.h"

#include <cmath>
#include <string>
#include <vector>

#include <doctest/doctest.h>
#include <fmt/core.h>

#include "printer/job.h"
#include "printer/print_time.h"
#include "printer/test_program.h"
#include "sim/sim_link.h"

namespace print_eta_test {

using namespace printer;

namespace {

double seconds(std::chrono::nanoseconds t) { return std::chrono::duration<double>(t).count(); }

// What the progress line showed at one tick of the job.
struct Tick {
  double elapsed = 0, remaining = 0, fraction = 0;
  std::size_t done = 0;
  JobState state = JobState::printing;
};

struct TimedPrint {
  std::vector<Tick> ticks;
  double total = 0;       // from the job's start until the last move ran out, s
  double estimate = 0;    // the model's time for the file, s
};

TimedPrint timed_print(const GcodeFile& file, const sim::Config& config, JobOptions options,
                       const std::function<void(Job&)>& steer = {}) {
  sim::SimLink link(config);
  LineProtocol protocol(link);
  protocol.connect();
  Job job(protocol, file, std::move(options));
  TimedPrint timed;
  job.on_tick = [&](Job& j) {
    const JobProgress p = j.progress();
    REQUIRE(p.remaining);
    timed.ticks.push_back({seconds(p.elapsed), seconds(*p.remaining), p.fraction, p.commands_done, p.state});
    if (steer) steer(j);
  };
  const double start = seconds(link.now());
  const JobResult result = job.run();
  REQUIRE(result.state == JobState::completed);
  link.printer().finish();
  timed.total = std::max(seconds(result.elapsed), link.printer().motion_end_time() - start);
  timed.estimate = job.estimated_seconds();
  return timed;
}

// Heating as a slicer writes it, then `layers` of whatever `layer` writes.
template <class Layer>
std::string program(int layers, Layer&& layer) {
  std::string g = "M140 S60\nM104 S210\nM190 S60\nM109 S210\nG28\nG90\nM82\n";
  for (int i = 0; i < layers; ++i) {
    g += fmt::format(";LAYER:{}\n;Z:{:.2f}\nG92 E0\nG1 Z{:.2f} F600\n", i, 0.2 * (i + 1), 0.2 * (i + 1));
    g += layer(i);
  }
  return g + "M104 S0\nM140 S0\nM84\n";
}

// A circle of many short moves: many lines, little time.
std::string dense_layer() {
  std::string g = "G0 X110 Y100 F6000\n";
  double e = 0;
  for (int k = 1; k <= 400; ++k) {
    const double a = 2 * std::acos(-1.0) * k / 400;
    e += 0.003;
    g += fmt::format("G1 X{:.3f} Y{:.3f} E{:.4f} F1800\n", 100 + 10 * std::cos(a), 100 + 10 * std::sin(a), e);
  }
  return g;
}

// A square of 64 moves of 10 mm at 20 mm/s: few lines, much time (half a second a line).
std::string sparse_layer() {
  std::string g = "G0 X20 Y20 F6000\n";
  const double corners[5][2] = {{20, 20}, {180, 20}, {180, 180}, {20, 180}, {20, 20}};
  double e = 0;
  for (int side = 0; side < 4; ++side) {
    for (int k = 1; k <= 16; ++k) {
      const double x = corners[side][0] + (corners[side + 1][0] - corners[side][0]) * k / 16;
      const double y = corners[side][1] + (corners[side + 1][1] - corners[side][1]) * k / 16;
      e += 0.33;
      g += fmt::format("G1 X{:.1f} Y{:.1f} E{:.2f} F1200\n", x, y, e);
    }
  }
  return g;
}

}  // namespace

TEST_CASE("eta_model_time_is_the_print_time_estimate_command_by_command") {
  const std::string text = test_support::ring_program(20, 50);
  const GcodeFile file = parse_gcode(text, "ring.gcode");
  MotionLimits limits;
  limits.print_acceleration = 700;
  PrintEta eta(file, limits);
  eta.work(0);
  REQUIRE(file.size() < kGcodeBlock);  // one block: every command's time known at once
  CHECK(*eta.at(0) == 0);
  CHECK(*eta.total() == doctest::Approx(estimate_print_time(text, limits)).epsilon(1e-6));
  CHECK(eta.at(file.size()) == eta.total());
  bool rising = true;
  for (std::size_t i = 1; i <= file.size(); ++i) rising = rising && *eta.at(i) >= *eta.at(i - 1);
  CHECK(rising);
  CHECK(eta.fraction(0) == 0);
  CHECK(eta.fraction(file.size()) == 1);
  // Before the pace is measured, the remaining time is the model's alone.
  CHECK(*eta.remaining(file.size() / 2, 1e6, 1e6) ==
        doctest::Approx(*eta.total() - *eta.at(file.size() / 2)));
}

TEST_CASE("eta_follows_motion_time_not_the_share_of_lines") {
  // Ten layers of dense short moves, then ten of long slow ones: half the lines are sent in
  // a small part of the time.
  const GcodeFile file = parse_gcode(
      program(20, [](int i) { return i < 10 ? dense_layer() : sparse_layer(); }), "mixed.gcode");
  const TimedPrint timed = timed_print(file, sim::Config{}, {});
  // The sim runs the same motion model as the estimate; only the heat-up is extra.
  CHECK(timed.total > timed.estimate);
  int checked = 0;
  double worst = 0, line_share_worst = 0;
  for (const Tick& t : timed.ticks) {
    if (t.fraction < 0.05 || t.fraction > 0.95) continue;
    ++checked;
    worst = std::max(worst, std::abs(t.elapsed + t.remaining - timed.total) / timed.total);
    // The ETA by the share of lines sent (the time so far over that share), which this
    // test shows to be far off.
    const double by_lines = t.elapsed * static_cast<double>(file.size()) / static_cast<double>(t.done);
    line_share_worst = std::max(line_share_worst, std::abs(by_lines - timed.total) / timed.total);
  }
  CHECK(checked > 100);
  CHECK(worst < 0.01);
  CHECK(line_share_worst > 0.3);  // the case this test exists for
  MESSAGE("predicted end within " << worst * 100 << "% (by the share of lines: "
                                  << line_share_worst * 100 << "%)");
}

TEST_CASE("eta_takes_the_pace_of_a_printer_slower_than_its_model") {
  // The profile's limits are not the firmware's: the model is off by a factor, the pace
  // measured since the first layer corrects it.
  const GcodeFile file = parse_gcode(test_support::ring_program(60, 100), "ring.gcode");
  sim::Config slow;  // the firmware caps X and Y at 15 mm/s; the profile says 300
  slow.motion.max_speed = {15, 15, 10, 60};
  const TimedPrint timed = timed_print(file, slow, {});
  const double model = timed.estimate;
  double worst = 0;
  int checked = 0;
  for (const Tick& t : timed.ticks) {
    if (t.fraction < 0.3) continue;  // the pace is measured over a minute of model time
    ++checked;
    worst = std::max(worst, std::abs(t.elapsed + t.remaining - timed.total) / timed.total);
  }
  CHECK(checked > 50);
  CHECK(worst < 0.01);
  // Uncorrected, the model would be off by far more: the printer is slower than it says.
  double motion = 0;
  {
    sim::SimLink link(slow);
    LineProtocol protocol(link);
    protocol.connect();
    Job job(protocol, file, {});
    REQUIRE(job.run().state == JobState::completed);
    link.printer().finish();
    motion = link.printer().motion_time();
  }
  CHECK(motion > 1.5 * model);
  MESSAGE("model " << model << " s of motion, printer " << motion << " s; predicted end within "
                   << worst * 100 << "%");
}

TEST_CASE("eta_stands_still_while_paused_and_leaves_the_pause_out") {
  const GcodeFile file = parse_gcode(test_support::ring_program(30, 60), "ring.gcode");
  JobOptions options;
  options.pause_at_layers = {12};
  double paused_at = -1;
  const TimedPrint timed = timed_print(file, sim::Config{}, options, [&](Job& job) {
    const JobProgress p = job.progress();
    if (p.state != JobState::paused) return;
    if (paused_at < 0) paused_at = seconds(p.elapsed);
    if (seconds(p.elapsed) > paused_at + 600) job.request(JobRequest::resume);  // ten minutes
  });
  REQUIRE(paused_at > 0);
  std::vector<double> while_paused;
  double worst_after = 0;
  bool resumed = false;
  for (const Tick& t : timed.ticks) {
    if (t.state == JobState::paused) while_paused.push_back(t.remaining);
    if (!while_paused.empty() && t.state == JobState::printing) resumed = true;
    if (resumed && t.fraction < 0.95) {
      worst_after = std::max(worst_after, std::abs(t.elapsed + t.remaining - timed.total) / timed.total);
    }
  }
  REQUIRE(while_paused.size() > 100);
  CHECK(while_paused.front() == doctest::Approx(while_paused.back()).epsilon(1e-9));
  CHECK(resumed);
  CHECK(worst_after < 0.01);
  MESSAGE("after the pause, predicted end within " << worst_after * 100 << "%");
}

}  // namespace print_eta_test
