// The canonical commands a G-code program means, in the vocabulary of LinuxCNC's canonical
// machining interface: what the planner consumes and `pkm gcode --canon` prints.
#pragma once

#include <array>
#include <numbers>
#include <string>
#include <string_view>

#include "pkm/text/text_buffer.hpp"

namespace pkm::gcode {

// Axis order of every position: x y z a b c u v w.
inline constexpr int kAxes = 9;
using Position = std::array<double, kAxes>;

enum class Plane { xy, xz, yz };
enum class LengthUnits { inch, mm };
// G94, G93, G95. A move fed per revolution (G95, and the spindle-synchronised moves of G33,
// G33.1 and G76) runs at its `value` (units per revolution) times the spindle's speed.
enum class FeedMode { units_per_minute, inverse_time, units_per_revolution };

// LinuxCNC's tolerance on the two radii of a centre-format arc (and on the arcs cutter
// compensation makes), in `units`: 0.02*sqrt(2) mm or 0.002*sqrt(2) inch.
inline double arc_radius_tolerance(LengthUnits units) {
  return (units == LengthUnits::inch ? 0.001 : 0.01) * 2.0 * std::numbers::sqrt2;
}

enum class CanonKind {
  traverse,          // STRAIGHT_TRAVERSE to `end`
  feed,              // STRAIGHT_FEED to `end`
  probe,             // STRAIGHT_PROBE towards `end` (G38.x): a feed move that stops on contact
  arc,               // ARC_FEED to `end` about `center` in `plane`, `turns` (+ ccw, - cw)
  dwell,             // DWELL `value` seconds
  set_feed_rate,     // `value` in length units per minute (or inverse time)
  set_feed_mode,     // `feed_mode`
  select_plane,      // `plane`
  use_length_units,  // `units`
  comment,           // `text`
  message,           // `text` of a (MSG, ...) comment
  spindle_speed,     // `value` rpm
  spindle_clockwise,
  spindle_counterclockwise,
  spindle_stop,
  mist_on,
  mist_off,
  flood_on,
  flood_off,
  select_tool,         // `integer` tool number
  change_tool,         // `integer` tool number
  tool_length_offset,  // `end` holds the offset per axis
  g5x_offset,          // `integer` coordinate system 1..9, `end` its offsets
  g92_offset,          // `end`
  xy_rotation,    // `value` deg: the XY plane of the active coordinate system turned (G10 L2 R)
  path_control,   // `integer` 61 exact path, 611 exact stop, 64 continuous with `value` P
  program_stop,   // M0, and M60 (`integer` 60: the pallet shuttle first)
  optional_stop,  // M1
  program_end,    // M2, M30, or the end of the file
  event,          // a code with no meaning off a real machine, passed on: `text`
  // Spindle-synchronised motion (G33, G33.1, G76). The moves between a sync and a sync_stop
  // are fed per revolution at the pitch; each says so itself (feed_mode, value, spindle_rpm).
  speed_feed_sync,       // START_SPEED_FEED_SYNC: `value` the pitch, units per revolution (signed)
  speed_feed_sync_stop,  // STOP_SPEED_FEED_SYNCH
  rigid_tap,       // RIGID_TAP (G33.1): from where the tool is to `end` (X Y Z) and back again
  feed_override,   // `integer` 1 ENABLE_FEED_OVERRIDE, 0 DISABLE_ (tapping and threading cycles)
  speed_override,  // `integer` 1 ENABLE_SPEED_OVERRIDE, 0 DISABLE_ (tapping cycles)
  // M19: turn the stopped spindle to `value` deg (R), `integer` 0 the shorter way, 1 clockwise,
  // 2 counterclockwise (P); then, with Q, wait up to `value` s for it to get there.
  orient_spindle,
  wait_orient_spindle,
};

struct Canon {
  CanonKind kind = CanonKind::comment;
  int line = 0;                         // source line of the block
  std::string n_label;                  // its N word as written ("" when none)
  LengthUnits units = LengthUnits::mm;  // the units of every length below
  Position end{};  // program coordinates (current work offsets applied by the machine)
  Plane plane = Plane::xy;
  std::array<double, 2> center{};  // arc centre in the plane's first and second axis
  int turns = 0;
  double value = 0.0;  // moves: the F word in effect (units/min, 1/min in inverse time, units/rev
                       // fed per revolution, where a synchronised move's is its pitch)
  double value2 = 0.0;
  // Moves fed per revolution: the speed of the spindle (rpm), 0 when it is stopped (the move
  // cannot run then: its consumer refuses it at its line).
  double spindle_rpm = 0.0;
  int integer = 0;
  FeedMode feed_mode = FeedMode::units_per_minute;
  std::string text;
};

// The command in the text form of LinuxCNC's `rs274 -g` (numbers as %.4f), without the leading
// sequence number and N label, appended to `out` (which allocates nothing once grown).
void append_canon_text(const Canon& canon, text::TextBuffer& out);
std::string canon_text(const Canon& canon);  // the same as a new string

// The start of each line `rs274 -g` prints (printf's "%5d N%-5s "): the sequence number, then
// the N label as written, "....." when the block has none.
void append_canon_line_start(int sequence, std::string_view n_label, text::TextBuffer& out);

}  // namespace pkm::gcode
