#include "pkm/view/machine_drawing.hpp"

#include <cmath>
#include <numbers>

#include "pkm/kinematics/cable_plotter.hpp"
#include "pkm/kinematics/glide.hpp"
#include "pkm/kinematics/hexapod.hpp"
#include "pkm/kinematics/rotary_delta.hpp"

namespace pkm::view {

namespace {

void add_loop(std::vector<Segment>& out, Part part, const std::vector<Eigen::Vector3d>& corners) {
  for (std::size_t i = 0; i < corners.size(); ++i) {
    out.push_back({part, corners[i], corners[(i + 1) % corners.size()]});
  }
}

// A circle of `radius` about `centre` in the plane spanned by unit vectors u and v, as 24 chords.
void add_circle(std::vector<Segment>& out, Part part, const Eigen::Vector3d& centre, double radius,
                const Eigen::Vector3d& u, const Eigen::Vector3d& v) {
  std::vector<Eigen::Vector3d> corners;
  for (int k = 0; k < 24; ++k) {
    const double angle = 2.0 * std::numbers::pi * k / 24.0;
    corners.push_back(centre + radius * (std::cos(angle) * u + std::sin(angle) * v));
  }
  add_loop(out, part, corners);
}

// The work envelope's box over the coordinates it bounds (a planar machine's rectangle at z 0).
void add_envelope(std::vector<Segment>& out, const Machine& machine) {
  const CartesianLimits& limits = machine.cartesian();
  Eigen::Vector3d low, high;
  for (int axis = 0; axis < 3; ++axis) {
    low[axis] = limits.envelope_min[axis];
    high[axis] = limits.envelope_max[axis];
    if (!std::isfinite(low[axis]) || !std::isfinite(high[axis])) low[axis] = high[axis] = 0.0;
  }
  if (low.x() == high.x() || low.y() == high.y()) return;
  for (double z : {low.z(), high.z()}) {
    add_loop(out, Part::envelope,
             {{low.x(), low.y(), z},
              {high.x(), low.y(), z},
              {high.x(), high.y(), z},
              {low.x(), high.y(), z}});
    if (low.z() == high.z()) return;
  }
  for (double x : {low.x(), high.x()}) {
    for (double y : {low.y(), high.y()}) {
      out.push_back({Part::envelope, {x, y, low.z()}, {x, y, high.z()}});
    }
  }
}

Eigen::Vector3d planar(const Eigen::Vector2d& point) {
  return {point.x(), point.y(), 0.0};
}

void add_hexapod(std::vector<Segment>& out, const HexapodGeometry& geometry, const Pose& pose) {
  const Eigen::Matrix3d rotation = rotation_from_abc(pose.orientation_rad);
  const Eigen::Vector3d up(0.0, 0.0, geometry.tool_length_mm);
  const Eigen::Vector3d centre = pose.position_mm + rotation * up;
  std::vector<Eigen::Vector3d> joints;
  for (std::size_t i = 0; i < 6; ++i) {
    joints.push_back(pose.position_mm + rotation * geometry.platform_from_tip_mm(i));
    out.push_back({Part::link, geometry.base_mm[i], joints.back()});
  }
  add_loop(out, Part::platform, joints);
  out.push_back({Part::tool, centre, pose.position_mm});
}

void add_glide(std::vector<Segment>& out, const GlideKinematics& glide, const Pose& pose,
               const JointVector& joints) {
  const Eigen::Matrix3d rotation = rotation_from_abc(pose.orientation_rad);
  std::vector<Eigen::Vector3d> ends;
  for (std::size_t i = 0; i < glide.rails().size(); ++i) {
    const GlideRail& rail = glide.rails()[i];
    const Eigen::Vector3d carriage = rail.origin_mm + joints[static_cast<int>(i)] * rail.direction;
    ends.push_back(pose.position_mm + rotation * rail.attach_mm);
    out.push_back({Part::link, carriage, ends.back()});
  }
  if (ends.size() == 2) {
    out.push_back({Part::platform, ends[0], ends[1]});
  } else {
    add_loop(out, Part::platform, ends);
  }
  for (const Eigen::Vector3d& end : ends) out.push_back({Part::tool, end, pose.position_mm});
}

// The cables drawn straight (a sagging cable's curve is not drawn), the effector tilted as its
// balance at rest tilts it (an effector with a mass, tied at two points).
void add_cables(std::vector<Segment>& out, const CablePlotterKinematics& cables, const Pose& pose) {
  const CablePlotterGeometry& geometry = cables.geometry();
  const Eigen::Vector3d pen = pose.position_mm;
  const Eigen::Vector3d pen_xy(pen.x(), pen.y(), 0.0);
  CableStatics statics;
  if (geometry.effector_mass_kg <= 0.0 ||
      !cables.statics(pose, Eigen::Vector2d::Zero(), statics).ok()) {
    statics.tilt_rad = 0.0;
  }
  const Eigen::Rotation2Dd tilt(statics.tilt_rad);
  std::array<Eigen::Vector3d, 2> tied;
  for (int cable = 0; cable < 2; ++cable) {
    tied[cable] = pen_xy + planar(tilt * geometry.attach_mm[cable]);
    // The cable leaves its pulley where its line from the tie point touches the circle: drawn
    // from the pulley's centre when the pulley is a point.
    const Eigen::Vector3d anchor = planar(geometry.anchors_mm[cable]);
    const Eigen::Vector3d away = tied[cable] - anchor;
    const double distance = away.norm();
    const double radius = geometry.pulley_radius_mm;
    Eigen::Vector3d leave = anchor;
    if (radius > 0.0 && distance > radius) {
      const double angle = std::acos(radius / distance);
      const double side = cable == 0 ? 1.0 : -1.0;  // left cable leaves on the pulley's right
      const Eigen::Rotation2Dd turn(side * angle);
      const Eigen::Vector2d towards = turn * Eigen::Vector2d(away.x(), away.y()).normalized();
      leave = anchor + radius * Eigen::Vector3d(towards.x(), towards.y(), 0.0);
    }
    out.push_back({Part::link, leave, tied[cable]});
  }
  if ((tied[0] - tied[1]).norm() > 0.0) out.push_back({Part::platform, tied[0], tied[1]});
  for (const Eigen::Vector3d& tie : tied) {
    if ((tie - pen_xy).norm() > 0.0) out.push_back({Part::platform, tie, pen_xy});
  }
}

void add_rotary_delta_base(std::vector<Segment>& out, const RotaryDeltaGeometry& geometry) {
  add_circle(out, Part::frame, Eigen::Vector3d::Zero(), geometry.base_radius_mm,
             Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitY());
}

// Each arm from its pivot to its elbow (joint 0: horizontal and outward, positive: elbow down),
// the forearm on to its platform joint, the platform as the circle of its joints.
void add_rotary_delta(std::vector<Segment>& out, const RotaryDeltaGeometry& geometry,
                      const Pose& pose, const JointVector& joints) {
  for (int arm = 0; arm < 3; ++arm) {
    const Eigen::Vector3d outward = RotaryDeltaKinematics::arm_direction(arm);
    const Eigen::Vector3d pivot = geometry.base_radius_mm * outward;
    const Eigen::Vector3d elbow =
        pivot + geometry.arm_length_mm * (std::cos(joints[arm]) * outward -
                                          std::sin(joints[arm]) * Eigen::Vector3d::UnitZ());
    out.push_back({Part::link, pivot, elbow});
    out.push_back({Part::link, elbow, pose.position_mm + geometry.platform_radius_mm * outward});
  }
  add_circle(out, Part::platform, pose.position_mm, geometry.platform_radius_mm,
             Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitY());
}

}  // namespace

bool drawn_planar(const Machine& machine) {
  const Dof dof = machine.kinematics().dof();
  return machine.kinematics().type() == "cable_plotter" ||
         (!dof.controls(2) && !dof.any_rotation());
}

std::vector<Segment> fixed_parts(const Machine& machine) {
  std::vector<Segment> out;
  const Kinematics& model = machine.kinematics();
  if (const auto* hexapod = dynamic_cast<const HexapodKinematics*>(&model)) {
    add_loop(out, Part::frame,
             {hexapod->geometry().base_mm.begin(), hexapod->geometry().base_mm.end()});
  } else if (const auto* glide = dynamic_cast<const GlideKinematics*>(&model)) {
    for (std::size_t i = 0; i < glide->rails().size(); ++i) {
      const GlideRail& rail = glide->rails()[i];
      const JointSpec& joint = machine.joints()[i];
      out.push_back({Part::frame, rail.origin_mm + joint.min * rail.direction,
                     rail.origin_mm + joint.max * rail.direction});
    }
  } else if (const auto* cables = dynamic_cast<const CablePlotterKinematics*>(&model)) {
    const CablePlotterGeometry& geometry = cables->geometry();
    out.push_back({Part::frame, planar(geometry.anchors_mm[0]), planar(geometry.anchors_mm[1])});
    if (geometry.pulley_radius_mm > 0.0) {
      for (const Eigen::Vector2d& anchor : geometry.anchors_mm) {
        add_circle(out, Part::frame, planar(anchor), geometry.pulley_radius_mm,
                   Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitY());
      }
    }
  } else if (const auto* delta = dynamic_cast<const RotaryDeltaKinematics*>(&model)) {
    add_rotary_delta_base(out, delta->geometry());
  }
  add_envelope(out, machine);
  return out;
}

std::vector<Segment> moving_parts(const Machine& machine, const Pose& pose,
                                  const JointVector& joints) {
  std::vector<Segment> out;
  const Kinematics& model = machine.kinematics();
  if (const auto* hexapod = dynamic_cast<const HexapodKinematics*>(&model)) {
    add_hexapod(out, hexapod->geometry(), pose);
  } else if (const auto* glide = dynamic_cast<const GlideKinematics*>(&model)) {
    add_glide(out, *glide, pose, joints);
  } else if (const auto* cables = dynamic_cast<const CablePlotterKinematics*>(&model)) {
    add_cables(out, *cables, pose);
  } else if (const auto* delta = dynamic_cast<const RotaryDeltaKinematics*>(&model)) {
    add_rotary_delta(out, delta->geometry(), pose, joints);
  }
  return out;
}

}  // namespace pkm::view
