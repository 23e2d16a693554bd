// The rotation's share of the derivative bounds every platform model uses (derivative_bounds.hpp).
#include "pkm/kinematics/derivative_bounds.hpp"

#include <cmath>
#include <string>

namespace pkm::kinematics {

double platform_point_gain(double b_norm_mm, double angle_scale_mm) {
  return std::sqrt(1.0 + 3.0 * (b_norm_mm / angle_scale_mm) * (b_norm_mm / angle_scale_mm));
}

double rotation_curvature(double b_norm_mm, double angle_scale_mm) {
  return 3.0 * b_norm_mm / (angle_scale_mm * angle_scale_mm);
}

double platform_point_change(double position, const Chord& chord, double b_norm_mm,
                             double angle_scale_mm) {
  return position + std::sqrt(3.0) * b_norm_mm / angle_scale_mm * chord.angle;
}

ReachMargin DerivativeBounds::reach_margin(int index) const {
  return {"the mechanism's reach (margin " + std::to_string(index + 1) + ")", false,
          Status::failure(StatusCode::unreachable, index)};
}

}  // namespace pkm::kinematics
