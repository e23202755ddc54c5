// G-code read as Marlin runs it; see gcode_interpreter.h for each rule's source.
#include "printer/gcode_interpreter.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <numbers>
#include <string_view>

namespace printer {

namespace {

constexpr double kInch = 25.4;  // mm

// Marlin 2.1's arc defaults (Configuration_adv.h; G2_G3.cpp).
constexpr double kMinArcSegment = 0.1;  // mm, MIN_ARC_SEGMENT_MM
constexpr double kMaxArcSegment = 1.0;  // mm, MAX_ARC_SEGMENT_MM
constexpr int kMinCircleSegments = 72;  // MIN_CIRCLE_SEGMENTS
constexpr int kArcCorrection = 25;      // N_ARC_CORRECTION: every 25th chord end exact
constexpr double kTurn = 2 * std::numbers::pi;

void add_motion(GcodeStep& step, const AxisPosition& from, const AxisPosition& to,
                double feedrate) {
  step.motions[step.count++] = {from, to, feedrate};
}

// G28: the axes it homes to 0.
void home(GcodeState& s, const GcodeCommand& c, GcodeStep& step) {
  const auto [x, y, z] = homed_axes(c);
  if (x) s.x = 0;
  if (y) s.y = 0;
  if (z) s.z = 0;
  s.homed = true;
  step.homed = step.position_set = true;
}

// G92: each axis given to its value (in the current units); E directly. With Teacup's rule
// a bare axis is 0, and no axis at all is all four at 0.
void set_position(GcodeState& s, const GcodeCommand& c, GcodeStep& step) {
  const bool no_axis = !c.has('X') && !c.has('Y') && !c.has('Z') && !c.has('E');
  const auto value = [&](char axis) -> std::optional<double> {
    if (!s.rules.g92_bare_axis_is_zero) return c.get(axis);
    if (no_axis || c.has(axis)) return c.get(axis).value_or(0);
    return std::nullopt;
  };
  if (const auto v = value('X')) s.x = *v * s.unit;
  if (const auto v = value('Y')) s.y = *v * s.unit;
  if (const auto v = value('Z')) s.z = *v * s.unit;
  if (const auto v = value('E')) s.e = *v * s.unit;
  step.position_set = true;
}

MoveWords move_words(const GcodeCommand& c) {
  return {c.get('X'), c.get('Y'), c.get('Z'), c.get('E'), c.get('F')};
}

// get_destination_from_command: each axis word moves its axis in the current modes and
// units; F above 0 is the feedrate.
void take_move_words(GcodeState& s, const MoveWords& words) {
  const auto axis = [&](const std::optional<double>& word, double& value, bool relative) {
    if (word) value = relative ? value + *word * s.unit : *word * s.unit;
  };
  axis(words.x, s.x, s.relative_xyz);
  axis(words.y, s.y, s.relative_xyz);
  axis(words.z, s.z, s.relative_xyz);
  axis(words.e, s.e, e_is_relative(s));
  if (words.f && *words.f > 0) s.feedrate = *words.f * s.unit;
}

// G2/G3's centre from the start (Marlin's arc_offset), mm: from R when R has a value, else
// I and J; {0, 0} for none. `s` is at the arc's end, (x0, y0) its start.
std::array<double, 2> arc_offset(const GcodeState& s, double x0, double y0, const GcodeCommand& c,
                                 bool clockwise) {
  if (const auto radius = c.get('R')) {
    const double r = *radius * s.unit;
    if (r == 0 || (s.x == x0 && s.y == y0)) return {0, 0};
    const double dx = (s.x - x0) / 2, dy = (s.y - y0) / 2;  // to the middle of the chord
    const double side = clockwise != (r < 0) ? -1 : 1;
    const double half = std::hypot(dx, dy), h2 = (r - half) * (r + half);
    const double h = h2 >= 0 ? std::sqrt(h2) : 0;  // from the middle to the centre
    return {dx - dy / half * side * h, dy + dx / half * side * h};
  }
  return {c.get('I').value_or(0) * s.unit, c.get('J').value_or(0) * s.unit};
}

// How many chords plan_arc cuts an arc of `length` mm into: 1 mm ones, at least `fewest`,
// then kept within MIN_ARC_SEGMENT_MM and MAX_ARC_SEGMENT_MM.
int arc_segments(double length, int fewest) {
  const double nominal = std::max(std::floor(length / kMaxArcSegment), static_cast<double>(fewest));
  const double chord = length / nominal;
  if (chord > kMaxArcSegment) return static_cast<int>(std::ceil(length / kMaxArcSegment));
  if (chord < kMinArcSegment) return std::max(1, static_cast<int>(std::floor(length / kMinArcSegment)));
  return static_cast<int>(nominal);
}

// G2 (clockwise) or G3, as G2_G3.cpp's G2_G3 and plan_arc: the chords' ends turn about the
// centre by a rotation matrix of small-angle sin and cos, every 25th exactly; the last
// chord ends at the end written.
void arc(GcodeState& s, const GcodeCommand& c, bool clockwise, GcodeStep& step) {
  const double x0 = s.x, y0 = s.y, z0 = s.z, e0 = s.e;
  const AxisPosition start = machine_position(s);
  take_move_words(s, move_words(c));
  const auto stay = [&] { s.x = x0, s.y = y0, s.z = z0, s.e = e0; };
  const auto [i, j] = arc_offset(s, x0, y0, c, clockwise);
  if (i == 0 && j == 0) {
    step.bad_arc = true;
    return stay();
  }
  const double cx = x0 + i, cy = y0 + j, radius = std::hypot(i, j);
  double angle = 0;
  int fewest = kMinCircleSegments;
  const auto near = [](double a, double b) { return std::abs(a - b) <= 1e-6; };
  if (near(x0, s.x) && near(y0, s.y)) {
    angle = clockwise ? -kTurn : kTurn;
  } else {
    const double tx = s.x - cx, ty = s.y - cy;  // centre to end; -i, -j: centre to start
    angle = std::atan2(-i * ty + j * tx, -i * tx - j * ty);
    if (angle == 0) return stay();
    if (angle > 0 && clockwise) angle -= kTurn;
    if (angle < 0 && !clockwise) angle += kTurn;
    fewest = static_cast<int>(std::ceil(kMinCircleSegments * std::abs(angle) / kTurn));
  }
  const double rise = s.z - z0, fed = s.e - e0, length = radius * std::abs(angle);
  if (length < 0.0001 && rise < 0.0001) return stay();
  const int segments = arc_segments(length, fewest);
  const double theta = angle / segments;
  const double sin_t = theta - theta * theta * theta / 6, cos_t = 1 - theta * theta / 2;
  const double speed = s.feedrate / 60.0;
  step.chords.reserve(static_cast<std::size_t>(segments));
  double ra = -i, rb = -j;  // centre to the chord's end
  AxisPosition from = start;
  int exact_in = kArcCorrection;
  for (int k = 1; k < segments; ++k) {
    if (--exact_in) {
      const double b = ra * sin_t + rb * cos_t;
      ra = ra * cos_t - rb * sin_t;
      rb = b;
    } else {
      exact_in = kArcCorrection;
      const double cos_k = std::cos(k * theta), sin_k = std::sin(k * theta);
      ra = -i * cos_k + j * sin_k;
      rb = -i * sin_k - j * cos_k;
    }
    const AxisPosition to{cx + ra, cy + rb, from.z + rise / segments, from.e + fed / segments};
    step.chords.push_back({from, to, speed});
    from = to;
  }
  step.chords.push_back({from, machine_position(s), speed});
}

// G10 (retracting) or G11, as feature/fwretract.cpp's FWRetract::retract().
void retract(GcodeState& s, bool retracting, GcodeStep& step) {
  if (s.retracted == retracting) return;
  const FirmwareRetraction& r = s.retraction;
  constexpr double kAxisMaximum = std::numeric_limits<double>::infinity();
  AxisPosition at = machine_position(s);
  if (retracting) {
    s.filament_offset -= r.length;
    add_motion(step, at, machine_position(s), r.feedrate);
    if (s.hop == 0 && r.z_raise > 0.01) {
      at = machine_position(s);
      s.hop = r.z_raise;
      add_motion(step, at, machine_position(s), kAxisMaximum);
    }
  } else {
    if (s.hop != 0) {
      s.hop = 0;
      add_motion(step, at, machine_position(s), kAxisMaximum);
      at = machine_position(s);
    }
    s.filament_offset += r.length + r.recover_extra;
    add_motion(step, at, machine_position(s), r.recover_feedrate);
  }
  s.retracted = retracting;
}

void follow_comment(GcodeState& s, const std::string& comment, GcodeStep& step) {
  if (comment.starts_with("LAYER:")) {
    char* end = nullptr;
    const long number = std::strtol(comment.c_str() + 6, &end, 10);
    if (end == comment.c_str() + 6) return;
    s.layer = number;
    step.layer_started = true;
  } else if (comment.starts_with("TYPE:")) {
    s.type = comment.substr(5);
    step.type_started = true;
  }
}

}  // namespace

bool lays_filament(const Motion& move) {
  return move.to.e > move.from.e && (move.to.x != move.from.x || move.to.y != move.from.y);
}

AxisPosition machine_position(const GcodeState& s) {
  return {s.x, s.y, s.z + s.hop, s.e + s.filament_offset};
}

bool e_is_relative(const GcodeState& s) {
  return s.relative_e || (s.rules.e_relative_while_g91 && s.relative_xyz);
}

Motion move_motion(GcodeState& s, const MoveWords& words) {
  const AxisPosition from = machine_position(s);
  take_move_words(s, words);
  return {from, machine_position(s), s.feedrate / 60.0};
}

GcodeStep interpret_move(GcodeState& s, const MoveWords& words) {
  GcodeStep step;
  step.motions[step.count++] = move_motion(s, words);
  return step;
}

GcodeStep interpret(GcodeState& s, const GcodeCommand& c) {
  GcodeStep step;
  if (c.empty()) {
    if (!c.comment.empty()) follow_comment(s, c.comment, step);
    return step;
  }
  if (c.letter == 'G') {
    switch (c.code) {
      case 0: case 1: step = interpret_move(s, move_words(c)); break;
      case 2: case 3: arc(s, c, c.code == 2, step); break;
      case 10: retract(s, true, step); break;
      case 11: retract(s, false, step); break;
      case 20: s.unit = kInch; break;
      case 21: s.unit = 1; break;
      case 28: home(s, c, step); break;
      case 90: case 91:
        s.relative_xyz = c.code == 91;
        if (!s.rules.e_relative_while_g91) s.relative_e = s.relative_xyz;
        break;
      case 92:
        if (c.subcode == 0) set_position(s, c, step);
        break;
      default: break;
    }
  } else if (c.letter == 'M') {
    FirmwareRetraction& r = s.retraction;
    switch (c.code) {
      case 82: s.relative_e = false; break;
      case 83: s.relative_e = true; break;
      case 207:
        if (const auto v = c.get('S')) r.length = *v * s.unit;
        if (const auto v = c.get('F')) r.feedrate = *v * s.unit / 60.0;
        if (const auto v = c.get('Z')) r.z_raise = *v * s.unit;
        break;
      case 208:
        if (const auto v = c.get('S')) r.recover_extra = *v * s.unit;
        if (const auto v = c.get('F')) r.recover_feedrate = *v * s.unit / 60.0;
        break;
      case 221:
        if (const auto v = c.get('S'); v && *v >= 0) s.flow = std::trunc(*v);
        break;
      default: break;
    }
  }
  if (!c.comment.empty()) follow_comment(s, c.comment, step);
  return step;
}

std::optional<MotionLimits> motion_limits_after(const MotionLimits& limits, const GcodeCommand& c) {
  if (c.letter != 'M' || (c.code != 201 && c.code != 203 && c.code != 204 && c.code != 205)) {
    return std::nullopt;
  }
  MotionLimits after = limits;
  constexpr std::string_view kAxes = "XYZE";
  for (std::size_t axis = 0; axis < kAxes.size(); ++axis) {
    const auto v = c.get(kAxes[axis]);
    if (!v || *v <= 0) continue;
    if (c.code == 201) after.max_acceleration[axis] = *v;
    if (c.code == 203) after.max_speed[axis] = *v;
  }
  if (c.code == 204) {
    if (const auto v = c.get('S'); v && *v > 0) after.print_acceleration = after.travel_acceleration = *v;
    if (const auto v = c.get('P'); v && *v > 0) after.print_acceleration = *v;
    if (const auto v = c.get('R'); v && *v > 0) after.retract_acceleration = *v;
    if (const auto v = c.get('T'); v && *v > 0) after.travel_acceleration = *v;
  }
  if (c.code == 205) {
    if (const auto v = c.get('J'); v && *v > 0) after.junction_deviation = *v;
    if (const auto v = c.get('S'); v && *v >= 0) after.min_feedrate = *v;
  }
  return after;
}

std::optional<double> dwell_seconds(const GcodeCommand& c) {
  if (!c.is('G', 4)) return std::nullopt;
  double seconds = 0;
  if (const auto p = c.get('P')) seconds = *p / 1000.0;
  if (const auto s = c.get('S')) seconds = *s;
  return std::max(seconds, 0.0);
}

std::array<bool, 3> homed_axes(const GcodeCommand& c) {
  const bool x = c.has('X'), y = c.has('Y'), z = c.has('Z');
  const bool all = x == y && x == z;  // G28.cpp: home_all = homeX == homeY && homeX == homeZ
  return {all || x, all || y, all || z};
}

}  // namespace printer
