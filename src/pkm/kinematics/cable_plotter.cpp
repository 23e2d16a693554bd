#include "pkm/kinematics/cable_plotter.hpp"

#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace pkm {

namespace {
// Below this height (relative to the anchor distance) the cables are nearly collinear: the
// pen's height is then ill-defined and the tension unbounded.
constexpr double kMinRelativeDepth = 1e-9;
}  // namespace

CablePlotterKinematics::CablePlotterKinematics(const CablePlotterGeometry& geometry,
                                               PassThroughAxes passthrough)
    : geometry_(geometry), passthrough_(std::move(passthrough)) {
  validate(geometry_);
}

void CablePlotterKinematics::validate(const CablePlotterGeometry& geometry) {
  if (!(geometry.anchor_distance_mm > 0.0) || !std::isfinite(geometry.anchor_distance_mm)) {
    throw std::invalid_argument("anchor distance must be a positive length");
  }
  if (!std::isfinite(geometry.left_cable_offset_mm) ||
      !std::isfinite(geometry.right_cable_offset_mm)) {
    throw std::invalid_argument("cable offsets must be finite");
  }
}

Status CablePlotterKinematics::inverse(const Pose& pose, JointVector& joints) const {
  if (!all_finite(pose)) return Status::failure(StatusCode::invalid_input);
  const double x = pose.position_mm.x();
  const double y = pose.position_mm.y();
  const double d = geometry_.anchor_distance_mm;
  if (y > 0.0) return Status::failure(StatusCode::unreachable);  // above the anchors
  if (-y <= kMinRelativeDepth * d) return Status::failure(StatusCode::singular);
  // Outside the anchors the pen would hang from one cable while the other pushes it sideways.
  if (!(x > 0.0)) return Status::failure(StatusCode::unreachable, 1);
  if (!(x < d)) return Status::failure(StatusCode::unreachable, 0);
  joints.resize(joint_count());
  joints[0] = std::hypot(x, y) + geometry_.left_cable_offset_mm;
  joints[1] = std::hypot(d - x, y) + geometry_.right_cable_offset_mm;
  passthrough_.inverse(pose, joints, 2);
  return Status::success();
}

Status CablePlotterKinematics::forward(const JointVector& joints, Pose& pose_inout) const {
  if (joints.size() != joint_count() || !all_finite(joints)) {
    return Status::failure(StatusCode::invalid_input);
  }
  const double left = joints[0] - geometry_.left_cable_offset_mm;
  const double right = joints[1] - geometry_.right_cable_offset_mm;
  const double d = geometry_.anchor_distance_mm;
  if (left <= 0.0) return Status::failure(StatusCode::unreachable, 0);
  if (right <= 0.0) return Status::failure(StatusCode::unreachable, 1);
  const double x = (left * left - right * right + d * d) / (2.0 * d);
  const double depth_squared = left * left - x * x;
  if (depth_squared < 0.0) {
    return Status::failure(StatusCode::unreachable, left > right ? 0 : 1);  // circles do not meet
  }
  const double depth = std::sqrt(depth_squared);
  if (depth <= kMinRelativeDepth * d) return Status::failure(StatusCode::singular);
  // No refusal outside the anchors here: calibration solves FK with a geometry still slightly
  // off, and the pose the joints imply is the answer it needs; inverse() says what is reachable.
  pose_inout.position_mm.x() = x;
  pose_inout.position_mm.y() = -depth;  // gravity takes the lower intersection
  passthrough_.forward(joints, 2, pose_inout);
  return Status::success();
}

std::string CablePlotterKinematics::why_refused(const Pose& pose, const Status& /*status*/) const {
  const double x = pose.position_mm.x();
  const double d = geometry_.anchor_distance_mm;
  if (pose.position_mm.y() > 0.0) return "the pen would hang above the anchors (y > 0)";
  if (-pose.position_mm.y() <= kMinRelativeDepth * d) {
    return "on the anchor line (y = 0) the cables pull only sideways";
  }
  if (!(x > 0.0)) return "left of the left anchor (x <= 0) the right cable would have to push";
  if (!(x < d)) {
    char text[96];
    std::snprintf(text, sizeof text,
                  "right of the right anchor (x >= %g mm) the left cable would have to push", d);
    return text;
  }
  return {};
}

Status CablePlotterKinematics::jacobian(const Pose& pose, JointJacobian& d_joints_d_pose) const {
  const double x = pose.position_mm.x();
  const double y = pose.position_mm.y();
  const double d = geometry_.anchor_distance_mm;
  const double left = std::hypot(x, y);
  const double right = std::hypot(d - x, y);
  if (left == 0.0 || right == 0.0) return Status::failure(StatusCode::singular);
  d_joints_d_pose.setZero(joint_count(), kPoseSize);
  passthrough_.jacobian(d_joints_d_pose, 2);
  d_joints_d_pose(0, 0) = x / left;
  d_joints_d_pose(0, 1) = y / left;
  d_joints_d_pose(1, 0) = -(d - x) / right;
  d_joints_d_pose(1, 1) = y / right;
  return Status::success();
}

std::vector<Parameter> CablePlotterKinematics::parameters() const {
  return {{"anchor_distance", geometry_.anchor_distance_mm, "mm"},
          {"cable_offset_left", geometry_.left_cable_offset_mm, "mm"},
          {"cable_offset_right", geometry_.right_cable_offset_mm, "mm"}};
}

void CablePlotterKinematics::set_parameters(std::span<const double> values) {
  if (values.size() != 3) throw std::invalid_argument("cable plotter takes 3 parameters");
  const CablePlotterGeometry geometry{values[0], values[1], values[2]};
  validate(geometry);
  geometry_ = geometry;
}

std::unique_ptr<Kinematics> make_cable_plotter_kinematics(const ModelConfig& config) {
  CablePlotterGeometry geometry;
  geometry.anchor_distance_mm = config.length("anchor_distance");
  if (config.has("cable_offsets")) {
    const std::vector<double> offsets = config.length_list("cable_offsets");
    if (offsets.size() != 2) config.fail("cable_offsets", "needs two lengths: [left, right]");
    geometry.left_cable_offset_mm = offsets[0];
    geometry.right_cable_offset_mm = offsets[1];
  }
  // A pen on a real Z axis (or a drag knife's C) is a joint that follows the program.
  PassThroughAxes passthrough = PassThroughAxes::read(config, Dof::planar_xy(), Dof::all());
  try {
    return std::make_unique<CablePlotterKinematics>(geometry, std::move(passthrough));
  } catch (const std::invalid_argument& error) {
    config.fail("anchor_distance", error.what());
  }
}

}  // namespace pkm
