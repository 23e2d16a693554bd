// The text formats as they were written before issue 16 made them fast: snprintf per command of
// `pkm gcode --canon` and fprintf per value of a CSV sample row. Kept as the reference the fast
// formatters are compared with byte for byte (tests/test_text_formats.cpp) and timed against
// (bench/bench_text.cpp). Not used by the library.
#pragma once

#include <cstdio>
#include <string>

#include "pkm/gcode/canon.hpp"

namespace pkm::legacy {

namespace detail {

inline std::string format(const char* pattern, auto... values) {
  char buffer[512];
  std::snprintf(buffer, sizeof buffer, pattern, values...);
  return buffer;
}

inline std::string six(const gcode::Position& p) {
  return format("%.4f, %.4f, %.4f, %.4f, %.4f, %.4f", p[0], p[1], p[2], p[3], p[4], p[5]);
}

inline void plane_axes(gcode::Plane plane, int& first, int& second, int& normal) {
  switch (plane) {
    case gcode::Plane::xy:
      first = 0, second = 1, normal = 2;
      return;
    case gcode::Plane::xz:
      first = 2, second = 0, normal = 1;
      return;
    case gcode::Plane::yz:
      first = 1, second = 2, normal = 0;
      return;
  }
}

inline const char* plane_name(gcode::Plane plane) {
  switch (plane) {
    case gcode::Plane::xy:
      return "CANON_PLANE_XY";
    case gcode::Plane::xz:
      return "CANON_PLANE_XZ";
    case gcode::Plane::yz:
      return "CANON_PLANE_YZ";
  }
  return "";
}

}  // namespace detail

// canon_text as it was (src/pkm/gcode/canon_text.cpp before issue 16).
inline std::string canon_text(const gcode::Canon& c) {
  using detail::format;
  using detail::six;
  using gcode::CanonKind;
  switch (c.kind) {
    case CanonKind::traverse:
      return "STRAIGHT_TRAVERSE(" + six(c.end) + ")";
    case CanonKind::feed:
      return "STRAIGHT_FEED(" + six(c.end) + ")";
    case CanonKind::probe:
      return "STRAIGHT_PROBE(" + six(c.end) + ")";
    case CanonKind::arc: {
      int first = 0, second = 0, normal = 0;
      detail::plane_axes(c.plane, first, second, normal);
      return format("ARC_FEED(%.4f, %.4f, %.4f, %.4f, %d, %.4f, %.4f, %.4f, %.4f)", c.end[first],
                    c.end[second], c.center[0], c.center[1], c.turns, c.end[normal], c.end[3],
                    c.end[4], c.end[5]);
    }
    case CanonKind::dwell:
      return format("DWELL(%.4f)", c.value);
    case CanonKind::set_feed_rate:
      return format("SET_FEED_RATE(%.4f)", c.value);
    case CanonKind::set_feed_mode:
      return format("SET_FEED_MODE(0, %d)",
                    c.feed_mode == gcode::FeedMode::units_per_revolution ? 1 : 0);
    case CanonKind::select_plane:
      return std::string("SELECT_PLANE(") + detail::plane_name(c.plane) + ")";
    case CanonKind::use_length_units:
      return c.units == gcode::LengthUnits::inch ? "USE_LENGTH_UNITS(CANON_UNITS_INCHES)"
                                                 : "USE_LENGTH_UNITS(CANON_UNITS_MM)";
    case CanonKind::comment:
      return "COMMENT(\"" + c.text + "\")";
    case CanonKind::message:
      return "MESSAGE(\"" + c.text + "\")";
    case CanonKind::spindle_speed:
      return format("SET_SPINDLE_SPEED(0, %.4f)", c.value);
    case CanonKind::spindle_clockwise:
      return "START_SPINDLE_CLOCKWISE(0)";
    case CanonKind::spindle_counterclockwise:
      return "START_SPINDLE_COUNTERCLOCKWISE(0)";
    case CanonKind::spindle_stop:
      return "STOP_SPINDLE_TURNING(0)";
    case CanonKind::orient_spindle:
      return format("ORIENT_SPINDLE(0, %.4f, %d)", c.value, c.integer);
    case CanonKind::wait_orient_spindle:
      return format("SPINDLE.0.WAIT_ORIENT_COMPLETE(%.4f)", c.value);
    case CanonKind::mist_on:
      return "MIST_ON()";
    case CanonKind::mist_off:
      return "MIST_OFF()";
    case CanonKind::flood_on:
      return "FLOOD_ON()";
    case CanonKind::flood_off:
      return "FLOOD_OFF()";
    case CanonKind::select_tool:
      return format("SELECT_TOOL(%d)", c.integer);
    case CanonKind::change_tool:
      return format("CHANGE_TOOL(%d)", c.integer);
    case CanonKind::tool_length_offset:
      return format("USE_TOOL_LENGTH_OFFSET(%.4f %.4f %.4f, %.4f %.4f %.4f, %.4f %.4f %.4f)",
                    c.end[0], c.end[1], c.end[2], c.end[3], c.end[4], c.end[5], c.end[6], c.end[7],
                    c.end[8]);
    case CanonKind::g5x_offset:
      return format("SET_G5X_OFFSET(%d, ", c.integer) + six(c.end) + ")";
    case CanonKind::g92_offset:
      return "SET_G92_OFFSET(" + six(c.end) + ")";
    case CanonKind::xy_rotation:
      return format("SET_XY_ROTATION(%.4f)", c.value);
    case CanonKind::path_control:
      if (c.integer == 64) return format("SET_MOTION_CONTROL_MODE(CANON_CONTINUOUS, %f)", c.value);
      return c.integer == 61 ? "SET_MOTION_CONTROL_MODE(CANON_EXACT_PATH)"
                             : "SET_MOTION_CONTROL_MODE(CANON_EXACT_STOP)";
    case CanonKind::program_stop:
      return "PROGRAM_STOP()";
    case CanonKind::optional_stop:
      return "OPTIONAL_PROGRAM_STOP()";
    case CanonKind::program_end:
      return "PROGRAM_END()";
    case CanonKind::event:
      return "COMMENT(\"pkmkit: " + c.text + "\")";
    case CanonKind::speed_feed_sync:
      return format("START_SPEED_FEED_SYNC(%f,0)", c.value);
    case CanonKind::speed_feed_sync_stop:
      return "STOP_SPEED_FEED_SYNCH()";
    case CanonKind::rigid_tap:
      return format("RIGID_TAP(%.4f, %.4f, %.4f)", c.end[0], c.end[1], c.end[2]);
    case CanonKind::feed_override:
      return c.integer ? "ENABLE_FEED_OVERRIDE()" : "DISABLE_FEED_OVERRIDE()";
    case CanonKind::speed_override:
      return c.integer ? "ENABLE_SPEED_OVERRIDE(0)" : "DISABLE_SPEED_OVERRIDE(0)";
  }
  return "";
}

// A line of `pkm gcode --canon` as apps/pkm printed it.
inline std::string canon_line(int sequence, const std::string& label, const std::string& text) {
  char start[64];
  std::snprintf(start, sizeof start, "%5d N%-5s ", sequence,
                label.empty() ? "....." : label.c_str());
  return start + text + "\n";
}

// A CSV sample row as sample_files.cpp wrote it (fprintf per value): `row` of `n` values, the
// last the pen's 0 or 1 when `pen`.
inline std::string csv_row(const double* row, std::size_t n, bool pen) {
  char value[512];
  std::snprintf(value, sizeof value, "%.6f,%d", row[0], static_cast<int>(row[1]));
  std::string out = value;
  const std::size_t reals = pen ? n - 1 : n;
  for (std::size_t i = 2; i < reals; ++i) {
    std::snprintf(value, sizeof value, ",%.9f", row[i]);
    out += value;
  }
  if (pen) {
    std::snprintf(value, sizeof value, ",%d", static_cast<int>(row[n - 1]));
    out += value;
  }
  return out + "\n";
}

// A CSV sample row written as sample_files.cpp wrote it: fprintf per value to the file's stream.
inline void write_csv_row(std::FILE* out, const double* row, std::size_t n, bool pen) {
  std::fprintf(out, "%.6f,%d", row[0], static_cast<int>(row[1]));
  const std::size_t reals = pen ? n - 1 : n;
  for (std::size_t i = 2; i < reals; ++i) std::fprintf(out, ",%.9f", row[i]);
  if (pen) std::fprintf(out, ",%d", static_cast<int>(row[n - 1]));
  std::fputc('\n', out);
}

}  // namespace pkm::legacy
