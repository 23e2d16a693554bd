// One block executed in LinuxCNC's order of execution: comments and messages, feed mode, feed,
// spindle speed, tool selection, M codes (tool change, spindle, coolant, passed-on events),
// dwell, modes (plane, units, cutter compensation, tool length, coordinate system, path control,
// distance and retract modes), the non-modal codes (G10, G28/G30, G92), motion, stop and end.
#include <cctype>
#include <cstdio>

#include "pkm/gcode/interpreter_state.hpp"

namespace pkm::gcode {

void Interpreter::State::execute_block(const Block& block) {
  // Most lines of a CAM program are bare axis words continuing a G0 or G1: nothing but the move
  // to make. (The general path below makes the same move; this one skips its checks.)
  if (block.plain && (motion == 0 || motion == 10) && block.letters != 0 &&
      (block.letters & ~kAxisSlots) == 0) {
    motion_changed = false;
    move_column = 1;
    if (motion == 10) require_feed(block, 1);
    target(block, false, move_.end);  // built in place: straight() finds it there
    straight(motion == 0 ? CanonKind::traverse : CanonKind::feed, block, move_.end);
    return;
  }
  apply_assignments(block);
  emit_comments(block);
  if (block.empty) return;
  group_codes(block);
  if (m_by_group[4] && m_by_group[4]->tenths == 980) return call_fanuc_program_alone(block);
  refuse_motion_without_axes(block);
  refuse_unused_words(block);
  check_synchronised_words(block);
  const Code* const non_modal = g_by_group[0];
  const Code* const motion_code = g_by_group[1];
  bool has_axis = (block.letters & (kAxisSlots | kPolarSlots)) != 0;
  // Before the block's S and M3 run, and before its D word (G96's speed limit) is taken for a
  // cutter compensation's.
  if (const Code* const css = g_by_group[14]; css && css->tenths == 960) {
    fail(css->column, "G96 (constant surface speed) is not supported");
  }

  set_feed_speed_and_tool(block, g_by_group[5]);
  if (m_by_group.any()) execute_m_codes(block);  // most blocks have no M code
  dwell_if_asked(block, non_modal);
  if (!g_by_group[7] && block.word('d')) {
    fail(block.word('d')->column, "D word with no G41, G42, G41.1 or G42.1 to use it");
  }
  if (g_by_group.any()) set_modes(block, has_axis);  // most blocks have no G code
  const bool axes_used = non_modal && execute_non_modal(block, *non_modal);

  const bool machine_coordinates = non_modal && non_modal->tenths == 530;
  const bool previous_cycle = is_canned_cycle(motion);
  motion_changed = false;
  if (motion_code) {
    motion_changed = motion_code->tenths != motion;
    if (motion_code->tenths == 800) cycle_series = false;
    motion = motion_code->tenths;
  }
  // An explicit G0..G3 moves even without axis words (to where it is, as LinuxCNC does).
  const bool explicit_move = motion_code && motion_code->tenths <= 30;
  if (!axes_used && (has_axis || explicit_move))
    make_motion(block, motion_code, machine_coordinates);
  if (!motion_code || !is_canned_cycle(motion_code->tenths)) {
    if (previous_cycle && !is_canned_cycle(motion)) cycle_series = false;
  }
  if (m_by_group[4]) stop_or_end(block);
  if (resync_position) {
    // After a tool change the position is where the last move left the tool (off the
    // programmed point after G40), as LinuxCNC re-reads it before the next line.
    pos = canon_pos = tool_off_path.value_or(canon_pos);
    tool_off_path.reset();
    resync_position = false;
  }
}

void Interpreter::State::emit_comments(const Block& block) {
  for (const Comment& comment : block.comments) {
    std::string text = comment.text;
    std::string lower = text;
    for (char& ch : lower) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
    const auto first = lower.find_first_not_of(" \t");
    if (first != std::string::npos && lower.compare(first, 4, "msg,") == 0) {
      Canon message = make(CanonKind::message, block);
      message.text = text.substr(first + 4);
      emit(message);
    } else {
      Canon c = make(CanonKind::comment, block);
      c.text = text;
      emit(c);
    }
  }
}

void Interpreter::State::set_feed_speed_and_tool(const Block& block, const Code* feed_mode_code) {
  if (feed_mode_code) set_feed_mode(block, feed_mode_code->tenths);
  if (block.has('f')) {
    const double f = block.value('f');
    if (f < 0.0) fail(block.word('f')->column, "negative F word");
    feed = f;
    if (feed_mode != FeedMode::inverse_time) {
      Canon c = make(CanonKind::set_feed_rate, block);
      c.value = f;
      emit(c);
    }
  }
  if (block.has('s')) {
    if (block.value('s') < 0.0) fail(block.word('s')->column, "negative spindle speed");
    require_word_in_range(block, 's', 0.0, kMaxSpindleRpm, "a spindle speed (rpm) goes from");
    speed = block.value('s');
    Canon c = make(CanonKind::spindle_speed, block);
    c.value = speed;
    emit(c);
  }
  if (block.has('t')) select_tool(block);
}

void Interpreter::State::set_feed_mode(const Block& block, int code) {
  feed_mode = code == 930   ? FeedMode::inverse_time
              : code == 950 ? FeedMode::units_per_revolution
                            : FeedMode::units_per_minute;
  Canon c = make(CanonKind::set_feed_mode, block);
  c.feed_mode = feed_mode;
  emit(c);
  // G94 and G95 forget the feed rate, as LinuxCNC does: F is per minute or per revolution.
  if (code != 930) {
    feed = 0.0;
    emit(make(CanonKind::set_feed_rate, block));
  }
}

// M19: LinuxCNC orients the spindle only when R or P is given (to R, 0 without it, plus the INI's
// ORIENT_OFFSET) and with Q waits up to Q seconds for it.
void Interpreter::State::orient_spindle(const Block& block) {
  const auto& p = block.word('p');
  if (p && p->value != 0.0 && p->value != 1.0 && p->value != 2.0) {
    fail(p->column, "M19 P" + written_number(p->value) +
                        ": the direction must be 0 (the shorter way), 1 (clockwise) or 2 "
                        "(counterclockwise)");
  }
  const auto& q = block.word('q');
  if (q && !(q->value > 0.0)) {
    fail(q->column, "Q word with M19 requires a value > 0 (the seconds to wait for the spindle)");
  }
  if (block.has('r') || p) {
    Canon c = make(CanonKind::orient_spindle, block);
    c.value = (block.has('r') ? block.value('r') : 0.0) + options.orient_offset_deg;
    c.integer = p ? static_cast<int>(p->value) : 0;
    emit(c);
  }
  if (q) {
    Canon c = make(CanonKind::wait_orient_spindle, block);
    c.value = q->value;
    emit(c);
  }
}

void Interpreter::State::execute_m_codes(const Block& block) {
  if (m_by_group[6]) change_tool(block, *m_by_group[6]);
  if (const Code* const code = m_by_group[7]; code && code->tenths >= 700) {
    save_or_restore_modes(*code);  // M70-M73, where LinuxCNC runs them
  } else if (code) {
    if (code->tenths == 30) emit(CanonKind::spindle_clockwise, block);
    if (code->tenths == 40) emit(CanonKind::spindle_counterclockwise, block);
    if (code->tenths == 50) emit(CanonKind::spindle_stop, block);
    if (code->tenths == 190) orient_spindle(block);
    // M19 orients it: stopped.
    spindle_direction = code->tenths == 30 ? 1 : code->tenths == 40 ? -1 : 0;
  }
  for (const int group : {8, 11}) {
    if (!m_by_group[group]) continue;
    const int code = m_by_group[group]->tenths;
    if (code == 70) emit(CanonKind::mist_on, block);
    if (code == 80) emit(CanonKind::flood_on, block);
    if (code == 90) {
      emit(CanonKind::mist_off, block);
      emit(CanonKind::flood_off, block);
    }
    mist = code == 70 || (mist && code == 80);
    flood = code == 80 || (flood && code == 70);
  }
  if (m_by_group[9]) set_override_state(block, m_by_group[9]->tenths);
  // Overrides, digital and analog I/O and user codes: a real machine's business, passed on,
  // I/O and user codes with their words (M62 P1, M66 P0 L3 Q2, M101 P2 Q3) so that a joint
  // program can carry them whole.
  for (const int group : {9, 5, 10}) {
    if (!m_by_group[group]) continue;
    const int code = m_by_group[group]->tenths;
    Canon event = make(CanonKind::event, block);
    event.text = code_name('M', code);
    if (group != 9) {
      for (const char letter : {'p', 'e', 'l', 'q'}) {
        if (!block.has(letter)) continue;
        char word[40];
        std::snprintf(word, sizeof word, " %c%.10g", letter - 'a' + 'A', block.value(letter));
        event.text += word;
      }
    }
    if (group == 10) warn(code_name('M', code) + " (user M-code) passed on as an event");
    emit(event);
  }
}

void Interpreter::State::set_override_state(const Block& block, int code) {
  // M50-M53 enable without a P word or with any P but P0, as LinuxCNC reads them.
  const bool enable = !block.has('p') || block.value('p') != 0.0;
  if (code == 480 || code == 490) feed_override_on = speed_override_on = code == 480;
  if (code == 500) feed_override_on = enable;
  if (code == 510) speed_override_on = enable;
  if (code == 520) adaptive_feed_on = enable;
  if (code == 530) feed_hold_on = enable;
}

void Interpreter::State::dwell_if_asked(const Block& block, const Code* non_modal) {
  if (!non_modal || non_modal->tenths != 40) return;
  if (!block.has('p')) fail(non_modal->column, "G4 needs a P word (seconds)");
  if (block.value('p') < 0.0) fail(block.word('p')->column, "negative dwell");
  dwell(block, block.value('p'));
}

void Interpreter::State::set_modes(const Block& block, bool& has_axis) {
  if (const auto code = g_by_group[2]) {
    const Plane wanted = code->tenths == 170   ? Plane::xy
                         : code->tenths == 180 ? Plane::xz
                                               : Plane::yz;
    if (wanted != plane) refuse_with_compensation(*code, "change planes");
    plane = wanted;
    emit(CanonKind::select_plane, block);
  }
  if (const auto code = g_by_group[6]) {
    set_units(code->tenths == 200 ? LengthUnits::inch : LengthUnits::mm);
    emit(CanonKind::use_length_units, block);
  }
  if (const auto code = g_by_group[7]) set_compensation(block, *code);
  if (const auto code = g_by_group[8]) set_tool_length_offset(block, *code, has_axis);
  if (const auto code = g_by_group[12]) select_coordinate_system(block, *code);
  if (const auto code = g_by_group[13]) set_path_control(block, *code);
  if (const auto code = g_by_group[3]) absolute = code->tenths == 900;
  if (const auto code = g_by_group[4]) arc_absolute = code->tenths == 901;
  if (const auto code = g_by_group[10]) retract_to_old = code->tenths == 980;
  // Group 15, lathe radius (G8) and diameter (G7) mode: after G7 LinuxCNC reads X words (and
  // G76's I J K) as diameters, which pkm does not: refused rather than cut twice as far out.
  if (const auto code = g_by_group[15]; code && code->tenths == 70) {
    fail(code->column,
         "G7 (lathe diameter mode) is not supported: X would be a diameter; give "
         "radii in G8");
  }
}

void Interpreter::State::set_units(LengthUnits wanted) {
  if (wanted == units) return;
  const double factor = wanted == LengthUnits::inch ? 1.0 / kMmPerInch : kMmPerInch;
  for (int axis = 0; axis < kAxes; ++axis) {
    if (!is_linear(axis)) continue;
    pos[axis] *= factor;
    canon_pos[axis] *= factor;
  }
  feed *= factor;
  units = wanted;
  compensation.rescale(factor, units);
}

void Interpreter::State::set_path_control(const Block& block, const Code& code) {
  refuse_with_compensation(code, "change the path control mode");
  path_mode = code.tenths == 640 ? 64 : code.tenths == 610 ? 61 : 611;
  path_tolerance = code.tenths == 640 && block.has('p') ? block.value('p') : 0.0;
  naive_tolerance = code.tenths == 640 && block.has('q') ? block.value('q') : 0.0;
  Canon c = make(CanonKind::path_control, block);
  c.integer = path_mode;
  c.value = path_tolerance;
  c.value2 = naive_tolerance;
  emit(c);
}

void Interpreter::State::call_fanuc_program_alone(const Block& block) {
  // LinuxCNC runs an M98 line as a call and nothing else (it refuses axis words and G codes
  // there, and drops other M codes): pkm refuses whatever else the line asks for.
  constexpr std::uint32_t kCallWords = (1u << ('p' - 'a')) | (1u << ('l' - 'a'));
  const Code& m98 = *m_by_group[4];
  if (!block.g_codes.empty() || block.m_codes.size() > 1 || (block.letters & ~kCallWords) != 0) {
    fail(m98.column,
         "M98 takes only its P and L words: put the line's other codes and words on "
         "a line of their own");
  }
  call_fanuc_program(block, m98);
}

void Interpreter::State::stop_or_end(const Block& block) {
  const int code = m_by_group[4]->tenths;
  if (code == 990) return return_from_fanuc_program(block, *m_by_group[4]);
  release_compensation(m_by_group[4]->column);
  if (code == 0) emit(CanonKind::program_stop, block);
  if (code == 10) emit(CanonKind::optional_stop, block);
  if (code == 600) {
    Canon stop = make(CanonKind::program_stop, block);
    stop.integer = 60;  // M60's pallet shuttle, then the stop
    emit(stop);
  }
  if (code == 20 || code == 300) end_program(block);
}

void Interpreter::State::end_program(const Block& block) {
  // LinuxCNC resets the modal state at the program end.
  const Offsets old = offsets();
  const bool plane_changes = plane != Plane::xy;
  coord_system = 1;
  rotation_deg = rotation_of(1);
  g92_mm = {};
  reexpress(old);
  plane = Plane::xy;
  absolute = true;
  motion = 10;
  cycle_series = false;
  compensation.turn_off();  // nothing is held any more: the stop released it
  straight_exit = false;
  emit_offsets(block);
  if (plane_changes) emit(CanonKind::select_plane, block);
  set_feed_mode(block, 940);  // G94 and no feed rate, as rs274 ends
  emit(CanonKind::spindle_stop, block);
  spindle_direction = 0;
  if (mist) emit(CanonKind::mist_off, block);
  if (flood) emit(CanonKind::flood_off, block);
  mist = flood = false;
  feed_override_on = speed_override_on = true;
  emit(CanonKind::program_end, block);
  saw_end = true;
  ended = true;
}

}  // namespace pkm::gcode
