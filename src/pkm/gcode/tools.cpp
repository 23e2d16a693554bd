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
  Position offset{};  // G49
  if (code.tenths == 430) {
    offset = table_tool_offset(block, code);
  } else if (code.tenths == 431) {
    // G43.1 replaces the offsets of the axes it names; the others keep theirs (rs274: G43 H1,
    // then G43.1 X0.1, keeps tool 1's Z offset).
    offset = tool_offset_mm;
    for (int axis = 0; axis < kAxes; ++axis) {
      if (block.has(kAxisLetters[axis]))
        offset[axis] = axis_to_mm(axis, block.value(kAxisLetters[axis]));
    }
    has_axis = false;  // the axis words were the offset
  } else if (code.tenths == 432) {
    // G43.2 H adds a tool's offsets to those in effect (LinuxCNC 2.9's rs274 knows only the H
    // form; a later LinuxCNC adds axis words instead, which pkm refuses rather than guess).
    if ((block.letters & kAxisSlots) != 0 || !block.has('h')) {
      fail(code.column, "G43.2 needs an H word (a tool whose offsets to add) and no axis words");
    }
    const Position added = table_tool_offset(block, code);
    offset = tool_offset_mm;
    for (int axis = 0; axis < kAxes; ++axis) offset[axis] += added[axis];
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

Position Interpreter::State::table_tool_offset(const Block& block, const Code& code) const {
  require_word_in_range(block, 'h', -kMaxToolNumber, kMaxToolNumber, "tool numbers go from");
  // H0, like no H, is the tool in the spindle (LinuxCNC's tool table index 0): rs274 gives
  // T1 M6 G43 H0 tool 1's offset.
  const long h = block.has('h') ? std::lround(block.value('h')) : 0;
  const int tool = h != 0 ? static_cast<int>(h) : tool_in_spindle;
  if (tool == 0 || !options.tool_table) return {};
  const auto entry = options.tool_table->find(tool);
  if (entry == options.tool_table->end()) {
    fail(code.column, "tool " + std::to_string(tool) + " for " + code_name('G', code.tenths) +
                          " not in the tool table");
  }
  return entry->second.offset;
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
