// Canonical commands to moves in machine coordinates: the offsets a program sets, its units, its
// feed modes (per minute, inverse time, per revolution of the spindle) and arcs, turned into
// segments (mm, rad); a rigid tap (G33.1) into its two moves, in and back out. Shared by every
// consumer of a program's path (the planner, the joint-space post-processor, verify, the job
// summary).
#pragma once

#include <array>
#include <span>
#include <string>

#include "pkm/gcode/canon.hpp"
#include "pkm/gcode/interpreter.hpp"
#include "pkm/motion/segment.hpp"

namespace pkm::motion {

// `options` for a program that starts where the machine is: `start` (machine pose, mm, rad) seen
// from the program's `origin`, in the interpreter's start units (mm, deg), so the axes a program
// never names stay at the start pose.
gcode::InterpreterOptions starting_at(gcode::InterpreterOptions options,
                                      const geometry::Vector6d& start,
                                      const geometry::Vector6d& origin);

// The moves one command makes: none (a change of state), one, or two (a rigid tap); valid until
// the builder's next take.
using Moves = std::span<const Segment>;

class SegmentBuilder {
 public:
  // `start`: the machine pose the program starts from; `origin`: where the program's origin sits
  // in machine coordinates (both mm, rad).
  SegmentBuilder(const geometry::Vector6d& start, const geometry::Vector6d& origin,
                 bool great_circle_attitude);

  // The moves a command makes (line, arc, dwell; a rigid tap's two lines), or none for the
  // commands that only change state (offsets, path control, ...), which the builder keeps.
  // A move fed per revolution with the spindle stopped, at S0 or at a zero pitch cannot be
  // timed: a gcode::GcodeError at its line in `file` (set_file).
  Moves take(const gcode::Canon& canon);
  void set_file(std::string file) { file_ = std::move(file); }

  // The machine does not move Z: moves are measured without it (Segment::z_free), which sets
  // the time of inverse-time (G93) moves.
  void set_z_free(bool z_free) { z_free_ = z_free; }

  const geometry::Vector6d& pose() const { return pose_; }  // where the last move ended
  int path_mode() const { return path_mode_; }              // 61, 611 or 64 (G61, G61.1, G64)
  double blend_tolerance_mm() const { return blend_tolerance_mm_; }  // G64 P, or 0

 private:
  void store_offset(const gcode::Canon& canon, geometry::Vector6d& offset) const;
  geometry::Vector6d machine_pose(const gcode::Canon& canon) const;
  void set_feed(const gcode::Canon& canon, Segment& segment) const;
  Segment line_segment(const gcode::Canon& canon, const geometry::Vector6d& end) const;
  Moves rigid_tap(const gcode::Canon& canon);
  Segment arc_segment(const gcode::Canon& canon) const;
  double per_revolution_feed(const gcode::Canon& canon, const Segment& segment) const;

  std::string file_;
  std::array<Segment, 2> moves_;  // what take returns points here: made once, not per command
  geometry::Vector6d pose_;
  geometry::Vector6d origin_;
  bool great_circle_attitude_;
  bool z_free_ = false;
  // A program position's XY to the machine's under the coordinate system's rotation.
  void turn_xy(double& x, double& y) const;

  geometry::Vector6d g5x_mm_ = geometry::Vector6d::Zero(), g92_mm_ = geometry::Vector6d::Zero(),
                     tool_mm_ = geometry::Vector6d::Zero();
  double xy_rotation_rad_ = 0.0;  // G10 L2 R: XY turned about the G5x origin, after G92
  int path_mode_ = 64;            // LinuxCNC starts in G64
  double blend_tolerance_mm_ = 0.0;
};

}  // namespace pkm::motion
