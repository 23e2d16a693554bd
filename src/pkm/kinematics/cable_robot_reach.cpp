// Where the cable robot can be: its reach box (Kinematics::tool_position_box). Each tool position
// is within the cable's longest length (its max less its offset, plus the most it stretches with
// flex compensation) plus its swivel arm of the cable's centre, its anchor less its tie point; a
// planar robot's z is its pass-through joint's.
#include <algorithm>
#include <cmath>

#include "pkm/kinematics/cable_robot.hpp"

namespace pkm::kinematics {

double CableRobotKinematics::most_stretch(const RobotCable& cable, double unstretched_mm) const {
  // With flex compensation the straight length d is the joint plus its stretch s, s = t (d U + Y)
  // / (S U) with t at most tension_limits' max X: s <= X (j U + Y) / (U (S - X)) for the joint j.
  const CableRobotGeometry& g = geometry_;
  if (!g.flex_compensation) return 0.0;
  const double advantage = cable.spool ? cable.spool->mechanical_advantage : 1.0;
  const double stiffness_left = g.line_stiffness_N - g.tension_max_N;
  if (!(stiffness_left > 0.0)) return INFINITY;
  return g.tension_max_N * (unstretched_mm * advantage + cable.guy_wire_mm) /
         (advantage * stiffness_left);
}

std::optional<Eigen::AlignedBox3d> CableRobotKinematics::tool_position_box(
    const JointVector& joint_min, const JointVector& joint_max) const {
  Eigen::AlignedBox3d box(Eigen::Vector3d::Constant(-INFINITY),
                          Eigen::Vector3d::Constant(INFINITY));
  for (int i = 0; i < cable_count(); ++i) {
    const RobotCable& cable = geometry_.cables[i];
    double reach = std::max(joint_max[i] - cable.offset_mm + cable.swivel_arm_mm, 0.0);
    reach += most_stretch(cable, reach);
    const Eigen::Vector3d centre = cable.anchor_mm - cable.attach_mm;
    box.clamp(Eigen::AlignedBox3d(centre.array() - reach, centre.array() + reach));
  }
  if (geometry_.planar) {
    // The cables hold the sled in z = 0; a Z on it is the joint that passes z through.
    box.min().z() = 0.0;
    box.max().z() = 0.0;
    for (int k = 0; k < passthrough_.count(); ++k) {
      if (passthrough_.axes()[k] != 2) continue;
      box.min().z() = joint_min[cable_count() + k];
      box.max().z() = joint_max[cable_count() + k];
    }
  }
  return box;
}

}  // namespace pkm::kinematics
