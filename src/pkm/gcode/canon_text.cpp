#include <cstring>
#include <initializer_list>
#include <string_view>

#include "pkm/gcode/canon.hpp"
#include "pkm/text/decimal_text.hpp"

namespace pkm::gcode {

namespace {

// The text of one command, written in place at the end of a buffer: `rs274 -g` prints numbers as
// %.4f (and one as %f), written here by pkm::text, which gives printf's digits. Room for the
// longest command is made once, so each piece is written without a check.
class CanonWriter {
 public:
  CanonWriter(text::TextBuffer& out, std::size_t text_bytes)
      : out_(out), cursor_(out.room(kLongestWords + 9 * (text::kMaxFixedChars + 2) + text_bytes)) {}
  ~CanonWriter() { out_.commit(cursor_); }
  CanonWriter(const CanonWriter&) = delete;
  CanonWriter& operator=(const CanonWriter&) = delete;

  CanonWriter& operator<<(std::string_view text) {
    std::memcpy(cursor_, text.data(), text.size());
    cursor_ += text.size();
    return *this;
  }
  CanonWriter& operator<<(char c) {
    *cursor_++ = c;
    return *this;
  }
  CanonWriter& operator<<(int value) {
    cursor_ = text::write_int(cursor_, value);
    return *this;
  }
  CanonWriter& operator<<(double value) {  // %.4f
    cursor_ = text::write_fixed<4>(cursor_, value);
    return *this;
  }
  CanonWriter& with_6_decimals(double value) {  // %f
    cursor_ = text::write_fixed<6>(cursor_, value);
    return *this;
  }
  // Numbers separated by `separator`.
  CanonWriter& list(std::initializer_list<double> values, std::string_view separator = ", ") {
    bool first = true;
    for (const double value : values) {
      if (!first) *this << separator;
      first = false;
      *this << value;
    }
    return *this;
  }
  CanonWriter& six(const Position& p) { return list({p[0], p[1], p[2], p[3], p[4], p[5]}); }

 private:
  // Room for every word, separator and integer of a command but its numbers and its text.
  static constexpr std::size_t kLongestWords = 256;
  text::TextBuffer& out_;
  char* cursor_;
};

// The arc's first and second axes and the axis normal to its plane, as LinuxCNC orders them.
void plane_axes(Plane plane, int& first, int& second, int& normal) {
  switch (plane) {
    case Plane::xy:
      first = 0, second = 1, normal = 2;
      return;
    case Plane::xz:
      first = 2, second = 0, normal = 1;
      return;
    case Plane::yz:
      first = 1, second = 2, normal = 0;
      return;
  }
}

const char* plane_name(Plane plane) {
  switch (plane) {
    case Plane::xy:
      return "CANON_PLANE_XY";
    case Plane::xz:
      return "CANON_PLANE_XZ";
    case Plane::yz:
      return "CANON_PLANE_YZ";
  }
  return "";
}

// Moves, dwells and spindle-synchronised motion.
void write_motion(const Canon& c, CanonWriter& w) {
  switch (c.kind) {
    case CanonKind::traverse:
      w << "STRAIGHT_TRAVERSE(";
      w.six(c.end) << ')';
      return;
    case CanonKind::feed:
      w << "STRAIGHT_FEED(";
      w.six(c.end) << ')';
      return;
    case CanonKind::probe:
      w << "STRAIGHT_PROBE(";
      w.six(c.end) << ')';
      return;
    case CanonKind::arc: {
      int first = 0, second = 0, normal = 0;
      plane_axes(c.plane, first, second, normal);
      w << "ARC_FEED(";
      w.list({c.end[first], c.end[second], c.center[0], c.center[1]}) << ", " << c.turns << ", ";
      w.list({c.end[normal], c.end[3], c.end[4], c.end[5]}) << ')';
      return;
    }
    case CanonKind::dwell:
      w << "DWELL(" << c.value << ')';
      return;
    case CanonKind::rigid_tap:
      w << "RIGID_TAP(";
      w.list({c.end[0], c.end[1], c.end[2]}) << ')';
      return;
    case CanonKind::speed_feed_sync:  // the pitch as %f
      w << "START_SPEED_FEED_SYNC(";
      w.with_6_decimals(c.value) << ",0)";
      return;
    case CanonKind::speed_feed_sync_stop:
      w << "STOP_SPEED_FEED_SYNCH()";
      return;
    default:  // the other kinds are written by the other write_* functions
      return;
  }
}

// Modal settings: feed, plane, units, path control, offsets and overrides.
void write_setting(const Canon& c, CanonWriter& w) {
  switch (c.kind) {
    case CanonKind::set_feed_rate:
      w << "SET_FEED_RATE(" << c.value << ')';
      return;
    case CanonKind::set_feed_mode:
      // rs274 tells the machine per minute (0) or per revolution (1); G93 is per minute to it.
      w << "SET_FEED_MODE(0, " << (c.feed_mode == FeedMode::units_per_revolution ? 1 : 0) << ')';
      return;
    case CanonKind::select_plane:
      w << "SELECT_PLANE(" << plane_name(c.plane) << ')';
      return;
    case CanonKind::use_length_units:
      w << (c.units == LengthUnits::inch ? "USE_LENGTH_UNITS(CANON_UNITS_INCHES)"
                                         : "USE_LENGTH_UNITS(CANON_UNITS_MM)");
      return;
    case CanonKind::path_control:
      if (c.integer == 64) {  // the tolerance as %f
        w << "SET_MOTION_CONTROL_MODE(CANON_CONTINUOUS, ";
        w.with_6_decimals(c.value) << ')';
        return;
      }
      w << (c.integer == 61 ? "SET_MOTION_CONTROL_MODE(CANON_EXACT_PATH)"
                            : "SET_MOTION_CONTROL_MODE(CANON_EXACT_STOP)");
      return;
    case CanonKind::xy_rotation:
      w << "SET_XY_ROTATION(" << c.value << ')';
      return;
    case CanonKind::tool_length_offset:
      w << "USE_TOOL_LENGTH_OFFSET(";
      w.list({c.end[0], c.end[1], c.end[2]}, " ") << ", ";
      w.list({c.end[3], c.end[4], c.end[5]}, " ") << ", ";
      w.list({c.end[6], c.end[7], c.end[8]}, " ") << ')';
      return;
    case CanonKind::g5x_offset:
      w << "SET_G5X_OFFSET(" << c.integer << ", ";
      w.six(c.end) << ')';
      return;
    case CanonKind::g92_offset:
      w << "SET_G92_OFFSET(";
      w.six(c.end) << ')';
      return;
    case CanonKind::feed_override:
      w << (c.integer ? "ENABLE_FEED_OVERRIDE()" : "DISABLE_FEED_OVERRIDE()");
      return;
    case CanonKind::speed_override:
      w << (c.integer ? "ENABLE_SPEED_OVERRIDE(0)" : "DISABLE_SPEED_OVERRIDE(0)");
      return;
    default:  // the other kinds are written by the other write_* functions
      return;
  }
}

// The spindle, coolant and tool changer.
void write_spindle_coolant_tool(const Canon& c, CanonWriter& w) {
  switch (c.kind) {
    case CanonKind::spindle_speed:
      w << "SET_SPINDLE_SPEED(0, " << c.value << ')';
      return;
    case CanonKind::spindle_clockwise:
      w << "START_SPINDLE_CLOCKWISE(0)";
      return;
    case CanonKind::spindle_counterclockwise:
      w << "START_SPINDLE_COUNTERCLOCKWISE(0)";
      return;
    case CanonKind::spindle_stop:
      w << "STOP_SPINDLE_TURNING(0)";
      return;
    case CanonKind::orient_spindle:
      w << "ORIENT_SPINDLE(0, " << c.value << ", " << c.integer << ')';
      return;
    case CanonKind::wait_orient_spindle:
      w << "SPINDLE.0.WAIT_ORIENT_COMPLETE(" << c.value << ')';
      return;
    case CanonKind::mist_on:
      w << "MIST_ON()";
      return;
    case CanonKind::mist_off:
      w << "MIST_OFF()";
      return;
    case CanonKind::flood_on:
      w << "FLOOD_ON()";
      return;
    case CanonKind::flood_off:
      w << "FLOOD_OFF()";
      return;
    case CanonKind::select_tool:
      w << "SELECT_TOOL(" << c.integer << ')';
      return;
    case CanonKind::change_tool:
      w << "CHANGE_TOOL(" << c.integer << ')';
      return;
    default:  // the other kinds are written by the other write_* functions
      return;
  }
}

// Comments, messages, stops and the events passed on.
void write_program_flow(const Canon& c, CanonWriter& w) {
  switch (c.kind) {
    case CanonKind::comment:
      w << "COMMENT(\"" << c.text << "\")";
      return;
    case CanonKind::message:
      w << "MESSAGE(\"" << c.text << "\")";
      return;
    case CanonKind::program_stop:
      w << "PROGRAM_STOP()";
      return;
    case CanonKind::optional_stop:
      w << "OPTIONAL_PROGRAM_STOP()";
      return;
    case CanonKind::program_end:
      w << "PROGRAM_END()";
      return;
    case CanonKind::event:
      w << "COMMENT(\"pkmkit: " << c.text << "\")";
      return;
    default:  // the other kinds are written by the other write_* functions
      return;
  }
}
}  // namespace

void append_canon_text(const Canon& c, text::TextBuffer& out) {
  CanonWriter w(out, c.text.size());
  // Every kind listed, so that a new kind without its text is a compile error (-Wswitch).
  switch (c.kind) {
    case CanonKind::traverse:
    case CanonKind::feed:
    case CanonKind::probe:
    case CanonKind::arc:
    case CanonKind::dwell:
    case CanonKind::rigid_tap:
    case CanonKind::speed_feed_sync:
    case CanonKind::speed_feed_sync_stop:
      write_motion(c, w);
      return;
    case CanonKind::set_feed_rate:
    case CanonKind::set_feed_mode:
    case CanonKind::select_plane:
    case CanonKind::use_length_units:
    case CanonKind::path_control:
    case CanonKind::xy_rotation:
    case CanonKind::tool_length_offset:
    case CanonKind::g5x_offset:
    case CanonKind::g92_offset:
    case CanonKind::feed_override:
    case CanonKind::speed_override:
      write_setting(c, w);
      return;
    case CanonKind::spindle_speed:
    case CanonKind::spindle_clockwise:
    case CanonKind::spindle_counterclockwise:
    case CanonKind::spindle_stop:
    case CanonKind::orient_spindle:
    case CanonKind::wait_orient_spindle:
    case CanonKind::mist_on:
    case CanonKind::mist_off:
    case CanonKind::flood_on:
    case CanonKind::flood_off:
    case CanonKind::select_tool:
    case CanonKind::change_tool:
      write_spindle_coolant_tool(c, w);
      return;
    case CanonKind::comment:
    case CanonKind::message:
    case CanonKind::program_stop:
    case CanonKind::optional_stop:
    case CanonKind::program_end:
    case CanonKind::event:
      write_program_flow(c, w);
      return;
  }
}

std::string canon_text(const Canon& canon) {
  text::TextBuffer text(256);
  append_canon_text(canon, text);
  return std::string(text.view());
}

void append_canon_line_start(int sequence, std::string_view n_label, text::TextBuffer& out) {
  text::append_int_right(out, sequence, 5);
  out.append(" N");
  text::append_left(out, n_label.empty() ? std::string_view(".....") : n_label, 5);
  out.push_back(' ');
}

}  // namespace pkm::gcode
