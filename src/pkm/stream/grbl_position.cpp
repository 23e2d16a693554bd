#include "pkm/stream/grbl_position.hpp"

#include <stdexcept>
#include <string>

namespace pkm::stream {

int grbl_axis(const machine::JointSpec& joint) {
  const int axis = joint.axis_letter - 'X';
  if (axis < 0 || axis > 2) {
    throw std::invalid_argument("joint '" + joint.name + "' is written as " +
                                std::string(1, joint.axis_letter) +
                                ": grbl has the axes X Y Z only");
  }
  return axis;
}

kinematics::JointVector joints_from_axes(const machine::Machine& machine,
                                         const std::array<double, 3>& axes) {
  const auto& joints = machine.joints();
  kinematics::JointVector values(static_cast<Eigen::Index>(joints.size()));
  for (std::size_t i = 0; i < joints.size(); ++i) {
    const auto axis = static_cast<std::size_t>(grbl_axis(joints[i]));
    values[static_cast<Eigen::Index>(i)] = joints[i].from_interface(axes[axis]);
  }
  return values;
}

std::optional<geometry::Pose> tool_pose(const machine::Machine& machine,
                                        const std::array<double, 3>& axes,
                                        const geometry::Pose& seed) {
  geometry::Pose pose = seed;
  if (machine.forward(joints_from_axes(machine, axes), pose).code != kinematics::StatusCode::ok) {
    return std::nullopt;
  }
  return pose;
}

}  // namespace pkm::stream
