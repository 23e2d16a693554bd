// One move of the tool in machine coordinates (mm, rad): a line, an arc or helix, a corner blend,
// or a dwell.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "pkm/geometry/pose.hpp"

namespace pkm::motion {

enum class SegmentKind { line, arc, blend, dwell };

struct Segment {
  SegmentKind kind = SegmentKind::line;
  int line = 0;                                           // G-code source line
  bool rapid = false;                                     // G0: at the machine's highest feed
  geometry::Vector6d start = geometry::Vector6d::Zero();  // x y z (mm) a b c (rad)
  geometry::Vector6d end = geometry::Vector6d::Zero();
  double feed_mm_per_s = 0.0;  // programmed tool-tip speed (0 for rapids and dwells)
  // Attitude along the move: A B C linear in u (LinuxCNC's way), or the tool axis (the
  // platform's +Z) along the great circle between its start and end directions at a constant
  // rate, the spin about it shared out evenly (the paper's variable attitude).
  bool great_circle_attitude = false;
  double dwell_s = 0.0;
  // The machine does not move Z (a plotter): Z still follows the program in the pose, but it is
  // no part of the move's length, so a Z-only move takes no time and Z does not slow the feed.
  bool z_free = false;

  // Arcs: centre, the plane's two in-plane axes and its normal, signed sweep (rad, + ccw).
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  int first_axis = 0, second_axis = 1, normal_axis = 2;
  double sweep_rad = 0.0;

  // Blends: a circular arc in any plane rounding the corner between two lines, from centre +
  // radius * axis_u to centre + radius * (cos(sweep) axis_u + sin(sweep) axis_v).
  double radius_mm = 0.0;
  Eigen::Vector3d axis_u = Eigen::Vector3d::UnitX(), axis_v = Eigen::Vector3d::UnitY();

  // Length of the tool tip's path (mm, without Z where z_free); moves of the angles only are
  // measured in degrees as LinuxCNC does for a feed of rotary axes alone.
  double length() const;
  // The pose at fraction u of the path (0 = start, 1 = end).
  geometry::Vector6d at(double u) const;
  // d pose / du and d2 pose / du2 at fraction u, from the segment's own numbers (no differences of
  // poses, which rounding swamps on a segment a micrometre long). The angles' parts are linear in
  // u (the great circle's attitude is taken as linear, as it nearly is over a short stretch).
  geometry::Vector6d velocity_at(double u) const;
  geometry::Vector6d acceleration_at(double u) const;
  // The stretch of a line or arc from fraction u0 to u1, the same path: at(u0) to at(u1).
  Segment part(double u0, double u1) const;

 private:
  Eigen::Vector3d attitude_at(double u) const;
};

}  // namespace pkm::motion
