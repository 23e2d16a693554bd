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

void Interpreter::State::reexpress(const Position& old_total_mm) {
  const Position now = total_offset_mm();
  for (int axis = 0; axis < kAxes; ++axis) {
    pos[axis] += axis_from_mm(axis, old_total_mm[axis] - now[axis]);
  }
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

void Interpreter::State::select_coordinate_system(const Block& block, const Code& code) {
  static constexpr int kCodes[] = {540, 550, 560, 570, 580, 590, 591, 592, 593};
  const int system = static_cast<int>(std::find(std::begin(kCodes), std::end(kCodes), code.tenths) -
                                      std::begin(kCodes)) +
                     1;
  refuse_with_compensation(code, "change coordinate systems");
  const Position old_total = total_offset_mm();
  coord_system = system;
  parameters.set_numbered(5220, system);
  reexpress(old_total);
  emit_offsets(block);
}

bool Interpreter::State::execute_non_modal(const Block& block, const Code& non_modal) {
  const int code = non_modal.tenths;
  if (code == 280 || code == 300) refuse_with_compensation(non_modal, "use G28 or G30");
  if (code >= 920 && code <= 923) refuse_with_compensation(non_modal, "change axis offsets");
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
    case 920:
    case 921:
    case 922:
    case 923:
      set_axis_offsets(block, code);
      return code == 920;
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
  } else if (l == 1 || l == 10) {
    set_tool_entry(block, p, column);
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
  const Position old_total = total_offset_mm();
  for (int axis = 0; axis < kAxes; ++axis) {
    if (!block.has(kAxisLetters[axis])) continue;
    const int number = 5201 + 20 * system + axis;
    double value = axis_to_mm(axis, block.value(kAxisLetters[axis]));
    if (l == 20) {
      // The current point gets the given coordinate in that system.
      const Position g5x = g5x_mm(coord_system);
      const double machine =
          axis_to_mm(axis, pos[axis]) + g5x[axis] + g92_mm[axis] + tool_offset_mm[axis];
      value = machine - value - g92_mm[axis] - tool_offset_mm[axis];
    }
    parameters.set_numbered(number, value);
  }
  if (system == coord_system) {
    reexpress(old_total);
    emit_offsets(block);
  }
}

void Interpreter::State::set_tool_entry(const Block& block, long p, int column) {
  // G10 L1/L10: the tool table is the program's to change, as LinuxCNC's is.
  if (!options.tool_table) fail(column, "G10 L1/L10 needs a tool table");
  auto& table = const_cast<ToolTable&>(*options.tool_table);
  ToolEntry& entry = table[static_cast<int>(p)];
  entry.number = static_cast<int>(p);
  for (int axis = 0; axis < kAxes; ++axis) {
    if (block.has(kAxisLetters[axis]))
      entry.offset[axis] = axis_to_mm(axis, block.value(kAxisLetters[axis]));
  }
  if (block.has('r')) entry.diameter = 2.0 * to_mm(block.value('r'));
  require_finite_tool(entry, column);
}

void Interpreter::State::go_home(const Block& block, int code) {
  // G28/G30: through the programmed axes' intermediate point, then to the stored position
  // (#5161.. / #5181.., machine coordinates) of those axes, or of all axes when none is given.
  const int base = code == 280 ? 5161 : 5181;
  const bool any = (block.letters & kAxisSlots) != 0;
  // The intermediate move is made even when it goes nowhere, as LinuxCNC makes it.
  straight(CanonKind::traverse, block, target(block, false));
  const Position offsets = total_offset_mm();
  Position home = pos;
  for (int axis = 0; axis < kAxes; ++axis) {
    if (any && !block.has(kAxisLetters[axis])) continue;
    home[axis] = axis_from_mm(axis, parameters.numbered(base + axis) - offsets[axis]);
  }
  straight(CanonKind::traverse, block, home);
}

void Interpreter::State::store_home(int code) {
  // G28.1/G30.1: the current machine position becomes the G28/G30 home.
  const Position offsets = total_offset_mm();
  for (int axis = 0; axis < kAxes; ++axis) {
    parameters.set_numbered((code == 281 ? 5161 : 5181) + axis,
                            axis_to_mm(axis, pos[axis]) + offsets[axis]);
  }
}

void Interpreter::State::set_axis_offsets(const Block& block, int code) {
  const Position old_total = total_offset_mm();
  if (code == 920) {
    for (int axis = 0; axis < kAxes; ++axis) {
      if (!block.has(kAxisLetters[axis])) continue;
      g92_mm[axis] += axis_to_mm(axis, pos[axis] - block.value(kAxisLetters[axis]));
      parameters.set_numbered(5211 + axis, g92_mm[axis]);
    }
    parameters.set_numbered(5210, 1.0);
  } else if (code == 921 || code == 922) {
    g92_mm = {};
    if (code == 921) {
      for (int axis = 0; axis < kAxes; ++axis) parameters.set_numbered(5211 + axis, 0.0);
      parameters.set_numbered(5210, 0.0);
    }
  } else {
    // G92.3: the offsets kept in the parameters come back.
    for (int axis = 0; axis < kAxes; ++axis) g92_mm[axis] = parameters.numbered(5211 + axis);
  }
  reexpress(old_total);
  emit_offsets(block);
}

}  // namespace pkm::gcode
