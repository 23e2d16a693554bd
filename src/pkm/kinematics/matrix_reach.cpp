// The matrix model's reach box (Kinematics::tool_position_box): joints = C x, so the box of
// C^-1 over the corners of the joints' box (its first three joints; the others pass through).
#include "pkm/kinematics/matrix.hpp"

namespace pkm::kinematics {

std::optional<Eigen::AlignedBox3d> MatrixKinematics::tool_position_box(
    const JointVector& joint_min, const JointVector& joint_max) const {
  const Eigen::Matrix3d inverse = coefficients_.inverse();
  Eigen::AlignedBox3d box(Eigen::Vector3d::Constant(INFINITY),
                          Eigen::Vector3d::Constant(-INFINITY));
  for (int corner = 0; corner < 8; ++corner) {
    Eigen::Vector3d joints;
    for (int k = 0; k < 3; ++k) joints[k] = ((corner >> k) & 1) ? joint_max[k] : joint_min[k];
    box.extend(inverse * joints);
  }
  return box;
}

}  // namespace pkm::kinematics
