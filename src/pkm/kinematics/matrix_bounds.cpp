// A matrix machine's derivative bounds (derivative_bounds.hpp): linear, so every second
// derivative is zero and nothing but the joint limits bounds its workspace.
#include "pkm/kinematics/matrix.hpp"

namespace pkm::kinematics {

std::optional<HessianBounds> MatrixKinematics::own_hessian_bounds(
    const geometry::Vector6d& /*centre*/, double /*radius_mm*/, double /*angle_scale_mm*/,
    const Chord& /*chord*/) const {
  const std::vector<double> zero(static_cast<std::size_t>(joint_count()), 0.0);
  return HessianBounds{zero, zero, {}};
}

}  // namespace pkm::kinematics
