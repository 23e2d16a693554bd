// Tools: selection (T), change (M6, M61), tool length offsets (G43, G43.1, G49) from the tool
// table, and cutter radius compensation (G40, G41/G42 with a tool's diameter, G41.1/G42.1 with
// a D word's) turned on and off; the offset path itself is cutter_compensation.cpp's.
#include <cmath>

#include "pkm/gcode/interpreter_state.hpp"

namespace pkm::gcode {

void Interpreter::State::select_tool(const Block& block) {
  require_word_in_range(block, 't', -kMaxToolNumber, kMaxToolNumber, "tool numbers go from");
  const long t = std::lround(block.value('t'));
  if (t < 0) fail(block.word('t')->column, "negative tool number");
  if (options.tool_table && t != 0 && !options.tool_table->count(static_cast<int>(t))) {
    fail(block.word('t')->column,
         "requested tool " + std::to_string(t) + " not found in the tool table");
  }
  if (!options.tool_table && t != 0)
    warn("T" + std::to_string(t) + " without a tool table: no offsets known");
  selected_tool = static_cast<int>(t);
  Canon c = make(CanonKind::select_tool, block);
  c.integer = selected_tool;
  emit(c);
}

void Interpreter::State::change_tool(const Block& block, const Code& code) {
  refuse_with_compensation(code, "change tools");
  if (code.tenths == 60) {
    Canon c = make(CanonKind::change_tool, block);
    c.integer = selected_tool;
    emit(c);
  }
  resync_position = true;
  require_word_in_range(block, 'q', -kMaxToolNumber, kMaxToolNumber, "tool numbers go from");
  tool_in_spindle =
      code.tenths == 610 ? static_cast<int>(block.has('q') ? block.value('q') : 0) : selected_tool;
}

void Interpreter::State::set_tool_length_offset(const Block& block, const Code& code,
                                                bool& has_axis) {
  refuse_with_compensation(code, "change the tool length offset");
  Position offset{};
  if (code.tenths == 430) {
    require_word_in_range(block, 'h', -kMaxToolNumber, kMaxToolNumber, "tool numbers go from");
    const int tool =
        block.has('h') ? static_cast<int>(std::lround(block.value('h'))) : tool_in_spindle;
    if (tool != 0) {
      if (options.tool_table && !options.tool_table->count(tool)) {
        fail(code.column, "tool " + std::to_string(tool) + " for G43 not in the tool table");
      }
      if (options.tool_table) offset = options.tool_table->at(tool).offset;
    }
  } else if (code.tenths == 431) {
    for (int axis = 0; axis < kAxes; ++axis) {
      if (block.has(kAxisLetters[axis]))
        offset[axis] = axis_to_mm(axis, block.value(kAxisLetters[axis]));
    }
    has_axis = false;  // the axis words were the offset
  } else if (code.tenths == 432) {
    fail(code.column, "G43.2 is not supported");
  }
  // The machine stays where it is: the program position takes up the change of length, so
  // an axis the next move does not name keeps its machine coordinate (as rs274 shows: G43 H1
  // at Z10 with a 12.7 mm tool, then G0 X5, goes to Z-2.7). LinuxCNC does not turn the change
  // by a coordinate system's rotation, and neither does pkm.
  for (int axis = 0; axis < kAxes; ++axis) {
    pos[axis] += axis_from_mm(axis, tool_offset_mm[axis] - offset[axis]);
  }
  tool_offset_mm = offset;
  tool_length_g43 = code.tenths == 430;
  Canon c = make(CanonKind::tool_length_offset, block);
  for (int axis = 0; axis < kAxes; ++axis) c.end[axis] = axis_from_mm(axis, offset[axis]);
  emit(c);
}

void Interpreter::State::set_compensation(const Block& block, const Code& code) {
  if (code.tenths != 400) return start_compensation(block, code);
  const Position tool = compensation.tool_position(pos);
  compensating(code.column, [&] { straight_exit = compensation.turn_off(); });
  if (straight_exit) tool_off_path = tool;
}

void Interpreter::State::start_compensation(const Block& block, const Code& code) {
  if (plane == Plane::yz) {
    fail(code.column, "cutter radius compensation works in the XY (G17) or XZ (G18) plane only");
  }
  if (compensation.on()) fail(code.column, "cutter radius compensation is already on (G40 first)");
  const CompensationTool tool = compensation_tool(block, code);
  compensation.turn_on(
      code.tenths == 410 || code.tenths == 411 ? CompensationSide::left : CompensationSide::right,
      tool.radius, plane, tool.orientation);
}

Interpreter::State::CompensationTool Interpreter::State::compensation_tool(const Block& block,
                                                                           const Code& code) {
  const std::string name = code_name('G', code.tenths);
  const auto& d = block.word('d');
  if (code.tenths == 411 || code.tenths == 421) {
    // G41.1/G42.1: the D word is the tool's diameter, the L word a lathe tool's orientation.
    if (!d) fail(code.column, name + " needs a D word: the tool diameter");
    int orientation = 0;
    if (const auto& l = block.word('l')) {
      if (plane != Plane::xz) {
        fail(l->column, name + " with an L word (lathe tool orientation) needs the XZ plane (G18)");
      }
      if (!(l->value >= 0.0 && l->value <= 9.0) || l->value != std::floor(l->value)) {
        fail(l->column, name + " L" + written_number(l->value) +
                            ": a lathe tool's orientation is a whole number from 0 to 9");
      }
      orientation = static_cast<int>(l->value);
    }
    return {d->value / 2.0, orientation};
  }
  // G41/G42: the D word names a tool in the table; without one, the tool in the spindle.
  int tool = tool_in_spindle;
  const int column = d ? d->column : code.column;
  if (d) {
    require_word_in_range(block, 'd', -kMaxToolNumber, kMaxToolNumber, "tool numbers go from");
    const double number = std::round(d->value);
    if (std::abs(d->value - number) >= 1e-4) {
      fail(d->column, name + " needs D to be a whole number: a tool in the tool table");
    }
    if (number < 0.0) fail(d->column, "negative D word (tool number)");
    tool = static_cast<int>(number);
  }
  CompensationTool found;  // radius in program units
  if (tool != 0) {
    if (!options.tool_table) {
      fail(column, name + " needs a tool table (--tool-table) for the diameter of tool " +
                       std::to_string(tool));
    }
    const auto entry = options.tool_table->find(tool);
    if (entry == options.tool_table->end()) {
      fail(column, "tool " + std::to_string(tool) + " for " + name + " is not in the tool table");
    }
    found = {from_mm(entry->second.diameter) / 2.0, entry->second.orientation};
  }
  if (found.orientation != 0 && found.orientation != 9 && plane != Plane::xz) {
    fail(column, name + " with tool " + std::to_string(tool) + ", a lathe tool (orientation " +
                     std::to_string(found.orientation) + "), needs the XZ plane (G18)");
  }
  if (found.radius == 0.0) {
    warn(name + " with tool " + std::to_string(tool) +
         " of zero diameter: the moves are not offset");
  }
  return found;
}

}  // namespace pkm::gcode
