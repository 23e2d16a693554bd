#include "pkm/kinematics/passthrough.hpp"

#include <stdexcept>

namespace pkm::kinematics {

PassThroughAxes::PassThroughAxes(std::vector<int> axes, geometry::Dof mechanism)
    : axes_(std::move(axes)) {
  geometry::Dof seen;
  for (const int axis : axes_) {
    if (axis < 0 || axis >= geometry::kPoseSize) throw std::invalid_argument("no such pose axis");
    const std::string name(geometry::kAxisNames[axis]);
    if (mechanism.controls(axis)) {
      throw std::invalid_argument("the mechanism moves " + name + " itself");
    }
    if (seen.controls(axis)) throw std::invalid_argument(name + " passes through twice");
    seen = seen.with(axis);
  }
}

PassThroughAxes PassThroughAxes::read(const ModelConfig& config, geometry::Dof mechanism,
                                      geometry::Dof allowed) {
  if (!config.has("passthrough")) return {};
  std::string allowed_names;
  for (int axis = 0; axis < geometry::kPoseSize; ++axis) {
    if (allowed.controls(axis) && !mechanism.controls(axis)) {
      allowed_names +=
          (allowed_names.empty() ? "\"" : ", \"") + std::string(geometry::kAxisNames[axis]) + "\"";
    }
  }
  std::vector<int> axes;
  for (const std::string& name : config.string_list("passthrough")) {
    const int axis = geometry::axis_index(name);
    if (axis < 0 || !allowed.controls(axis) || mechanism.controls(axis)) {
      config.fail("passthrough", "'" + name + "' cannot pass through here; this model passes " +
                                     (allowed_names.empty() ? "none" : allowed_names));
    }
    axes.push_back(axis);
  }
  try {
    return PassThroughAxes(std::move(axes), mechanism);
  } catch (const std::invalid_argument& error) {
    config.fail("passthrough", error.what());
  }
}

geometry::Dof PassThroughAxes::add_to(geometry::Dof mechanism) const {
  for (const int axis : axes_) mechanism = mechanism.with(axis);
  return mechanism;
}

void PassThroughAxes::inverse(const geometry::Pose& pose, JointVector& joints, int first) const {
  const geometry::Vector6d values = pose.as_vector();
  for (int k = 0; k < count(); ++k) joints[first + k] = values[axes_[k]];
}

void PassThroughAxes::forward(const JointVector& joints, int first, geometry::Pose& pose) const {
  for (int k = 0; k < count(); ++k) {
    const int axis = axes_[k];
    if (axis < 3) {
      pose.position_mm[axis] = joints[first + k];
    } else {
      pose.orientation_rad[axis - 3] = joints[first + k];
    }
  }
}

void PassThroughAxes::jacobian(JointJacobian& d_joints_d_pose, int first) const {
  for (int k = 0; k < count(); ++k) {
    d_joints_d_pose.row(first + k).setZero();
    d_joints_d_pose(first + k, axes_[k]) = 1.0;
  }
}

void PassThroughAxes::write(ModelConfigWriter& out) const {
  if (axes_.empty()) return;
  std::vector<std::string> names;
  for (const int axis : axes_) names.emplace_back(geometry::kAxisNames[axis]);
  out.string_list("passthrough", names);
}

}  // namespace pkm::kinematics
