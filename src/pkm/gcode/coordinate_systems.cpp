// Coordinate systems and offsets: G54-G59.3 and their offsets (G10 L2/L20), G92 and its
// relatives, G28/G30 homes, where a block's axis words lead (program, machine or polar
// coordinates), and the offsets handed on when they change. Offsets are kept in mm, as LinuxCNC
// keeps them in machine units.
#include <algorithm>
#include <bit>
#include <cmath>
#include <iterator>
#include <numbers>

#include "pkm/gcode/interpreter_state.hpp"

namespace pkm::gcode {

namespace {
// (x, y) turned counter-clockwise by `degrees` about the origin.
void rotate_xy(double& x, double& y, double degrees) {
  if (degrees == 0.0) return;
  const double radians = degrees * std::numbers::pi / 180.0;
  const double cos = std::cos(radians), sin = std::sin(radians);
  const double turned_x = x * cos - y * sin;
  y = x * sin + y * cos;
  x = turned_x;
}
}  // namespace

Position Interpreter::State::g5x_mm(int system) const {
  Position offset{};
  for (int axis = 0; axis < kAxes; ++axis) {
    offset[axis] = parameters.numbered(5201 + 20 * system + axis);
  }
  return offset;
}

Position Interpreter::State::total_offset_mm() const {
  const Position g5x = g5x_mm(coord_system);
  Position total{};
  for (int axis = 0; axis < kAxes; ++axis) {
    total[axis] = g5x[axis] + g92_mm[axis] + tool_offset_mm[axis];
  }
  return total;
}

Position Interpreter::State::machine_mm(const Position& program) const {
  const Position offsets = total_offset_mm();
  Position machine;
  for (int axis = 0; axis < kAxes; ++axis)
    machine[axis] = axis_to_mm(axis, program[axis]) + offsets[axis];
  if (rotation_deg != 0.0) {
    const Position g5x = g5x_mm(coord_system);
    double x = to_mm(program[kX]) + g92_mm[kX], y = to_mm(program[kY]) + g92_mm[kY];
    rotate_xy(x, y, rotation_deg);
    machine[kX] = x + g5x[kX] + tool_offset_mm[kX];
    machine[kY] = y + g5x[kY] + tool_offset_mm[kY];
  }
  return machine;
}

Position Interpreter::State::program_from_machine(const Position& machine) const {
  const Position offsets = total_offset_mm();
  Position program;
  for (int axis = 0; axis < kAxes; ++axis) {
    program[axis] = axis_from_mm(axis, machine[axis] - offsets[axis]);
  }
  if (rotation_deg != 0.0) {
    const Position g5x = g5x_mm(coord_system);
    double x = machine[kX] - g5x[kX] - tool_offset_mm[kX];
    double y = machine[kY] - g5x[kY] - tool_offset_mm[kY];
    rotate_xy(x, y, -rotation_deg);
    program[kX] = from_mm(x - g92_mm[kX]);
    program[kY] = from_mm(y - g92_mm[kY]);
  }
  return program;
}

void Interpreter::State::reexpress(const Offsets& old, bool g92_turns) {
  const double old_x = to_mm(pos[kX]), old_y = to_mm(pos[kY]);
  const Position now = total_offset_mm();
  for (int axis = 0; axis < kAxes; ++axis) {
    const double moved = axis_from_mm(axis, old.total_mm[axis] - now[axis]);
    pos[axis] += moved;
    canon_pos[axis] += moved;  // the canonical layer moves with offsets, never turns
  }
  if (old.rotation_deg == 0.0 && rotation_deg == 0.0) return;  // translations only: done
  // XY through the machine position: turned by the old rotation, back by the new one.
  const Position g5x = g5x_mm(coord_system);
  double x = old_x + (g92_turns ? old.g92_mm[kX] : 0.0);
  double y = old_y + (g92_turns ? old.g92_mm[kY] : 0.0);
  rotate_xy(x, y, old.rotation_deg);
  x += old.g5x_mm[kX] + old.tool_mm[kX] - g5x[kX] - tool_offset_mm[kX];
  y += old.g5x_mm[kY] + old.tool_mm[kY] - g5x[kY] - tool_offset_mm[kY];
  rotate_xy(x, y, -rotation_deg);
  pos[kX] = from_mm(x - (g92_turns ? g92_mm[kX] : 0.0));
  pos[kY] = from_mm(y - (g92_turns ? g92_mm[kY] : 0.0));
}

void Interpreter::State::emit_offsets(const Block& block) {
  Canon g5x = make(CanonKind::g5x_offset, block);
  g5x.integer = coord_system;
  const Position offset = g5x_mm(coord_system);
  for (int axis = 0; axis < kAxes; ++axis) g5x.end[axis] = axis_from_mm(axis, offset[axis]);
  emit(g5x);
  Canon g92 = make(CanonKind::g92_offset, block);
  for (int axis = 0; axis < kAxes; ++axis) g92.end[axis] = axis_from_mm(axis, g92_mm[axis]);
  emit(g92);
  // Programs that never turn a coordinate system hand on no rotation at all.
  if (rotation_deg != 0.0 || rotation_sent_deg != 0.0) {
    Canon rotation = make(CanonKind::xy_rotation, block);
    rotation.value = rotation_deg;
    emit(rotation);
    rotation_sent_deg = rotation_deg;
  }
}

void Interpreter::State::target(const Block& block, bool machine_coordinates, Position& end) const {
  end = pos;
  const std::uint32_t axes = block.letters & kAxisSlots;
  if (machine_coordinates) {
    const Position offsets = total_offset_mm();
    for (std::uint32_t used = axes; used != 0; used &= used - 1) {
      const int slot = std::countr_zero(used);
      const int axis = kAxisOfSlot[static_cast<std::size_t>(slot)];
      end[axis] =
          block.words[static_cast<std::size_t>(slot)]->value - axis_from_mm(axis, offsets[axis]);
    }
    if (rotation_deg != 0.0 && (block.has('x') || block.has('y'))) {
      machine_xy_under_rotation(block, end);
    }
  } else {
    for (std::uint32_t used = axes; used != 0; used &= used - 1) {
      const int slot = std::countr_zero(used);
      const int axis = kAxisOfSlot[static_cast<std::size_t>(slot)];
      const double value = block.words[static_cast<std::size_t>(slot)]->value;
      end[axis] = absolute ? value : pos[axis] + value;
    }
  }
  // Polar coordinates about the origin in XY: @ radius, ^ angle (deg). A missing one keeps the
  // current point's; in G91 both are increments to the current point's.
  const auto& radius = block.words['g' - 'a'];
  const auto& angle = block.words['m' - 'a'];
  if (radius || angle) {
    const double current_radius = std::hypot(pos[kX], pos[kY]);
    const double current_angle = std::atan2(pos[kY], pos[kX]) * 180.0 / std::numbers::pi;
    double r = current_radius, a = current_angle;
    if (absolute) {
      if (radius) r = radius->value;
      if (angle) a = angle->value;
    } else {
      if (radius) r += radius->value;
      if (angle) a += angle->value;
    }
    end[kX] = r * std::cos(a * std::numbers::pi / 180.0);
    end[kY] = r * std::sin(a * std::numbers::pi / 180.0);
  }
}

void Interpreter::State::machine_xy_under_rotation(const Block& block, Position& end) const {
  // A G53 X or Y word is a machine coordinate; the other one stays where the tool is, seen
  // from the turned system's origin, as LinuxCNC takes it.
  const Position g5x = g5x_mm(coord_system);
  double x = to_mm(pos[kX]) + g92_mm[kX], y = to_mm(pos[kY]) + g92_mm[kY];
  rotate_xy(x, y, rotation_deg);
  if (block.has('x')) x = to_mm(block.value('x')) - g5x[kX] - tool_offset_mm[kX];
  if (block.has('y')) y = to_mm(block.value('y')) - g5x[kY] - tool_offset_mm[kY];
  rotate_xy(x, y, -rotation_deg);
  end[kX] = from_mm(x - g92_mm[kX]);
  end[kY] = from_mm(y - g92_mm[kY]);
}

void Interpreter::State::select_coordinate_system(const Block& block, const Code& code) {
  static constexpr int kCodes[] = {540, 550, 560, 570, 580, 590, 591, 592, 593};
  const int system = static_cast<int>(std::find(std::begin(kCodes), std::end(kCodes), code.tenths) -
                                      std::begin(kCodes)) +
                     1;
  refuse_with_compensation(code, "change coordinate systems");
  const Offsets old = offsets();
  coord_system = system;
  rotation_deg = rotation_of(system);
  parameters.set_numbered(5220, system);
  reexpress(old);
  emit_offsets(block);
}

bool Interpreter::State::execute_non_modal(const Block& block, const Code& non_modal) {
  const int code = non_modal.tenths;
  if (code == 280 || code == 300) refuse_with_compensation(non_modal, "use G28 or G30");
  if (code == 520 || (code >= 920 && code <= 923)) {
    refuse_with_compensation(non_modal, "change axis offsets");
  }
  if (code == 530 && compensation.offsetting()) {
    fail(non_modal.column, "cannot use G53 with cutter radius compensation on (G40 first)");
  }
  switch (code) {
    case 100:
      set_coordinates(block);
      return true;
    case 280:
    case 300:
      go_home(block, code);
      return true;
    case 281:
    case 301:
      store_home(code);
      return false;
    case 520:
    case 920:
    case 921:
    case 922:
    case 923:
      set_axis_offsets(block, code);
      return code == 520 || code == 920;
    default:
      return false;
  }
}

void Interpreter::State::set_coordinates(const Block& block) {
  // G10 L1/L2/L10/L20.
  const int column = block.g_codes.front().column;
  if (!block.has('l')) fail(column, "G10 needs an L word");
  const long l = std::lround(block.value('l'));
  if (!block.has('p')) fail(column, "G10 needs a P word");
  require_word_in_range(block, 'p', -kMaxToolNumber, kMaxToolNumber,
                        "G10 P (a coordinate system or tool) goes from");
  const long p = std::lround(block.value('p'));
  if (l == 2 || l == 20) {
    set_coordinate_system(block, l, p);
  } else if (l == 1 || l == 10 || l == 11) {
    set_tool_entry(block, l, p, column);
  } else {
    fail(block.word('l')->column, "G10 L" + std::to_string(l) + " is not supported");
  }
}

void Interpreter::State::set_coordinate_system(const Block& block, long l, long p) {
  const int system = p == 0 ? coord_system : static_cast<int>(p);
  if (system < 1 || system > 9) fail(block.word('p')->column, "G10 P must be 0..9");
  if (system == coord_system) {
    refuse_with_compensation(block.g_codes.front(), "change the active coordinate system");
  }
  if (l == 20 && block.has('r')) {
    fail(block.word('r')->column, "R is not allowed in G10 L20 (turn a system with G10 L2 R)");
  }
  const Offsets old = offsets();
  if (l == 20 && (rotation_deg != 0.0 || rotation_of(system) != 0.0)) {
    const Position origin = origin_making_current(block, system);
    const bool xy = block.has('x') || block.has('y');
    for (int axis = 0; axis < kAxes; ++axis) {
      if (block.has(kAxisLetters[axis]) || (xy && axis <= kY)) {
        parameters.set_numbered(5201 + 20 * system + axis, origin[axis]);
      }
    }
  } else {
    for (int axis = 0; axis < kAxes; ++axis) {
      if (!block.has(kAxisLetters[axis])) continue;
      double value = axis_to_mm(axis, block.value(kAxisLetters[axis]));
      if (l == 20) {
        // The current point gets the given coordinate in that system.
        const Position g5x = g5x_mm(coord_system);
        const double machine =
            axis_to_mm(axis, pos[axis]) + g5x[axis] + g92_mm[axis] + tool_offset_mm[axis];
        value = machine - value - g92_mm[axis] - tool_offset_mm[axis];
      }
      parameters.set_numbered(5201 + 20 * system + axis, value);
    }
  }
  if (block.has('r')) parameters.set_numbered(5210 + 20 * system, block.value('r'));
  if (system == coord_system) {
    rotation_deg = rotation_of(system);
    reexpress(old, false);
    emit_offsets(block);
  }
}

Position Interpreter::State::origin_making_current(const Block& block, int system) const {
  const Position point = current_in_system_mm(system, false);
  Position origin = g5x_mm(system);
  for (int axis = kZ; axis < kAxes; ++axis) {
    if (!block.has(kAxisLetters[axis])) continue;
    origin[axis] += point[axis] - axis_to_mm(axis, block.value(kAxisLetters[axis]));
  }
  // X and Y are turned with the system: its origin moves by the turned difference.
  double current_x = point[kX], current_y = point[kY];
  double wanted_x = block.has('x') ? to_mm(block.value('x')) : current_x;
  double wanted_y = block.has('y') ? to_mm(block.value('y')) : current_y;
  rotate_xy(current_x, current_y, rotation_of(system));
  rotate_xy(wanted_x, wanted_y, rotation_of(system));
  origin[kX] += current_x - wanted_x;
  origin[kY] += current_y - wanted_y;
  return origin;
}

Position Interpreter::State::current_in_system_mm(int system, bool without_tool) const {
  Position point;
  for (int axis = 0; axis < kAxes; ++axis) point[axis] = axis_to_mm(axis, pos[axis]) + g92_mm[axis];
  rotate_xy(point[kX], point[kY], rotation_deg);
  const Position active = g5x_mm(coord_system), target = g5x_mm(system);
  for (int axis = 0; axis < kAxes; ++axis) {
    point[axis] += active[axis] + (without_tool ? tool_offset_mm[axis] : 0.0) - target[axis];
  }
  rotate_xy(point[kX], point[kY], -rotation_of(system));
  if (parameters.numbered(5210) != 0.0) {
    for (int axis = 0; axis < kAxes; ++axis) point[axis] -= parameters.numbered(5211 + axis);
  }
  return point;
}

void Interpreter::State::set_tool_entry(const Block& block, long l, long p, int column) {
  // G10 L1/L10/L11: the tool table is the program's to change, as LinuxCNC's is.
  if (!options.tool_table) fail(column, "G10 L" + std::to_string(l) + " needs a tool table");
  auto& table = const_cast<ToolTable&>(*options.tool_table);
  ToolEntry& entry = table[static_cast<int>(p)];
  entry.number = static_cast<int>(p);
  if (l == 1) {
    for (int axis = 0; axis < kAxes; ++axis) {
      if (block.has(kAxisLetters[axis]))
        entry.offset[axis] = axis_to_mm(axis, block.value(kAxisLetters[axis]));
    }
  } else {
    set_tool_offset_from_current(block, l, entry);
  }
  if (block.has('r')) entry.diameter = 2.0 * to_mm(block.value('r'));
  if (const auto& q = block.word('q')) {
    if (!(q->value >= 0.0 && q->value <= 9.0) || q->value != std::floor(q->value)) {
      fail(q->column, "G10 L" + std::to_string(l) + " Q" + written_number(q->value) +
                          ": a lathe tool's orientation is a whole number from 0 to 9");
    }
    entry.orientation = static_cast<int>(q->value);
  }
  require_finite_tool(entry, column);
}

void Interpreter::State::set_tool_offset_from_current(const Block& block, long l,
                                                      ToolEntry& entry) const {
  // L10: the offset that gives the current point the block's coordinates in the active system
  // once the tool's offset is taken up again; L11 the same in G59.3 without G92/G52 offsets.
  const int system = l == 11 ? 9 : coord_system;
  Position point = current_in_system_mm(system, true);
  if (l == 11 && parameters.numbered(5210) != 0.0) {
    for (int axis = 0; axis < kAxes; ++axis) point[axis] += parameters.numbered(5211 + axis);
  }
  for (int axis = kZ; axis < kAxes; ++axis) {
    if (!block.has(kAxisLetters[axis])) continue;
    entry.offset[axis] = point[axis] - axis_to_mm(axis, block.value(kAxisLetters[axis]));
  }
  const bool has_x = block.has('x'), has_y = block.has('y');
  if (!has_x && !has_y) return;
  // X and Y are turned with the system; a word for one keeps the entry's offset along the other.
  const double turn = rotation_of(system);
  double kept_x = 0.0, kept_y = 0.0;
  if (!has_x || !has_y) {
    kept_x = entry.offset[kX], kept_y = entry.offset[kY];
    rotate_xy(kept_x, kept_y, -turn);
    (has_x ? kept_x : kept_y) = 0.0;
    rotate_xy(kept_x, kept_y, turn);
  }
  double x = has_x ? point[kX] - to_mm(block.value('x')) : 0.0;
  double y = has_y ? point[kY] - to_mm(block.value('y')) : 0.0;
  rotate_xy(x, y, turn);
  entry.offset[kX] = x + kept_x;
  entry.offset[kY] = y + kept_y;
}

void Interpreter::State::go_home(const Block& block, int code) {
  // G28/G30: through the programmed axes' intermediate point, then to the stored position
  // (#5161.. / #5181.., machine coordinates) of those axes, or of all axes when none is given.
  const int base = code == 280 ? 5161 : 5181;
  const bool any = (block.letters & kAxisSlots) != 0;
  // The intermediate move is made even when it goes nowhere, as LinuxCNC makes it.
  straight(CanonKind::traverse, block, target(block, false));
  Position stored{};
  for (int axis = 0; axis < kAxes; ++axis) stored[axis] = parameters.numbered(base + axis);
  const Position stored_here = program_from_machine(stored);
  Position home = pos;
  for (int axis = 0; axis < kAxes; ++axis) {
    if (any && !block.has(kAxisLetters[axis])) continue;
    home[axis] = stored_here[axis];
  }
  straight(CanonKind::traverse, block, home);
}

void Interpreter::State::store_home(int code) {
  // G28.1/G30.1: the current machine position becomes the G28/G30 home.
  const Position machine = machine_mm(pos);
  for (int axis = 0; axis < kAxes; ++axis) {
    parameters.set_numbered((code == 281 ? 5161 : 5181) + axis, machine[axis]);
  }
}

void Interpreter::State::set_axis_offsets(const Block& block, int code) {
  const Offsets old = offsets();
  if (code == 520) {
    // G52: the offset itself is given (LinuxCNC keeps it where G92 keeps its offset).
    for (int axis = 0; axis < kAxes; ++axis) {
      if (!block.has(kAxisLetters[axis])) continue;
      g92_mm[axis] = axis_to_mm(axis, block.value(kAxisLetters[axis]));
      parameters.set_numbered(5211 + axis, g92_mm[axis]);
    }
    parameters.set_numbered(5210, 1.0);
  } else if (code == 920) {
    for (int axis = 0; axis < kAxes; ++axis) {
      if (!block.has(kAxisLetters[axis])) continue;
      g92_mm[axis] += axis_to_mm(axis, pos[axis] - block.value(kAxisLetters[axis]));
      parameters.set_numbered(5211 + axis, g92_mm[axis]);
    }
    parameters.set_numbered(5210, 1.0);
  } else if (code == 921 || code == 922) {
    g92_mm = {};
    parameters.set_numbered(5210, 0.0);
    if (code == 921) {
      for (int axis = 0; axis < kAxes; ++axis) parameters.set_numbered(5211 + axis, 0.0);
    }
  } else {
    // G92.3: the offsets kept in the parameters come back.
    for (int axis = 0; axis < kAxes; ++axis) g92_mm[axis] = parameters.numbered(5211 + axis);
    parameters.set_numbered(5210, 1.0);
  }
  reexpress(old);
  emit_offsets(block);
}

}  // namespace pkm::gcode
