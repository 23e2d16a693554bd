// Motion: the block's move in the active motion mode, straight traverses and feeds, arcs in the
// selected plane (centre from R or from I/J/K, checked as LinuxCNC checks them), probing as the
// stand-alone interpreter simulates it; spindle-synchronised motion (G33's straight move and
// G33.1's rigid tap), fed at a pitch per revolution of the spindle.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>

#include "pkm/gcode/interpreter_state.hpp"

namespace pkm::gcode {

namespace {
// The most turns a G2/G3 P word may ask for.
constexpr double kMaxArcTurns = 1e6;

// The plane's two axes and the words giving the arc centre's offsets along them.
struct ArcAxes {
  int first = kX, second = kY;
  char first_offset = 'i', second_offset = 'j';
};

ArcAxes arc_axes(Plane plane) {
  switch (plane) {
    case Plane::xz:
      return {kZ, kX, 'k', 'i'};
    case Plane::yz:
      return {kY, kZ, 'j', 'k'};
    case Plane::xy:
      break;
  }
  return {};
}
}  // namespace

void Interpreter::State::make_motion(const Block& block, const Code* motion_code,
                                     bool machine_coordinates) {
  if (motion < 0 || motion == 800) {
    fail(1, "axis words with no motion mode active (after G80, give G0 or G1)");
  }
  const Position end = target(block, machine_coordinates);
  const int column = motion_code ? motion_code->column : 1;
  move_column = column;
  if (compensation.on() && motion >= 330 && motion != 800) {
    const char* what = motion < 380 || motion == 760 ? " (spindle-synchronised motion)"
                       : motion < 390                ? " (probing)"
                                                     : " (canned cycle)";
    fail(column, "cannot use " + code_name('G', motion) + what +
                     " with cutter radius compensation on (G40 first)");
  }
  switch (motion) {
    case 0:
      straight(CanonKind::traverse, block, end);
      break;
    case 10:
      require_feed(block, column);
      straight(CanonKind::feed, block, end);
      break;
    case 20:
    case 30:
      require_feed(block, column);
      arc(block, motion, end);
      break;
    case 330:
      synchronised_move(block, end);
      break;
    case 331:
      rigid_tap(block, end);
      break;
    case 760:
      threading_cycle(block, end);
      break;
    case 382:
    case 383:
    case 384:
    case 385:
      probe(block, column, end);
      break;
    default:
      if (motion < 730) fail(column, "motion mode " + code_name('G', motion) + " is not supported");
      cycle(block, motion, end);
  }
}

void Interpreter::State::straight(CanonKind kind, const Block& block, const Position& end) {
  Canon& canon = next_move(kind, block);
  if (&end != &canon.end) canon.end = end;
  canon.value = feed;  // the F in effect: the planner's programmed speed (or inverse time)
  canon.feed_mode = feed_mode;
  canon.spindle_rpm = turning_rpm();
  straight_exit = false;
  send_move(canon, &CutterCompensation::straight);
}

void Interpreter::State::arc(const Block& block, int code, const Position& end) {
  const ArcAxes axes = arc_axes(plane);
  const int column = block.g_codes.empty() ? 1 : block.g_codes.front().column;
  if (straight_exit) {
    fail(column, "the move after G40 (cutter compensation off) must be straight, not an arc");
  }
  if (rotation_deg != 0.0 && plane != Plane::xy) {
    // Turned about Z, an XZ or YZ arc leaves the principal planes the planner's arcs lie in.
    fail(move_column,
         "an arc in the XZ or YZ plane (G18, G19) in a coordinate system turned by G10 L2 "
         "R" +
             written_number(rotation_deg) + " is not supported: give it as G1 moves");
  }
  const std::array<double, 2> start{pos[axes.first], pos[axes.second]};
  const std::array<double, 2> to{end[axes.first], end[axes.second]};
  int turns = code == 20 ? -1 : 1;
  if (block.has('p')) {
    const double p = block.value('p');
    if (p < 1.0 || p != std::floor(p))
      fail(block.word('p')->column, "P must be a whole number of turns, 1 or more");
    require_word_in_range(block, 'p', 1.0, kMaxArcTurns, "an arc's turns go from");
    turns *= static_cast<int>(p);
  }
  std::array<double, 2> centre{};
  if (block.has('r')) {
    centre = arc_centre_from_radius(block, code, start, to);
  } else {
    if (!block.has(axes.first_offset) && !block.has(axes.second_offset)) {
      fail(column, "R, I, J, K words all missing for the arc");
    }
    const double i = block.has(axes.first_offset) ? block.value(axes.first_offset) : 0.0;
    const double j = block.has(axes.second_offset) ? block.value(axes.second_offset) : 0.0;
    centre = {arc_absolute ? i : start[0] + i, arc_absolute ? j : start[1] + j};
    check_arc_radii(column, centre, start, to);
  }
  Canon& canon = next_move(CanonKind::arc, block);
  canon.end = end;
  canon.value = feed;
  canon.feed_mode = feed_mode;
  canon.spindle_rpm = turning_rpm();
  canon.center = centre;
  canon.turns = turns;
  send_move(canon, &CutterCompensation::arc);
}

std::array<double, 2> Interpreter::State::arc_centre_from_radius(
    const Block& block, int code, const std::array<double, 2>& start,
    const std::array<double, 2>& end) const {
  const double radius = block.value('r');
  const int column = block.word('r')->column;
  if (end[0] == start[0] && end[1] == start[1]) {
    fail(column, "an R arc's end point equals its start: the centre is undefined");
  }
  const double abs_radius = std::abs(radius);
  const double mid_1 = (end[0] + start[0]) / 2.0, mid_2 = (end[1] + start[1]) / 2.0;
  double half = std::hypot(mid_1 - end[0], mid_2 - end[1]);
  const double tolerance = units == LengthUnits::inch ? 0.0005 : 0.005;
  if (half - abs_radius > tolerance) fail(column, "arc radius too small to reach the end point");
  if (half / abs_radius > 1.0 - 1e-12) half = abs_radius;
  const double direction = std::atan2(end[1] - start[1], end[0] - start[0]);
  // A positive R takes the short way round, a negative one the long way.
  const double theta = ((code == 20 && radius > 0) || (code == 30 && radius < 0))
                           ? direction - std::numbers::pi / 2
                           : direction + std::numbers::pi / 2;
  const double offset = abs_radius * std::cos(std::asin(half / abs_radius));
  return {mid_1 + offset * std::cos(theta), mid_2 + offset * std::sin(theta)};
}

void Interpreter::State::check_arc_radii(int column, const std::array<double, 2>& centre,
                                         const std::array<double, 2>& start,
                                         const std::array<double, 2>& end) const {
  const double radius = std::hypot(centre[0] - start[0], centre[1] - start[1]);
  const double radius2 = std::hypot(centre[0] - end[0], centre[1] - end[1]);
  const double abs_tolerance = arc_radius_tolerance(units);
  if (radius < 0.1 * abs_tolerance || radius2 < 0.1 * abs_tolerance)
    fail(column, "zero radius arc");
  const double abs_err = std::abs(radius - radius2);
  const double rel_err = abs_err / std::max(radius, radius2);
  if (abs_err > abs_tolerance && rel_err > 0.001) {
    char message[256];
    std::snprintf(message, sizeof message,
                  "radius to end of arc differs from radius to start: r1=%.4f r2=%.4f "
                  "(LinuxCNC accepts %.4f or 0.1%%)",
                  radius, radius2, abs_tolerance);
    fail(column, message);
  }
}

void Interpreter::State::probe(const Block& block, int column, const Position& end) {
  // Probing as LinuxCNC's stand-alone interpreter simulates it: the probe trips at the target
  // (#5061.. hold it), and the tool backs off 0.01 inch towards the start.
  if (feed_mode == FeedMode::units_per_revolution) {
    fail(column, "cannot probe in feed per revolution mode (G95): give G94 first");
  }
  require_feed(block, column);
  if (!options.probe_refusal.empty()) fail(column, options.probe_refusal);
  double length = 0.0;
  for (int axis = 0; axis < 3; ++axis) length += (end[axis] - pos[axis]) * (end[axis] - pos[axis]);
  length = std::sqrt(length);
  if (length == 0.0) fail(column, "probe start and end points must differ");
  Canon probe = make(CanonKind::probe, block);
  probe.end = end;
  probe.value = feed;  // the F it probes at: the planner's speed, as for G1
  probe.feed_mode = feed_mode;
  emit(probe);
  const double back_off = units == LengthUnits::inch ? 0.01 : 0.254;
  for (int axis = 0; axis < kAxes; ++axis) parameters.set_numbered(5061 + axis, end[axis]);
  parameters.set_numbered(5070, 0.0);
  Position after_probe = end;
  for (int axis = 0; axis < 3; ++axis) {
    after_probe[axis] = end[axis] - back_off * (end[axis] - pos[axis]) / length;
  }
  pos = canon_pos = after_probe;
}

void Interpreter::State::require_turning_spindle(int code) const {
  if (spindle_direction != 0) return;
  fail(move_column, "spindle not turning in " + code_name('G', code) +
                        ": a synchronised move follows the spindle (M3 or M4 first)");
}

void Interpreter::State::synchronised_feed(const Block& block, const Position& end, double pitch) {
  Canon& canon = next_move(CanonKind::feed, block);
  canon.end = end;
  canon.value = std::abs(pitch);  // the sign is the machine's business; the speed is |pitch| S
  canon.feed_mode = FeedMode::units_per_revolution;
  canon.spindle_rpm = turning_rpm();
  straight_exit = false;
  send_move(canon, &CutterCompensation::straight);
}

void Interpreter::State::start_synchronisation(const Block& block, double pitch) {
  Canon sync = make(CanonKind::speed_feed_sync, block);
  sync.value = pitch;
  emit(sync);
}

void Interpreter::State::synchronised_move(const Block& block, const Position& end) {
  require_turning_spindle(330);
  const double pitch = block.value('k');
  start_synchronisation(block, pitch);
  synchronised_feed(block, end, pitch);
  emit(CanonKind::speed_feed_sync_stop, block);
}

void Interpreter::State::rigid_tap(const Block& block, const Position& end) {
  require_turning_spindle(331);
  const double pitch = block.value('k');
  start_synchronisation(block, pitch);
  // The tap goes along X Y Z and comes back: only those move. Other axis words are kept as
  // the program's position, as rs274 keeps them (the next move goes there).
  Canon tap = make(CanonKind::rigid_tap, block);
  for (int axis = 0; axis < 3; ++axis) tap.end[axis] = end[axis];
  tap.value = std::abs(pitch);
  tap.feed_mode = FeedMode::units_per_revolution;
  tap.spindle_rpm = turning_rpm();
  emit(tap);
  emit(CanonKind::speed_feed_sync_stop, block);
  for (int axis = 3; axis < kAxes; ++axis) pos[axis] = end[axis];
}

}  // namespace pkm::gcode
