// A translating glide's assembly mode over a ball (assembly_mode.hpp).
#include "pkm/bounds/assembly_mode.hpp"

#include <array>

namespace pkm::bounds {

namespace {

// Its rails' plane with two rails, its space with three: det[strut vectors].
double strut_determinant(const GlideKinematics& glide, const std::array<Eigen::Vector3d, 3>& strut,
                         int rails) {
  if (rails == 3) return strut[0].dot(strut[1].cross(strut[2]));
  int plane[2] = {0, 1};
  for (int axis = 0, k = 0; axis < 3 && k < 2; ++axis) {
    if (glide.rail_dof().controls(axis)) plane[k++] = axis;
  }
  return strut[0][plane[0]] * strut[1][plane[1]] - strut[0][plane[1]] * strut[1][plane[0]];
}

}  // namespace

ModeBound glide_mode_bound(const GlideKinematics& glide, int home_mode, const Vector6d& centre,
                           const JointVector& joints, std::span<const double> strut_speed,
                           ModeScale scale) {
  const int rails = static_cast<int>(glide.rails().size());
  Eigen::Vector3d tip = Eigen::Vector3d::Zero();
  for (int axis = 0; axis < 3; ++axis) {
    if (glide.rail_dof().controls(axis)) tip[axis] = centre[axis];
  }
  std::array<Eigen::Vector3d, 3> strut;
  for (int i = 0; i < rails; ++i) {
    const GlideRail& rail = glide.rails()[static_cast<std::size_t>(i)];
    strut[static_cast<std::size_t>(i)] =
        tip + rail.attach_mm - rail.origin_mm - joints[i] * rail.direction;
  }
  const double determinant = strut_determinant(glide, strut, rails);
  const auto speed = [&](int i) { return strut_speed[static_cast<std::size_t>(i)]; };
  const auto length = [&](int i) { return glide.rails()[static_cast<std::size_t>(i)].strut_mm; };
  if (scale == ModeScale::per_length) {
    double lengths = 1.0, rate = 0.0;
    for (int i = 0; i < rails; ++i) {
      rate += speed(i);
      lengths *= length(i);
    }
    return {home_mode * determinant / lengths, rate};
  }
  if (rails == 3) {
    return {home_mode * determinant, speed(0) * length(1) * length(2) +
                                         length(0) * speed(1) * length(2) +
                                         length(0) * length(1) * speed(2)};
  }
  return {home_mode * determinant, speed(0) * length(1) + length(0) * speed(1)};
}

}  // namespace pkm::bounds
