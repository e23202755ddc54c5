// The G-code writer (see gcode_writer.h). The program is generated once, by one run of the
// emitter whose every command goes both to a PrintClock, to learn the print time and each
// layer's start time, and to text held in memory, into which the header and the M73 progress
// lines, which need those times, are put at the end. The clock reads the very numbers the
// text says, so the estimate is exactly what re-reading the text gives. Not taken: two runs of
// the emitter side by side on two threads, one per sink, which end sooner on the wall clock
// but place and simplify every path twice: 70 M more instructions on the bunny's mid slice
// at 0.15 mm (1.3% of the slice, callgrind).
#include "printer/gcode_writer.h"

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <limits>
#include <string_view>

#include <fmt/core.h>
#include <fmt/format.h>

#include "printer/bead_model.h"
#include "printer/error.h"
#include "printer/firmware_dialect.h"
#include "printer/print_time.h"

namespace printer {

namespace {

using geometry::ExtrusionPath;
using geometry::LayerToolpaths;
using geometry::PathRole;
using geometry::Vec2;

// The integer nearest to `v`, halves to even, for |v| < 2^51: adding 1.5 * 2^52 leaves no
// fraction bits, so the sum is rounded to an integer (in the default rounding mode) and the
// difference back is exact.
double nearest_even(double v) {
  constexpr double kShift = 0x1.8p52;
  return (v + kShift) - kShift;
}

// std::round (halves away from zero) without its library call, the same double for every
// input: nearest_even, whose v - r is exact, moved away from zero where it is a half, with
// v's sign (std::round(-0.3) is -0). Beyond 2^51 (and NaN), std::round itself.
double round_half_away(double v) {
  if (!(std::abs(v) < 0x1p51)) return std::round(v);
  double r = nearest_even(v);
  if (std::abs(v - r) == 0.5) r = v + std::copysign(0.5, v);
  return std::copysign(r, v);
}

// The resolution written: what the firmware reads is what we time.
double round_to(double v, double unit) { return round_half_away(v / unit) * unit; }
double mm(double v) { return round_to(v, 1e-3); }
double filament_mm(double v) { return round_to(v, 1e-5); }
double per_minute(double mm_per_s) { return std::max(1.0, round_half_away(mm_per_s * 60)); }

// Room a number takes in the text at most: put_exact's 64 characters.
constexpr std::size_t kNumberRoom = 64;

constexpr char kDigitPairs[] =
    "00010203040506070809101112131415161718192021222324252627282930313233343536373839"
    "40414243444546474849505152535455565758596061626364656667686970717273747576777879"
    "8081828384858687888990919293949596979899";

// `units` of 10^-Decimals as fixed decimals without trailing zeros ("12.5", "0", "-0.8"),
// written at `p`; returns the end.
template <int Decimals>
char* put_units(char* p, std::int64_t units) {
  constexpr std::uint64_t kUnit = [] {
    std::uint64_t u = 1;
    for (int i = 0; i < Decimals; ++i) u *= 10;
    return u;
  }();
  std::uint64_t u = static_cast<std::uint64_t>(units);
  if (units < 0) {
    *p++ = '-';
    u = 0 - u;
  }
  p = std::to_chars(p, p + 20, u / kUnit).ptr;
  std::uint64_t fraction = u % kUnit;
  if (fraction == 0) return p;
  // All Decimals digits, two at a time from the right, then the trailing zeros taken off
  // (a digit is not zero, so the point stays).
  *p++ = '.';
  char* q = p + Decimals;
  char* const end = q;
  for (int i = 0; i + 1 < Decimals; i += 2, fraction /= 100) {
    q -= 2;
    std::memcpy(q, kDigitPairs + 2 * (fraction % 100), 2);
  }
  if (Decimals % 2 == 1) *--q = static_cast<char>('0' + fraction);
  char* last = end;
  while (last[-1] == '0') --last;
  return last;
}

// `v` as fmt's "{:.<decimals>f}" writes it, truncated to kNumberRoom characters, then
// without trailing zeros (nor a bare point) and "-0" as "0"; at `p`, returns the end.
char* put_exact(char* p, double v, int decimals) {
  const auto result = fmt::format_to_n(p, kNumberRoom, "{:.{}f}", v, decimals);
  std::size_t n = std::min(result.size, kNumberRoom);
  if (decimals > 0) {
    while (n > 0 && p[n - 1] == '0') --n;
    if (n > 0 && p[n - 1] == '.') --n;
  }
  if (n == 2 && p[0] == '-' && p[1] == '0') {
    p[0] = '0';
    n = 1;
  }
  return p + n;
}

// `v` with Decimals fixed decimals, shortest form (put_exact's text), at `p`; returns the end.
// Every number written is already rounded to its decimals (mm(), filament_mm(),
// per_minute()), so it is a whole count of units: written from the integer, a fraction of
// the instructions of formatting a double. It is the same text: with r = v * 10^Decimals
// exactly and |r| < 2^33, the product `scaled` is within half an ulp, 2^-21 < 5e-7, of r; a
// `scaled` more than 1e-6 from a half puts r less than 0.5 from `whole`, the integer nearest
// to `scaled`, so `whole` is the integer that correctly rounded decimal conversion (fmt)
// rounds r to. Values near a half, or larger, go to put_exact.
template <int Decimals>
char* put_number(char* p, double v) {
  constexpr double kScale = [] {
    double s = 1;
    for (int i = 0; i < Decimals; ++i) s *= 10;
    return s;
  }();
  const double scaled = v * kScale;
  if (std::abs(scaled) < 0x1p33) {
    const double whole = nearest_even(scaled);
    if (std::abs(std::abs(scaled - whole) - 0.5) > 1e-6) {
      return put_units<Decimals>(p, static_cast<std::int64_t>(whole));
    }
  }
  return put_exact(p, v, Decimals);
}

// Where the generated program goes: the clock, the text, or both (TeeSink).
class Sink {
 public:
  virtual ~Sink() = default;
  virtual void command(std::string_view line) = 0;  // any line the firmware reads
  virtual void comment(std::string_view text) = 0;  // ";text", ignored by the firmware
  virtual void move(int g, const MoveWords& words) = 0;
  virtual void layer_start(std::size_t layer, double z, double height) = 0;
};

class ClockSink final : public Sink {
 public:
  explicit ClockSink(const MotionLimits& limits) : clock_(limits) {}
  void command(std::string_view line) override {
    clock_.line(line);
    settle_layers();
  }
  void comment(std::string_view) override {}
  void move(int, const MoveWords& words) override {
    clock_.linear_move(words);
    settle_layers();
  }
  // A layer starts when the moves queued before it are done; the planner makes them final
  // a window later, so the time is taken then.
  void layer_start(std::size_t, double, double) override {
    layer_starts_.push_back(clock_.moves_queued());
    settle_layers();
  }

  double finish() {
    const double total = clock_.finish();
    settle_layers();
    return total;
  }
  const std::vector<double>& layer_times() const { return layer_times_; }

 private:
  void settle_layers() {
    while (layer_times_.size() < layer_starts_.size() &&
           clock_.moves_final() >= layer_starts_[layer_times_.size()]) {
      layer_times_.push_back(clock_.elapsed());
    }
  }

  PrintClock clock_;
  std::vector<std::size_t> layer_starts_;
  std::vector<double> layer_times_;
};

// The program's text, held in memory: each layer's M73 progress line needs the print time
// up to that layer and in all, which the clock fed the same commands learns only at the
// program's end. The places for them are kept, and write() puts them in.
class TextSink final : public Sink {
 public:
  void command(std::string_view line) override { write_line(line); }
  void comment(std::string_view text) override {
    buffer_.push_back(';');
    write_line(text);
  }
  // The line is written in place, into room made once for the longest it can be.
  void move(int g, const MoveWords& w) override {
    constexpr std::size_t kRoom = 2 + 5 * (2 + kNumberRoom) + 1;
    buffer_.reserve(buffer_.size() + kRoom);
    char* p = buffer_.data() + buffer_.size();
    *p++ = 'G';
    *p++ = g == 0 ? '0' : '1';
    p = word<3>(p, 'X', w.x);
    p = word<3>(p, 'Y', w.y);
    p = word<3>(p, 'Z', w.z);
    p = word<5>(p, 'E', w.e);
    p = word<0>(p, 'F', w.f);
    *p++ = '\n';
    buffer_.resize(static_cast<std::size_t>(p - buffer_.data()));
    ++lines_;
  }
  void layer_start(std::size_t layer, double z, double height) override {
    fmt::format_to(std::back_inserter(buffer_), ";LAYER:{}\n;Z:", layer);
    number<3>(z);
    // The layer's own thickness, as PrusaSlicer writes it: a stack may mix thicknesses.
    constexpr std::string_view kHeight = "\n;HEIGHT:";
    buffer_.append(kHeight.data(), kHeight.data() + kHeight.size());
    number<3>(height);
    ++lines_;
    end_line();
    if (!progress_lines_) return;
    progress_at_.push_back(buffer_.size());
    ++lines_;
  }
  // No M73 progress lines, for a firmware without M73.
  void without_progress_lines() { progress_lines_ = false; }

  void write_line(std::string_view line) {
    buffer_.append(line.data(), line.data() + line.size());
    end_line();
  }
  // Writes the text with layer k's progress line saying how much of `total_seconds` is done
  // when it starts (layer_times[k]; a layer past them: all). Returns the bytes written.
  std::size_t write(std::ostream& out, double total_seconds, const std::vector<double>& layer_times) {
    std::size_t from = 0, bytes = 0;
    auto put = [&](const char* data, std::size_t n) {
      out.write(data, static_cast<std::streamsize>(n));
      bytes += n;
    };
    for (std::size_t layer = 0; layer < progress_at_.size(); ++layer) {
      put(buffer_.data() + from, progress_at_[layer] - from);
      from = progress_at_[layer];
      const double at = layer < layer_times.size() ? layer_times[layer] : total_seconds;
      const int percent =
          total_seconds > 0 ? static_cast<int>(std::floor(100.0 * at / total_seconds)) : 0;
      const int minutes_left =
          static_cast<int>(std::ceil(std::max(0.0, total_seconds - at) / 60.0));
      char line[64];
      const auto written = fmt::format_to_n(line, sizeof line, "M73 P{} R{}\n",
                                            std::clamp(percent, 0, 100), minutes_left);
      put(line, std::min(written.size, sizeof line));
    }
    put(buffer_.data() + from, buffer_.size() - from);
    return bytes;
  }
  std::size_t lines() const { return lines_; }
  // Room for the program of `layers` at once: a move line is at most about 40 bytes, and a
  // buffer grown step by step would copy itself and hold half as much again unused. Pages
  // reserved and never written are not resident.
  void reserve(const std::vector<LayerToolpaths>& layers) {
    std::size_t points = 0;
    for (const LayerToolpaths& layer : layers) {
      for (const ExtrusionPath& path : layer.paths) points += path.points.size() + 4;
    }
    buffer_.reserve(48 * points + 256 * layers.size() + 4096);
    progress_at_.reserve(layers.size());
  }

 private:
  template <int Decimals>
  static char* word(char* p, char letter, const std::optional<double>& value) {
    if (!value) return p;
    *p++ = ' ';
    *p++ = letter;
    return put_number<Decimals>(p, *value);
  }
  template <int Decimals>
  void number(double v) {
    buffer_.reserve(buffer_.size() + kNumberRoom);
    char* const end = put_number<Decimals>(buffer_.data() + buffer_.size(), v);
    buffer_.resize(static_cast<std::size_t>(end - buffer_.data()));
  }
  void end_line() {
    buffer_.push_back('\n');
    ++lines_;
  }

  fmt::memory_buffer buffer_;
  std::vector<std::size_t> progress_at_;  // where each layer's M73 line goes
  bool progress_lines_ = true;
  std::size_t lines_ = 0;
};

// Both: each command to the clock, then to the text.
class TeeSink final : public Sink {
 public:
  TeeSink(Sink& first, Sink& second) : first_(first), second_(second) {}
  void command(std::string_view line) override {
    first_.command(line);
    second_.command(line);
  }
  void comment(std::string_view text) override {
    first_.comment(text);
    second_.comment(text);
  }
  void move(int g, const MoveWords& words) override {
    first_.move(g, words);
    second_.move(g, words);
  }
  void layer_start(std::size_t layer, double z, double height) override {
    first_.layer_start(layer, z, height);
    second_.layer_start(layer, z, height);
  }

 private:
  Sink& first_;
  Sink& second_;
};

double feature_speed(const FeatureSpeeds& s, PathRole role) {
  switch (role) {
    case PathRole::skirt: return s.skirt;
    case PathRole::outer_wall: return s.outer_wall;
    case PathRole::inner_wall: return s.inner_wall;
    case PathRole::thin_wall: return s.thin_wall;
    case PathRole::bottom_skin: return s.bottom_skin;
    case PathRole::top_skin: return s.top_skin;
    case PathRole::solid_infill: return s.solid_infill;
    case PathRole::sparse_infill: return s.sparse_infill;
    case PathRole::support: return s.support;
    case PathRole::support_interface: return s.support_interface;
    case PathRole::bridge: return s.bridge;
    case PathRole::brim: return s.brim;
    case PathRole::raft: return s.raft;
  }
  return s.outer_wall;
}

// The points of `path` to write: every point whose distance to the chord from the last kept
// point to the next candidate stays within `tolerance` for all points skipped is dropped.
// First and last points always stay; a tolerance of 0 keeps every distinct point.
std::vector<Vec2> simplify(const std::vector<Vec2>& path, double tolerance) {
  std::vector<Vec2> kept;
  kept.reserve(path.size());
  if (path.empty()) return kept;
  kept.push_back(path.front());
  std::size_t anchor = 0;
  for (std::size_t candidate = 2; candidate < path.size(); ++candidate) {
    const Vec2 a = path[anchor], b = path[candidate];
    bool fits = true;
    for (std::size_t i = anchor + 1; i < candidate && fits; ++i) {
      fits = geometry::distance_to_segment(path[i], a, b) <= tolerance;
    }
    if (!fits) {
      anchor = candidate - 1;
      kept.push_back(path[anchor]);
    }
  }
  if (path.size() > 1) kept.push_back(path.back());
  return kept;
}

// Splits a profile's G-code block into lines, dropping blank ones.
template <class F>
void for_each_line(std::string_view text, F&& f) {
  while (!text.empty()) {
    const std::size_t end = text.find('\n');
    std::string_view line = text.substr(0, end);
    while (!line.empty() && (line.back() == '\r' || line.back() == ' ')) line.remove_suffix(1);
    while (!line.empty() && line.front() == ' ') line.remove_prefix(1);
    if (!line.empty()) f(line);
    if (end == std::string_view::npos) break;
    text.remove_prefix(end + 1);
  }
}

// Whether a G-code block runs one of `codes` with a temperature (S or R): M104 S215 ; comment.
bool sets_temperature(std::string_view text, std::initializer_list<std::string_view> codes) {
  bool found = false;
  for_each_line(text, [&](std::string_view line) {
    line = line.substr(0, line.find(';'));
    for (const std::string_view code : codes) {
      if (!line.starts_with(code)) continue;
      const std::string_view rest = line.substr(code.size());
      if (!rest.empty() && rest.front() != ' ') continue;  // M1040 is not M104
      for (std::size_t i = 0; i + 1 < rest.size(); ++i) {
        if ((rest[i] == 'S' || rest[i] == 'R') && (i == 0 || rest[i - 1] == ' ')) found = true;
      }
    }
  });
  return found;
}

// Generates the program body into a sink; the same code for both runs.
class Emitter {
 public:
  Emitter(const Profiles& profiles, const GcodeOptions& options, Vec2 offset, Sink& sink)
      : printer_(profiles.printer), material_(profiles.material), profiles_(profiles),
        options_(options), offset_(offset), sink_(sink) {}

  void program(const std::vector<LayerToolpaths>& layers) {
    const MaterialProfile& m = material_;
    PlaceholderValues values = placeholder_values(layers);
    const std::string start = expand_placeholders(printer_.start_gcode, profiles_, values, "gcode.start");
    // A start G-code that sets a temperature itself (as PrusaSlicer's vendors' do) heats as it
    // says, and the writer leaves that heater to it (PrusaSlicer's GCode.cpp does the same).
    const bool start_heats_bed = sets_temperature(start, {"M140", "M190"});
    const bool start_heats_nozzle = sets_temperature(start, {"M104", "M109"});
    for (const std::string& line :
         heat_and_wait(printer_.firmware, start_heats_bed ? 0 : m.first_layer_bed_temperature,
                       start_heats_nozzle ? 0 : m.first_layer_nozzle_temperature)) {
      sink_.command(line);
    }
    sink_.comment("start G-code from the printer profile");
    for_each_line(start, [&](std::string_view line) { profile_line(line, "gcode.start"); });
    // G90 also resets Marlin's E to absolute, so the E mode comes after it.
    sink_.command("G90");
    sink_.command(printer_.relative_e ? "M83" : "M82");
    sink_.command("G92 E0");
    sink_.command(fan_off());

    for (std::size_t n = 0; n < layers.size(); ++n) {
      layer(n, layers[n]);
      if (on_layer_) on_layer_(n + 1);
    }

    sink_.command(fan_off());
    if (!layers.empty()) values.max_layer_z = mm(layers.back().z_hi);
    sink_.comment("end G-code from the printer profile");
    for_each_line(expand_placeholders(printer_.end_gcode, profiles_, values, "gcode.end"),
                  [&](std::string_view line) { profile_line(line, "gcode.end"); });
    if (dialect_of(printer_.firmware).has_m73) sink_.command("M73 P100 R0");
  }

  // What the slice tells the start and end G-code (the end's max_layer_z is set after the layers).
  PlaceholderValues placeholder_values(const std::vector<LayerToolpaths>& layers) const {
    PlaceholderValues values;
    values.layer_height = options_.layer_height;
    values.layer_count = layers.size();
    values.input_filename_base = options_.input_filename_base;
    if (!layers.empty()) {
      for (const ExtrusionPath& path : layers.front().paths) {
        if (path.points.size() < 2) continue;
        for (const Vec2& point : path.points) {
          const Vec2 q = place(point);
          if (values.first_layer_min_x > values.first_layer_max_x) {
            values.first_layer_min_x = values.first_layer_max_x = q.x;
            values.first_layer_min_y = values.first_layer_max_y = q.y;
          }
          values.first_layer_min_x = std::min(values.first_layer_min_x, q.x);
          values.first_layer_max_x = std::max(values.first_layer_max_x, q.x);
          values.first_layer_min_y = std::min(values.first_layer_min_y, q.y);
          values.first_layer_max_y = std::max(values.first_layer_max_y, q.y);
        }
      }
    }
    return values;
  }

  // What the profile's firmware turns the fan off with (Teacup has no M107).
  const char* fan_off() const { return dialect_of(printer_.firmware).has_m107 ? "M107" : "M106 S0"; }

  // A line of the profile's start or end G-code, as the profile's firmware takes it: the same,
  // its own equivalent (Teacup: M107 -> M106 S0, M109 -> M104 + M116), or refused with the
  // key, the line and what to do.
  void profile_line(std::string_view line, std::string_view key) {
    const std::size_t semicolon = line.find(';');
    std::string_view command = line.substr(0, semicolon);
    while (!command.empty() && command.back() == ' ') command.remove_suffix(1);
    if (command.empty()) {
      sink_.command(line);
      return;
    }
    const FirmwareCommand translated = for_firmware(printer_.firmware, command);
    if (translated.missing) {
      throw ConfigError(fmt::format(
          "the printer profile's {} has \"{}\", which {} does not have: remove it from the profile, "
          "or set firmware to the printer's (one of {})",
          key, command, dialect_of(printer_.firmware).display, firmware_names()));
    }
    if (translated.lines.size() == 1 && translated.lines.front() == command) {
      sink_.command(line);
      return;
    }
    for (const std::string& l : translated.lines) sink_.command(l);
  }

  double filament() const { return filament_; }
  double support_filament() const { return support_filament_; }
  void on_layer(LayersWritten f) { on_layer_ = std::move(f); }

 private:
  void layer(std::size_t n, const LayerToolpaths& toolpaths) {
    const double z = mm(toolpaths.z_hi);
    sink_.layer_start(n, z, mm(toolpaths.z_hi - toolpaths.z_lo));
    sink_.command("G92 E0");
    e_exact_ = 0;
    e_written_ = 0;
    if (n == 1) {
      if (material_.nozzle_temperature > 0 &&
          material_.nozzle_temperature != material_.first_layer_nozzle_temperature) {
        sink_.command(fmt::format("M104 S{:g}", material_.nozzle_temperature));
      }
      if (material_.bed_temperature > 0 &&
          material_.bed_temperature != material_.first_layer_bed_temperature) {
        sink_.command(fmt::format("M140 S{:g}", material_.bed_temperature));
      }
    }
    if (static_cast<int>(n) == material_.fan_start_layer && material_.fan_speed > 0) {
      sink_.command(fmt::format("M106 S{}", static_cast<int>(std::lround(material_.fan_speed * 2.55))));
      fan_ = fan_written_ = material_.fan_speed;
    }
    const double height = toolpaths.z_hi - toolpaths.z_lo;
    if (!(height > 0)) return;  // a layer without thickness lays nothing
    std::optional<PathRole> role;
    for (const ExtrusionPath& path : toolpaths.paths) {
      if (path.points.size() < 2) continue;
      if (!role || *role != path.role) {
        role = path.role;
        sink_.comment(fmt::format("TYPE:{}", geometry::role_name(path.role)));
      }
      const double width = path.width > 0 ? path.width
                           : n == 0       ? printer_.first_layer_width
                                          : printer_.extrusion_width;
      const double speed = n == 0 ? printer_.first_layer_speed : feature_speed(printer_.speed, path.role);
      // Bridges: the material's bridge flow and fan, the fan back after them.
      const bool bridge = path.role == geometry::PathRole::bridge;
      set_fan(bridge ? material_.bridge_fan : fan_);
      const double flow = bridge ? material_.bridge_flow : 1.0;
      placed_.clear();
      for (const Vec2& p : path.points) placed_.push_back(place(p));
      const std::vector<Vec2> points = simplify(placed_, printer_.resolution);
      travel_to(points.front(), z, path.retract_before);
      const double before = filament_;
      for (std::size_t i = 1; i < points.size(); ++i) extrude_to(points[i], width, height, speed, flow);
      if (geometry::is_support_role(path.role)) support_filament_ += filament_ - before;
    }
    set_fan(fan_);
  }

  // The part fan at `percent` unless it is there already (fan_off() for off).
  void set_fan(double percent) {
    if (percent == fan_written_) return;
    const int pwm = static_cast<int>(std::lround(percent * 2.55));
    sink_.command(pwm > 0 ? fmt::format("M106 S{}", pwm) : std::string(fan_off()));
    fan_written_ = percent;
  }

  Vec2 place(Vec2 p) const { return {mm(p.x + offset_.x), mm(p.y + offset_.y)}; }

  void set_feedrate(MoveWords& words, double mm_per_s) {
    const double f = per_minute(mm_per_s);
    if (f != feedrate_) {
      words.f = f;
      feedrate_ = f;
    }
  }

  std::optional<double> e_word(double e_exact) {
    const double written = filament_mm(e_exact);
    std::optional<double> word;
    if (printer_.relative_e) {
      word = filament_mm(written - e_written_);
    } else {
      word = written;
    }
    e_written_ = written;
    e_exact_ = e_exact;
    return word;
  }

  // Pulls the filament back before a travel (retract = true) or pushes it back after one.
  void set_retracted(bool retract) {
    const double length = printer_.retraction.length;
    if (!(length > 0) || retracted_ == retract) return;
    MoveWords words;
    words.e = e_word(e_exact_ + (retract ? -length : length));
    set_feedrate(words, retract ? printer_.retraction.speed : printer_.retraction.prime_speed);
    sink_.move(1, words);
    retracted_ = retract;
  }

  void move_z(double z) {
    if (z_known_ && z == z_) return;
    MoveWords words;
    words.z = z;
    set_feedrate(words, printer_.speed.z);
    sink_.move(1, words);
    z_ = z;
    z_known_ = true;
  }

  void travel_to(Vec2 p, double layer_z, bool retract) {
    const bool moves = !xy_known_ || !(p == xy_);
    const bool retracting = retract && moves && printer_.retraction.length > 0;
    if (retracting) set_retracted(true);
    const double hop = retracting ? printer_.retraction.z_hop : 0;
    // Up first (never drag the nozzle through the part), over, then down onto the layer.
    const double travel_z = mm(std::max(z_known_ ? z_ : layer_z, layer_z) + hop);
    move_z(travel_z);
    if (moves) {
      MoveWords words;
      words.x = p.x;
      words.y = p.y;
      set_feedrate(words, printer_.speed.travel);
      sink_.move(0, words);
      xy_ = p;
      xy_known_ = true;
    }
    move_z(layer_z);
    set_retracted(false);
  }

  void extrude_to(Vec2 p, double width, double height, double speed, double flow) {
    const double length = std::hypot(p.x - xy_.x, p.y - xy_.y);
    if (!(length > 0)) return;
    const double e = filament_for_bead(width, height, length, printer_.filament_diameter,
                                       material_.flow * flow);
    MoveWords words;
    words.x = p.x;
    words.y = p.y;
    words.e = e_word(e_exact_ + e);
    set_feedrate(words, speed);
    sink_.move(1, words);
    filament_ += e;
    xy_ = p;
  }

  const PrinterProfile& printer_;
  const MaterialProfile& material_;
  const Profiles& profiles_;
  const GcodeOptions& options_;
  Vec2 offset_;
  Sink& sink_;
  LayersWritten on_layer_;
  std::vector<Vec2> placed_;

  Vec2 xy_;
  bool xy_known_ = false;
  double z_ = 0;
  bool z_known_ = false;
  double feedrate_ = -1;  // mm/min as last written
  double e_exact_ = 0;    // E since the last G92 E0, unrounded
  double e_written_ = 0;  // E as last written (absolute value, rounded)
  bool retracted_ = false;
  double filament_ = 0;
  double support_filament_ = 0;  // of filament_, laid by support, support interface and raft
  double fan_ = 0;               // percent: the layer's fan (off until fan_start_layer)
  double fan_written_ = 0;       // percent, as last set in the program (M107 before layer 0)
};

// Refuses toolpaths that would leave the build volume once centred on the bed.
void check_build_volume(const std::vector<LayerToolpaths>& layers, const PrinterProfile& printer,
                        Vec2 offset) {
  double min_x = std::numeric_limits<double>::infinity(), min_y = min_x, top = 0;
  double max_x = -min_x, max_y = -min_x;
  for (const LayerToolpaths& layer : layers) {
    bool any = false;
    for (const ExtrusionPath& path : layer.paths) {
      if (path.points.size() < 2) continue;
      for (const Vec2& p : path.points) {
        min_x = std::min(min_x, p.x);
        max_x = std::max(max_x, p.x);
        min_y = std::min(min_y, p.y);
        max_y = std::max(max_y, p.y);
        any = true;
      }
    }
    if (any) top = std::max(top, layer.z_hi);
  }
  if (!(max_x >= min_x)) return;  // nothing to print
  constexpr double kTolerance = 1e-6;
  const double hop = travel_lift(printer);
  bool fits = on_bed(printer, min_x + offset.x, min_y + offset.y) &&
              on_bed(printer, max_x + offset.x, max_y + offset.y) && top + hop <= printer.bed_z + kTolerance;
  if (fits && printer.round_bed) {
    // The corners of the paths' box may lie off a round bed while every point is on it.
    for (const LayerToolpaths& layer : layers) {
      for (const ExtrusionPath& path : layer.paths) {
        for (const Vec2& p : path.points) fits = fits && on_bed(printer, p.x + offset.x, p.y + offset.y);
      }
    }
  }
  if (fits) return;
  throw ConfigError(fmt::format(
      "the toolpaths (part and skirt) span {:.1f} x {:.1f} x {:.1f} mm but the {} builds at most "
      "{:g} x {:g} x {:g} mm{}; scale the part down (--scale, --height), set a smaller "
      "print.skirt_distance, or choose a bigger printer (--printer)",
      max_x - min_x, max_y - min_y, top + hop, printer.name, printer.bed_x, printer.bed_y,
      printer.bed_z, printer.round_bed ? " (a round bed)" : ""));
}

void write_header(TextSink& text, const std::vector<LayerToolpaths>& layers, const Profiles& profiles,
                  const GcodeOptions& options, double seconds, double filament) {
  const PrinterProfile& p = profiles.printer;
  const MaterialProfile& m = profiles.material;
  const double grams = filament_weight(filament, p.filament_diameter, m.density);
  const double cm3 = filament * filament_area(p.filament_diameter) / 1000.0;
  // Cura's keys first: OctoPrint and printer screens read them.
  text.write_line(";FLAVOR:Marlin");
  text.write_line(fmt::format(";TIME:{:.0f}", std::round(seconds)));
  text.write_line(fmt::format(";Filament used: {:.5f}m", filament / 1000.0));
  text.write_line(fmt::format(";Layer height: {:g}", options.layer_height));
  text.write_line(fmt::format(";LAYER_COUNT:{}", layers.size()));
  text.write_line(";Generated with mahost (medial-axis contour slicing)");
  text.write_line(fmt::format("; printer: {} ({})", p.name, p.source));
  text.write_line(fmt::format("; material: {} ({}), {:g} C nozzle, {:g} C bed", m.name, m.source,
                              m.nozzle_temperature, m.bed_temperature));
  for (const std::string& note : options.notes) text.write_line("; " + note);
  text.write_line(fmt::format("; layers: {}", layers.size()));
  text.write_line(fmt::format("; estimated print time: {} (motion only, heating not counted)",
                              format_duration(seconds)));
  text.write_line(fmt::format(";PRINT_TIME_S:{:.3f}", seconds));
  text.write_line(fmt::format("; filament: {:.1f} mm, {:.2f} cm3, {:.2f} g", filament, cm3, grams));
  text.write_line(fmt::format(";FILAMENT_MM:{:.3f}", filament));
  text.write_line(fmt::format(";FILAMENT_G:{:.3f}", grams));
}

// What the clock's run of a program says of it: the summary but for the text's lines and bytes.
GcodeSummary clock_summary(std::size_t layers, double seconds, const Emitter& timing,
                           const ClockSink& clock, const Profiles& profiles) {
  GcodeSummary summary;
  summary.layers = layers;
  summary.print_seconds = seconds;
  summary.filament_mm = timing.filament();
  summary.support_filament_mm = timing.support_filament();
  summary.filament_grams = filament_weight(summary.filament_mm, profiles.printer.filament_diameter,
                                           profiles.material.density);
  summary.layer_starts = clock.layer_times();
  return summary;
}

}  // namespace

std::string format_duration(double seconds) {
  const long total = std::max(0L, std::lround(seconds));
  const long h = total / 3600, min = (total % 3600) / 60, s = total % 60;
  if (h > 0) return fmt::format("{} h {} min {} s", h, min, s);
  if (min > 0) return fmt::format("{} min {} s", min, s);
  return fmt::format("{} s", s);
}

GcodeSummary write_gcode(std::ostream& out, const std::vector<LayerToolpaths>& layers,
                         const Profiles& profiles, const GcodeOptions& options,
                         const LayersWritten& on_layer, const GcodeSummary* timed) {
  const Vec2 offset{bed_centre_x(profiles.printer), bed_centre_y(profiles.printer)};
  check_build_volume(layers, profiles.printer, offset);

  // One run: into the text alone where the clock ran already, else into both.
  TextSink body;
  body.reserve(layers);
  if (!dialect_of(profiles.printer.firmware).has_m73) body.without_progress_lines();
  ClockSink clock(profiles.printer.motion);
  TeeSink both(clock, body);
  Emitter writing(profiles, options, offset, timed ? static_cast<Sink&>(body) : both);
  writing.on_layer(on_layer);
  writing.program(layers);
  GcodeSummary summary = timed ? *timed : clock_summary(layers.size(), clock.finish(), writing, clock, profiles);

  TextSink header;
  write_header(header, layers, profiles, options, summary.print_seconds, summary.filament_mm);
  summary.lines = header.lines() + body.lines();
  summary.bytes = header.write(out, summary.print_seconds, {});
  summary.bytes += body.write(out, summary.print_seconds, summary.layer_starts);
  return summary;
}

GcodeSummary time_gcode(const std::vector<LayerToolpaths>& layers, const Profiles& profiles,
                        const GcodeOptions& options) {
  const Vec2 offset{bed_centre_x(profiles.printer), bed_centre_y(profiles.printer)};
  check_build_volume(layers, profiles.printer, offset);
  ClockSink clock(profiles.printer.motion);
  Emitter timing(profiles, options, offset, clock);
  timing.program(layers);
  const double seconds = clock.finish();
  return clock_summary(layers.size(), seconds, timing, clock, profiles);
}

GcodeSummary write_gcode_file(const std::string& path, const std::vector<LayerToolpaths>& layers,
                              const Profiles& profiles, const GcodeOptions& options,
                              const LayersWritten& on_layer, const GcodeSummary* timed) {
  // Written beside the target and renamed at the end: a refused or failed slice never leaves
  // a truncated program where a printer could pick it up, nor clobbers the previous one.
  const std::string partial = path + ".part";
  std::ofstream out(partial, std::ios::binary | std::ios::trunc);
  if (!out) {
    throw ConfigError(fmt::format("cannot write '{}': {}; check the folder exists and is writable",
                                  path, std::strerror(errno)));
  }
  GcodeSummary summary;
  try {
    summary = write_gcode(out, layers, profiles, options, on_layer, timed);
    out.close();
    if (!out) {
      throw ConfigError(fmt::format("writing '{}' failed (disk full?): {}", path,
                                    std::strerror(errno)));
    }
    if (std::rename(partial.c_str(), path.c_str()) != 0) {
      throw ConfigError(fmt::format("cannot write '{}': {}", path, std::strerror(errno)));
    }
  } catch (...) {
    out.close();
    std::remove(partial.c_str());
    throw;
  }
  return summary;
}

}  // namespace printer
