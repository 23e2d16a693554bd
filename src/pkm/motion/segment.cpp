#include "pkm/motion/segment.hpp"

#include <cmath>

namespace pkm::motion {

double Segment::length() const {
  switch (kind) {
    case SegmentKind::dwell:
      return 0.0;
    case SegmentKind::line: {
      const double position = (end.head<3>() - start.head<3>()).norm();
      if (position > 0.0) return position;
      return radians_to_degrees((end.tail<3>() - start.tail<3>()).norm());
    }
    case SegmentKind::blend:
      return radius_mm * sweep_rad;
    case SegmentKind::arc: {
      const double radius = std::hypot(start[first_axis] - centre[first_axis],
                                       start[second_axis] - centre[second_axis]);
      const double along_axis = end[normal_axis] - start[normal_axis];
      return std::hypot(radius * sweep_rad, along_axis);
    }
  }
  return 0.0;
}

Vector6d Segment::at(double u) const {
  if (kind == SegmentKind::blend) {
    Vector6d pose = start + u * (end - start);  // the angles blend linearly
    if (u >= 1.0) return end;
    const double angle = u * sweep_rad;
    pose.head<3>() = centre + radius_mm * (std::cos(angle) * axis_u + std::sin(angle) * axis_v);
    return pose;
  }
  if (kind != SegmentKind::arc) return start + u * (end - start);
  Vector6d pose = start + u * (end - start);  // the normal axis and the angles are linear
  const double start_angle =
      std::atan2(start[second_axis] - centre[second_axis], start[first_axis] - centre[first_axis]);
  const double start_radius =
      std::hypot(start[first_axis] - centre[first_axis], start[second_axis] - centre[second_axis]);
  const double end_radius =
      std::hypot(end[first_axis] - centre[first_axis], end[second_axis] - centre[second_axis]);
  // LinuxCNC accepts arcs whose end radius differs slightly: the radius blends linearly.
  const double radius = start_radius + u * (end_radius - start_radius);
  const double angle = start_angle + u * sweep_rad;
  pose[first_axis] = centre[first_axis] + radius * std::cos(angle);
  pose[second_axis] = centre[second_axis] + radius * std::sin(angle);
  if (u >= 1.0) {
    pose[first_axis] = end[first_axis];
    pose[second_axis] = end[second_axis];
  }
  return pose;
}

}  // namespace pkm::motion
