// Canned cycles G73, G74 and G81-G89 as LinuxCNC expands them into moves: sticky R, Z (the
// plane's normal), Q and P words, the level a series of cycles started from (G98/G99), repeats
// (L), G91 steps between holes (in radius and angle with polar words), pecks, the tapping
// cycles' spindle reversal. Each hole and peck counts against the program's bound.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <numbers>

#include "pkm/gcode/interpreter_state.hpp"

namespace pkm::gcode {

// One cycle block's geometry: the plane's axes and the levels along its normal, program units.
struct CycleLevels {
  int first = kX, second = kY, normal = kZ;
  char normal_letter = 'z';
  int column = 1;           // the cycle's code, for errors
  double r = 0.0;           // the R plane
  double bottom = 0.0;      // the hole's bottom
  double clear = 0.0;       // where the tool retracts to between holes (R, or the old level)
  double peck_clear = 0.0;  // how far above the last peck the tool comes back down
};

namespace {
CycleLevels cycle_axes(Plane plane) {
  CycleLevels levels;
  if (plane == Plane::xz) {
    levels.first = kZ, levels.second = kX, levels.normal = kY, levels.normal_letter = 'y';
  } else if (plane == Plane::yz) {
    levels.first = kY, levels.second = kZ, levels.normal = kX, levels.normal_letter = 'x';
  }
  return levels;
}
}  // namespace

void Interpreter::State::cycle(const Block& block, int code, const Position& end) {
  const CycleLevels levels = cycle_levels(block, code);
  // LinuxCNC (2.9 and its master's own tests) feeds a G84/G74 tap in the XZ and YZ planes to a
  // point whose coordinates it has permuted twice: the tap would leave its hole sideways. pkm
  // neither runs it so nor runs it differently from LinuxCNC.
  if ((code == 840 || code == 740) && plane != Plane::xy) {
    fail(levels.column, code_name('G', code) + " in the " +
                            (plane == Plane::xz ? "XZ plane (G18)" : "YZ plane (G19)") +
                            " is not supported: LinuxCNC feeds this tap off its axis (its "
                            "coordinates mixed up); tap in G17, or give the moves and the spindle "
                            "reversal (M4/M3) as G1 moves");
  }
  const long repeats = block.has('l') ? std::lround(block.value('l')) : 1;
  const int first = levels.first, second = levels.second;
  // Below R when the series began: every block of the series climbs to R first (even from R).
  if (cycle_old_cc < levels.r)
    cycle_move(block, levels, CanonKind::traverse, pos[first], pos[second], levels.r);
  // In G91 each repetition moves on by the programmed increment; with polar words the
  // increment is in radius and angle, applied to each hole's polar coordinates in turn.
  const double step_1 = end[first] - pos[first], step_2 = end[second] - pos[second];
  const auto& polar_radius = block.words['g' - 'a'];
  const auto& polar_angle = block.words['m' - 'a'];
  const bool polar = !absolute && plane == Plane::xy && (polar_radius || polar_angle);
  double at_1 = pos[first], at_2 = pos[second];
  for (long repeat = 0; repeat < repeats; ++repeat) {
    count_program_iteration(levels.column);
    if (absolute) {
      at_1 = end[first];
      at_2 = end[second];
    } else if (polar) {
      const double radius = std::hypot(at_1, at_2) + (polar_radius ? polar_radius->value : 0.0);
      const double angle = std::atan2(at_2, at_1) +
                           (polar_angle ? polar_angle->value * std::numbers::pi / 180.0 : 0.0);
      at_1 = radius * std::cos(angle);
      at_2 = radius * std::sin(angle);
    } else {
      at_1 += step_1;
      at_2 += step_2;
    }
    cycle_hole(block, code, levels, at_1, at_2);
  }
}

CycleLevels Interpreter::State::cycle_levels(const Block& block, int code) {
  CycleLevels levels = cycle_axes(plane);
  levels.column = block.g_codes.empty() ? 1 : block.g_codes.front().column;
  // Sticky R and Z are kept in mm, as LinuxCNC keeps them in machine units: read back in
  // inches they may differ from the written value in the last bit, which decides whether the
  // cycle first climbs to R (rs274's output shows it).
  double r_value = 0.0, z_value = 0.0;
  if (block.has('r')) {
    r_value = block.value('r');
    cycle_r = to_mm(r_value);
  } else if (motion_changed) {
    fail(levels.column, "R clearance plane unspecified in cycle");
  } else {
    r_value = from_mm(cycle_r);
  }
  if (block.has(levels.normal_letter)) {
    z_value = block.value(levels.normal_letter);
    cycle_z = to_mm(z_value);
  } else if (motion_changed) {
    fail(levels.column, std::string(1, static_cast<char>(std::toupper(levels.normal_letter))) +
                            " value unspecified in cycle");
  } else {
    z_value = from_mm(cycle_z);
  }
  if (block.has('q')) cycle_q = block.value('q');
  if (block.has('p')) cycle_p = block.value('p');
  if ((code == 830 || code == 730) && !(cycle_q > 0.0))
    fail(levels.column, "Q must be positive for G83/G73");
  require_feed(block, levels.column);
  if (!cycle_series) {
    cycle_old_cc = pos[levels.normal];
    cycle_series = true;
  }
  require_word_in_range(block, 'l', 0.0, static_cast<double>(options.max_loop_iterations),
                        "a canned cycle's repeats (the bound on one loop) go from");
  levels.r = r_value;
  levels.bottom = z_value;
  if (!absolute) {
    levels.r = cycle_old_cc + r_value;
    levels.bottom = levels.r + z_value;
  }
  if (levels.bottom > levels.r) fail(levels.column, "cycle bottom is above the R plane");
  levels.clear = (retract_to_old && cycle_old_cc > levels.r) ? cycle_old_cc : levels.r;
  levels.peck_clear = units == LengthUnits::inch ? 0.010 : 0.254;
  return levels;
}

void Interpreter::State::cycle_move(const Block& block, const CycleLevels& levels, CanonKind kind,
                                    double at_1, double at_2, double height) {
  Position p = pos;
  p[levels.first] = at_1;
  p[levels.second] = at_2;
  p[levels.normal] = height;
  straight(kind, block, p);
}

void Interpreter::State::cycle_hole(const Block& block, int code, const CycleLevels& levels,
                                    double at_1, double at_2) {
  const auto move = [&](CanonKind kind, double height) {
    cycle_move(block, levels, kind, at_1, at_2, height);
  };
  // Across to the hole at the current height when above R, else at the clearance height (a
  // G98 level above R, though the tool waits at R after G99 holes), then down to R.
  move(CanonKind::traverse, pos[levels.normal] > levels.r ? pos[levels.normal] : levels.clear);
  if (pos[levels.normal] != levels.r) move(CanonKind::traverse, levels.r);
  switch (code) {
    case 810:
      move(CanonKind::feed, levels.bottom);
      break;
    case 820:
      move(CanonKind::feed, levels.bottom);
      dwell(block, cycle_p);
      break;
    case 830:
    case 730:
      peck(block, code, levels, at_1, at_2);
      break;
    case 850:
      move(CanonKind::feed, levels.bottom);
      move(CanonKind::feed, levels.r);
      break;
    case 890:
      // G89 feeds all the way out to the clearance height (G85 feeds to R, then traverses).
      move(CanonKind::feed, levels.bottom);
      dwell(block, cycle_p);
      move(CanonKind::feed, levels.clear);
      return;
    case 840:
    case 740:
      tap(block, code, levels, at_1, at_2);
      return;
    default:
      fail(levels.column, code_name('G', code) + " is not supported (spindle-synchronised cycle)");
  }
  move(CanonKind::traverse, levels.clear);
}

void Interpreter::State::peck(const Block& block, int code, const CycleLevels& levels, double at_1,
                              double at_2) {
  if ((levels.r - levels.bottom) / cycle_q > static_cast<double>(options.max_loop_iterations)) {
    fail(levels.column, "Q" + written_number(cycle_q) + " makes more than " +
                            std::to_string(options.max_loop_iterations) +
                            " pecks (the bound on one loop)");
  }
  const auto move = [&](CanonKind kind, double height) {
    cycle_move(block, levels, kind, at_1, at_2, height);
  };
  double depth = levels.r;
  while (true) {
    count_program_iteration(levels.column);
    depth = std::max(depth - cycle_q, levels.bottom);
    move(CanonKind::feed, depth);
    if (depth <= levels.bottom) break;
    // G83 goes back out to R between pecks, G73 only breaks the chip.
    if (code == 830) move(CanonKind::traverse, levels.r);
    move(CanonKind::traverse, depth + levels.peck_clear);
  }
}

void Interpreter::State::tap(const Block& block, int code, const CycleLevels& levels, double at_1,
                             double at_2) {
  // A right-hand tap (G84) cuts with the spindle clockwise (M3), a left-hand one (G74) with it
  // counterclockwise (M4); at the bottom the spindle reverses and backs the tap out, as the
  // floating tap holder LinuxCNC's cycle is made for needs.
  const int cutting = code == 840 ? 1 : -1;
  const std::string name = code_name('G', code);
  if (spindle_direction == 0) {
    fail(levels.column, "spindle not turning in " + name + " (M3 or M4 first)");
  }
  if (spindle_direction != cutting) {
    fail(levels.column, cutting > 0 ? "spindle turning counterclockwise in G84 (a right-hand "
                                      "tap: M3 first, or G74 for a left-hand one)"
                                    : "spindle turning clockwise in G74 (a left-hand tap: M4 "
                                      "first, or G84 for a right-hand one)");
  }
  const auto move = [&](double height) {
    cycle_move(block, levels, CanonKind::feed, at_1, at_2, height);
  };
  const auto turn_spindle = [&](int direction) {
    emit(CanonKind::spindle_stop, block);
    emit(direction > 0 ? CanonKind::spindle_clockwise : CanonKind::spindle_counterclockwise, block);
    spindle_direction = direction;
  };
  emit_overrides(block, false);
  move(levels.bottom);
  turn_spindle(-cutting);
  dwell(block, cycle_p);
  move(levels.clear);
  turn_spindle(cutting);
  emit_overrides(block, true);
}

void Interpreter::State::emit_overrides(const Block& block, bool enabled) {
  for (const CanonKind kind : {CanonKind::feed_override, CanonKind::speed_override}) {
    Canon c = make(kind, block);
    c.integer = enabled ? 1 : 0;
    emit(c);
  }
}

}  // namespace pkm::gcode
