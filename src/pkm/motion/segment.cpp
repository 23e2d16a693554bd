#include "pkm/motion/segment.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

namespace pkm::motion {

namespace {

// The length of an arc in the XZ or YZ plane on a machine that does not move Z: its path in XY,
// by chords fine enough that their shortfall is below 1e-6 of the length.
double xy_length_by_chords(const Segment& arc) {
  const int chords = 256 * std::max(1, static_cast<int>(std::ceil(std::abs(arc.sweep_rad))));
  double length = 0.0;
  geometry::Vector6d previous = arc.at(0.0);
  for (int k = 1; k <= chords; ++k) {
    const geometry::Vector6d next = arc.at(static_cast<double>(k) / chords);
    length += (next.head<2>() - previous.head<2>()).norm();
    previous = next;
  }
  return length;
}

}  // namespace

double Segment::length() const {
  switch (kind) {
    case SegmentKind::dwell:
      return 0.0;
    case SegmentKind::line: {
      Eigen::Vector3d move = end.head<3>() - start.head<3>();
      if (z_free) move.z() = 0.0;
      const double position = move.norm();
      if (position > 0.0) return position;
      return geometry::radians_to_degrees((end.tail<3>() - start.tail<3>()).norm());
    }
    case SegmentKind::blend:
      return radius_mm * sweep_rad;
    case SegmentKind::arc: {
      if (z_free && normal_axis != 2) return xy_length_by_chords(*this);
      const double radius = std::hypot(start[first_axis] - centre[first_axis],
                                       start[second_axis] - centre[second_axis]);
      const double along_axis = z_free ? 0.0 : end[normal_axis] - start[normal_axis];
      return std::hypot(radius * sweep_rad, along_axis);
    }
  }
  return 0.0;
}

Segment Segment::part(double u0, double u1) const {
  Segment piece = *this;
  piece.start = at(u0);
  piece.end = at(u1);
  piece.sweep_rad = sweep_rad * (u1 - u0);
  return piece;
}

namespace {

// A B C of a rotation (R = Rz(C) Ry(B) Rx(A)), each the one of its 2 pi family nearest `near`.
Eigen::Vector3d abc_near(const Eigen::Matrix3d& r, const Eigen::Vector3d& near) {
  Eigen::Vector3d abc(std::atan2(r(2, 1), r(2, 2)), -std::asin(std::clamp(r(2, 0), -1.0, 1.0)),
                      std::atan2(r(1, 0), r(0, 0)));
  for (int i = 0; i < 3; ++i) {
    abc[i] += 2.0 * M_PI * std::round((near[i] - abc[i]) / (2.0 * M_PI));
  }
  return abc;
}

}  // namespace

Eigen::Vector3d Segment::attitude_at(double u) const {
  const Eigen::Vector3d start_abc = start.tail<3>(), end_abc = end.tail<3>();
  const Eigen::Vector3d linear = start_abc + u * (end_abc - start_abc);
  if (!great_circle_attitude || start_abc == end_abc || u <= 0.0 || u >= 1.0) {
    return u >= 1.0 ? end_abc : (u <= 0.0 ? start_abc : linear);
  }
  const Eigen::Matrix3d r0 = geometry::rotation_from_abc(start_abc);
  const Eigen::Matrix3d r1 = geometry::rotation_from_abc(end_abc);
  const Eigen::Vector3d axis0 = r0.col(2), axis1 = r1.col(2);
  // The tilt that turns the tool axis along the great circle, and the spin left over about it.
  const Eigen::Vector3d normal = axis0.cross(axis1);
  const double tilt = std::atan2(normal.norm(), axis0.dot(axis1));
  const Eigen::Matrix3d full_tilt =
      normal.norm() > 1e-12 ? Eigen::AngleAxisd(tilt, normal.normalized()).toRotationMatrix()
                            : Eigen::Matrix3d::Identity();
  const Eigen::Matrix3d residual = (full_tilt * r0).transpose() * r1;  // a turn about +Z
  const double spin = std::atan2(residual(1, 0), residual(0, 0));
  const Eigen::Matrix3d partial_tilt =
      normal.norm() > 1e-12 ? Eigen::AngleAxisd(u * tilt, normal.normalized()).toRotationMatrix()
                            : Eigen::Matrix3d::Identity();
  const Eigen::Matrix3d r =
      partial_tilt * r0 * Eigen::AngleAxisd(u * spin, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  return abc_near(r, linear);
}

geometry::Vector6d Segment::at(double u) const {
  if (kind == SegmentKind::blend) {
    geometry::Vector6d pose = start + u * (end - start);  // the angles blend linearly
    if (u >= 1.0) return end;
    const double angle = u * sweep_rad;
    pose.head<3>() = centre + radius_mm * (std::cos(angle) * axis_u + std::sin(angle) * axis_v);
    return pose;
  }
  if (kind != SegmentKind::arc) {
    geometry::Vector6d pose = start + u * (end - start);
    if (great_circle_attitude) pose.tail<3>() = attitude_at(u);
    return pose;
  }
  geometry::Vector6d pose = start + u * (end - start);  // the normal axis is linear
  if (great_circle_attitude) pose.tail<3>() = attitude_at(u);
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

namespace {

// An arc's polar frame at fraction u: its angle and radius there, and how they change with u
// (the radius blends linearly from the start's to the end's, as at() draws it).
struct ArcFrame {
  double angle = 0.0, radius = 0.0, radius_change = 0.0;
};
ArcFrame arc_frame(const Segment& arc, double u) {
  const int a = arc.first_axis, b = arc.second_axis;
  const double start_radius =
      std::hypot(arc.start[a] - arc.centre[a], arc.start[b] - arc.centre[b]);
  ArcFrame frame;
  frame.radius_change =
      std::hypot(arc.end[a] - arc.centre[a], arc.end[b] - arc.centre[b]) - start_radius;
  frame.radius = start_radius + u * frame.radius_change;
  frame.angle =
      std::atan2(arc.start[b] - arc.centre[b], arc.start[a] - arc.centre[a]) + u * arc.sweep_rad;
  return frame;
}

}  // namespace

geometry::Vector6d Segment::velocity_at(double u) const {
  geometry::Vector6d rate = end - start;  // lines, the angles, an arc's normal axis
  if (kind == SegmentKind::blend) {
    const double angle = u * sweep_rad;
    rate.head<3>() = radius_mm * sweep_rad * (-std::sin(angle) * axis_u + std::cos(angle) * axis_v);
  } else if (kind == SegmentKind::arc) {
    const ArcFrame f = arc_frame(*this, u);
    const double c = std::cos(f.angle), s = std::sin(f.angle);
    rate[first_axis] = f.radius_change * c - f.radius * sweep_rad * s;
    rate[second_axis] = f.radius_change * s + f.radius * sweep_rad * c;
  }
  return rate;
}

geometry::Vector6d Segment::acceleration_at(double u) const {
  geometry::Vector6d rate = geometry::Vector6d::Zero();
  if (kind == SegmentKind::blend) {
    const double angle = u * sweep_rad;
    rate.head<3>() =
        -radius_mm * sweep_rad * sweep_rad * (std::cos(angle) * axis_u + std::sin(angle) * axis_v);
  } else if (kind == SegmentKind::arc) {
    const ArcFrame f = arc_frame(*this, u);
    const double c = std::cos(f.angle), s = std::sin(f.angle);
    const double turn = sweep_rad * sweep_rad;
    rate[first_axis] = -2.0 * f.radius_change * sweep_rad * s - f.radius * turn * c;
    rate[second_axis] = 2.0 * f.radius_change * sweep_rad * c - f.radius * turn * s;
  }
  return rate;
}

}  // namespace pkm::motion
