// The hexapod's reach box (Kinematics::tool_position_box): every leg reaches at most its max, so
// the tool tip is within max - offset + |platform point + tool| of each base joint.
#include <algorithm>

#include "pkm/kinematics/hexapod.hpp"

namespace pkm::kinematics {

std::optional<Eigen::AlignedBox3d> HexapodKinematics::tool_position_box(
    const JointVector& /*joint_min*/, const JointVector& joint_max) const {
  const HexapodGeometry& g = geometry_;
  Eigen::AlignedBox3d box(Eigen::Vector3d::Constant(-INFINITY),
                          Eigen::Vector3d::Constant(INFINITY));
  for (std::size_t i = 0; i < 6; ++i) {
    const double reach = joint_max[static_cast<Eigen::Index>(i)] - g.leg_offset_mm[i] +
                         g.platform_from_tip_mm(i).norm();
    const double half = std::max(reach, 0.0);
    box.clamp(Eigen::AlignedBox3d(g.base_mm[i].array() - half, g.base_mm[i].array() + half));
  }
  return box;
}

}  // namespace pkm::kinematics
