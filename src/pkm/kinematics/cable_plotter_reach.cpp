// Where the cable plotter can be: its reach box (Kinematics::tool_position_box; each cable is
// at most its max less its offset, plus what wraps a pulley and the effector's attachment and
// centre of mass, from its anchor) and its cables without tension limits, for the tension map.
#include <algorithm>
#include <cmath>
#include <limits>

#include "pkm/kinematics/cable_plotter.hpp"

namespace pkm::kinematics {

std::optional<Eigen::AlignedBox3d> CablePlotterKinematics::tool_position_box(
    const JointVector& /*joint_min*/, const JointVector& joint_max) const {
  const CablePlotterGeometry& g = geometry_;
  Eigen::AlignedBox3d box(Eigen::Vector3d::Constant(-INFINITY),
                          Eigen::Vector3d::Constant(INFINITY));
  for (std::size_t i = 0; i < 2; ++i) {
    const double reach = joint_max[static_cast<Eigen::Index>(i)] - g.cable_offsets_mm[i] +
                         2.0 * M_PI * g.pulley_radius_mm + g.attach_mm[i].norm() +
                         g.center_of_mass_mm.norm();
    const double half = std::max(reach, 0.0);
    const Eigen::Vector3d anchor(g.anchors_mm[i].x(), g.anchors_mm[i].y(), 0.0);
    box.clamp(Eigen::AlignedBox3d(anchor.array() - half, anchor.array() + half));
  }
  return box;
}

std::unique_ptr<Kinematics> CablePlotterKinematics::without_tension_limits() const {
  CablePlotterGeometry geometry = geometry_;
  geometry.tension_limited = false;
  geometry.tension_min_N = 0.0;
  geometry.tension_max_N = std::numeric_limits<double>::infinity();
  return std::make_unique<CablePlotterKinematics>(geometry, passthrough_);
}

}  // namespace pkm::kinematics
