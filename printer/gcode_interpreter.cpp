// G-code read as Marlin runs it; see gcode_interpreter.h for each rule's source.
#include "printer/gcode_interpreter.h"

#include <cmath>
#include <cstdlib>
#include <limits>
#include <string_view>

namespace printer {

namespace {

constexpr double kInch = 25.4;  // mm

void add_motion(GcodeStep& step, const AxisPosition& from, const AxisPosition& to,
                double feedrate) {
  step.motions[step.count++] = {from, to, feedrate};
}

// G28: the named axes, or X, Y and Z when none or all three are named, to 0.
void home(GcodeState& s, const GcodeCommand& c, GcodeStep& step) {
  const bool x = c.has('X'), y = c.has('Y'), z = c.has('Z');
  const bool all = x == y && x == z;
  if (all || x) s.x = 0;
  if (all || y) s.y = 0;
  if (all || z) s.z = 0;
  s.homed = true;
  step.homed = step.position_set = true;
}

// G92: each axis given to its value (in the current units); E directly.
void set_position(GcodeState& s, const GcodeCommand& c, GcodeStep& step) {
  if (const auto v = c.get('X')) s.x = *v * s.unit;
  if (const auto v = c.get('Y')) s.y = *v * s.unit;
  if (const auto v = c.get('Z')) s.z = *v * s.unit;
  if (const auto v = c.get('E')) s.e = *v * s.unit;
  step.position_set = true;
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

GcodeStep interpret_move(GcodeState& s, const MoveWords& words) {
  const AxisPosition from = machine_position(s);
  const auto axis = [&](const std::optional<double>& word, double& value, bool relative) {
    if (word) value = relative ? value + *word * s.unit : *word * s.unit;
  };
  axis(words.x, s.x, s.relative_xyz);
  axis(words.y, s.y, s.relative_xyz);
  axis(words.z, s.z, s.relative_xyz);
  axis(words.e, s.e, s.relative_e);
  if (words.f && *words.f > 0) s.feedrate = *words.f * s.unit;
  GcodeStep step;
  add_motion(step, from, machine_position(s), s.feedrate / 60.0);
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
      case 0: case 1: case 2: case 3:
        step = interpret_move(s, {c.get('X'), c.get('Y'), c.get('Z'), c.get('E'), c.get('F')});
        break;
      case 10: retract(s, true, step); break;
      case 11: retract(s, false, step); break;
      case 20: s.unit = kInch; break;
      case 21: s.unit = 1; break;
      case 28: home(s, c, step); break;
      case 90: s.relative_xyz = s.relative_e = false; break;
      case 91: s.relative_xyz = s.relative_e = true; break;
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

}  // namespace printer
