// The glide's reach box (Kinematics::tool_position_box): each strut's platform end lies within
// its length of its carriage, the carriage on its rail between the joint's limits; the tip is the
// platform end less the attachment (its length for a rotating platform).
#include "pkm/kinematics/glide.hpp"

namespace pkm::kinematics {

std::optional<Eigen::AlignedBox3d> GlideKinematics::tool_position_box(
    const JointVector& joint_min, const JointVector& joint_max) const {
  Eigen::AlignedBox3d box(Eigen::Vector3d::Constant(-INFINITY),
                          Eigen::Vector3d::Constant(INFINITY));
  const bool rotating = rail_dof().any_rotation();
  for (std::size_t i = 0; i < rails_.size(); ++i) {
    const GlideRail& rail = rails_[i];
    const auto joint = static_cast<Eigen::Index>(i);
    const Eigen::Vector3d a = rail.origin_mm + joint_min[joint] * rail.direction;
    const Eigen::Vector3d b = rail.origin_mm + joint_max[joint] * rail.direction;
    const double spread = rail.strut_mm + (rotating ? rail.attach_mm.norm() : 0.0);
    const Eigen::Vector3d shift = rotating ? Eigen::Vector3d::Zero() : rail.attach_mm;
    box.clamp(Eigen::AlignedBox3d(a.cwiseMin(b).array() - spread - shift.array(),
                                  a.cwiseMax(b).array() + spread - shift.array()));
  }
  return box;
}

}  // namespace pkm::kinematics
