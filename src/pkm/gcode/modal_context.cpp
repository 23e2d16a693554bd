// M70-M73: the modal state saved in the frame of the running call (or of the main program) and
// restored, as LinuxCNC's save_settings and restore_settings do it. The state is kept in
// LinuxCNC's slots of active codes, and a restore executes the codes of the slots that differ,
// as LinuxCNC writes them: units alone first, then one line with F (one decimal), S (none), the
// other G codes, G64 with its P and Q, and the first M code, then each further M code on a line
// of its own. Executing codes rather than setting members gives the commands, the refusals and
// the order of LinuxCNC's restore. The motion mode is not restored, nor the tool.
#include <cstdio>
#include <cstdlib>

#include "pkm/gcode/interpreter_state.hpp"

namespace pkm::gcode {
namespace {

// LinuxCNC's slots of active_g_codes that a restore looks at.
enum GSlot {
  kPlane = 3,
  kCompensation = 4,
  kUnits = 5,
  kDistance = 6,
  kFeedMode = 7,
  kCoordinateSystem = 8,
  kToolLength = 9,
  kRetract = 10,
  kPathControl = 11,
  kSpindleMode = 13,
  kArcDistance = 14,
  kLatheDiameter = 15,
  kG92Applied = 16,
};
// The slots of active_m_codes: spindle, mist, flood, the overrides, adaptive feed, feed hold.
enum MSlot { kSpindle = 2, kMist = 4, kFlood = 5, kOverrides = 6, kAdaptive = 7, kHold = 8 };

// The G code slots restored on the one line, in LinuxCNC's order (G64 goes after them).
constexpr GSlot kRestoredOnTheLine[] = {
    kPlane,   kCompensation, kDistance,    kFeedMode,    kCoordinateSystem, kToolLength,
    kRetract, kPathControl,  kSpindleMode, kArcDistance, kLatheDiameter,    kG92Applied};

std::string printed(const char* format, double value) {
  char text[64];
  std::snprintf(text, sizeof text, format, value);
  return text;
}

}  // namespace

Interpreter::State::ModalContext Interpreter::State::active_modes() const {
  ModalContext modes;
  modes.g.fill(-1);
  modes.m.fill(-1);
  auto& g = modes.g;
  g[kPlane] = plane == Plane::xy ? 170 : plane == Plane::xz ? 180 : 190;
  const CompensationSide side = compensation.side();
  g[kCompensation] = side == CompensationSide::left    ? 410
                     : side == CompensationSide::right ? 420
                                                       : 400;
  g[kUnits] = units == LengthUnits::inch ? 200 : 210;
  g[kDistance] = absolute ? 900 : 910;
  g[kFeedMode] = feed_mode == FeedMode::inverse_time           ? 930
                 : feed_mode == FeedMode::units_per_revolution ? 950
                                                               : 940;
  g[kCoordinateSystem] = coord_system < 7 ? 530 + 10 * coord_system : 584 + coord_system;
  bool offset = tool_length_g43;
  for (const double value : tool_offset_mm) offset = offset || value != 0.0;
  g[kToolLength] = offset ? 430 : 490;
  g[kRetract] = retract_to_old ? 980 : 990;
  g[kPathControl] = path_mode == 64 ? 640 : path_mode == 61 ? 610 : 611;
  g[kSpindleMode] = 970;  // G96 is refused
  g[kArcDistance] = arc_absolute ? 901 : 911;
  g[kLatheDiameter] = 80;  // G7 is refused
  g[kG92Applied] = parameters.numbered(5210) == 1.0 ? 923 : -1;
  auto& m = modes.m;
  m[kSpindle] = spindle_direction == 1 ? 3 : spindle_direction == -1 ? 4 : 5;
  m[kMist] = mist ? 7 : flood ? -1 : 9;
  m[kFlood] = flood ? 8 : -1;
  m[kOverrides] = feed_override_on ? (speed_override_on ? 48 : 50) : (speed_override_on ? 51 : 49);
  m[kAdaptive] = adaptive_feed_on ? 52 : -1;
  m[kHold] = feed_hold_on ? 53 : -1;
  modes.feed = feed;
  modes.speed = speed;
  modes.path_tolerance = path_tolerance;
  modes.naive_tolerance = naive_tolerance;
  return modes;
}

void Interpreter::State::save_or_restore_modes(const Code& code) {
  SavedContext& context = context_here();
  const std::string name = code_name('M', code.tenths);
  if (code.tenths == 700 || code.tenths == 730) {
    context.modes = active_modes();
    context.valid = true;
    if (code.tenths == 730 && calls.empty()) {
      warn("M73 in the main program: nothing returns to restore its modes (M72 still can)");
    } else if (code.tenths == 730) {
      context.restore_on_return = true;
    }
  } else if (code.tenths == 710) {
    context.valid = false;
  } else {
    if (!context.valid) {
      fail(code.column,
           "M72 with no modes saved here: M70 or M73 first, in this subroutine (M71 forgets "
           "them)");
    }
    restore_modes(context.modes, code.column, name);
  }
}

void Interpreter::State::restore_modes(const ModalContext& saved, int column,
                                       const std::string& what) {
  const ModalContext now = active_modes();
  // Units first: F and the offsets that follow are then read in the saved units.
  if (saved.g[kUnits] != now.g[kUnits]) {
    execute_restoring(code_name('G', saved.g[kUnits]), column, what);
  }
  std::string line = " F" + printed("%.1f", saved.feed) + " S" + printed("%.0f", saved.speed);
  for (const GSlot slot : kRestoredOnTheLine) {
    const int code = saved.g[slot];
    if (code == now.g[slot] || code == -1 || (slot == kPathControl && code == 640)) continue;
    line += " " + code_name('G', code);
  }
  if (saved.g[kPathControl] == 640) {
    line += " G64";
    if (saved.path_tolerance >= 0.0) line += " P" + printed("%f", saved.path_tolerance);
    if (saved.path_tolerance >= 0.0 && saved.naive_tolerance >= 0.0) {
      line += " Q" + printed("%f", saved.naive_tolerance);
    }
  }
  // The first M code goes on that line, the others on lines of their own (M7 and M8 are of one
  // group), as LinuxCNC's restore writes them.
  std::vector<std::string> lines{line};
  bool first_m = true;
  for (const int slot : {kSpindle, kMist, kFlood, kOverrides, kAdaptive, kHold}) {
    const int code = saved.m[static_cast<std::size_t>(slot)];
    if (code == now.m[static_cast<std::size_t>(slot)] || code == -1) continue;
    const std::string m = "M" + std::to_string(code);
    if (first_m) {
      lines.front() += m;
    } else {
      lines.push_back(m);
    }
    first_m = false;
  }
  for (const std::string& restoring : lines) execute_restoring(restoring, column, what);
  // LinuxCNC writes F with one decimal and S with none: what it restores can differ from what
  // was saved. pkm restores what LinuxCNC does, and says so where it differs.
  if (std::strtod(printed("%.1f", saved.feed).c_str(), nullptr) != saved.feed) {
    warn(what + " restores F" + written_number(saved.feed) + " as F" + printed("%.1f", saved.feed) +
         ", as LinuxCNC does (it writes the saved feed with one decimal): give F again after " +
         what + " for F" + written_number(saved.feed));
  }
  if (std::strtod(printed("%.0f", saved.speed).c_str(), nullptr) != saved.speed) {
    warn(what + " restores S" + written_number(saved.speed) + " as S" +
         printed("%.0f", saved.speed) +
         ", as LinuxCNC does (it writes the saved speed as a whole number): give S again after " +
         what + " for S" + written_number(saved.speed));
  }
}

void Interpreter::State::execute_restoring(const std::string& line, int column,
                                           const std::string& what) {
  // The line runs inside the restoring block, whose codes by group its own steps still need.
  const auto g_codes = g_by_group;
  const auto m_codes = m_by_group;
  try {
    Block restoring;
    read_block(line, parameters, restoring);
    execute_block(restoring);
  } catch (const GcodeError& error) {
    fail(column, what + " cannot restore the saved modes: '" + line + "': " + error.message());
  } catch (const SyntaxError& error) {
    fail(column, what + " cannot restore the saved modes: '" + line + "': " + error.message);
  }
  g_by_group = g_codes;
  m_by_group = m_codes;
}

void Interpreter::State::restore_on_return(const SavedContext& leaving, int column) {
  if (leaving.valid && leaving.restore_on_return) {
    restore_modes(leaving.modes, column, "the return to M73's modes");
  }
}

}  // namespace pkm::gcode
