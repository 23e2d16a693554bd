#include "pkm/geometry/pose.hpp"

#include <cctype>
#include <cmath>

namespace pkm::geometry {

int axis_index(std::string_view letter) {
  if (letter.size() != 1) return -1;
  const char lower = static_cast<char>(std::tolower(static_cast<unsigned char>(letter[0])));
  for (int i = 0; i < kPoseSize; ++i) {
    if (kAxisNames[i][0] == lower) return i;
  }
  return -1;
}

Pose Pose::from_vector(const Vector6d& values) {
  return Pose{values.head<3>(), values.tail<3>()};
}

Vector6d Pose::as_vector() const {
  Vector6d values;
  values << position_mm, orientation_rad;
  return values;
}

Pose Pose::from_mm_deg(double x, double y, double z, double a_deg, double b_deg, double c_deg) {
  return Pose{Eigen::Vector3d(x, y, z),
              Eigen::Vector3d(degrees_to_radians(a_deg), degrees_to_radians(b_deg),
                              degrees_to_radians(c_deg))};
}

namespace {
struct SinCos {
  double sa, ca, sb, cb, sc, cc;
};
SinCos sincos_abc(const Eigen::Vector3d& abc) {
  return {std::sin(abc.x()), std::cos(abc.x()), std::sin(abc.y()),
          std::cos(abc.y()), std::sin(abc.z()), std::cos(abc.z())};
}

Eigen::Matrix3d rotation_from(const SinCos& t) {
  const auto [sa, ca, sb, cb, sc, cc] = t;
  Eigen::Matrix3d r;
  r << cc * cb, cc * sb * sa - sc * ca, cc * sb * ca + sc * sa,  //
      sc * cb, sc * sb * sa + cc * ca, sc * sb * ca - cc * sa,   //
      -sb, cb * sa, cb * ca;
  return r;
}

std::array<Eigen::Matrix3d, 3> derivatives_from(const SinCos& t) {
  const auto [sa, ca, sb, cb, sc, cc] = t;
  Eigen::Matrix3d d_a, d_b, d_c;
  d_a << 0.0, cc * sb * ca + sc * sa, -cc * sb * sa + sc * ca,  //
      0.0, sc * sb * ca - cc * sa, -sc * sb * sa - cc * ca,     //
      0.0, cb * ca, -cb * sa;
  d_b << -cc * sb, cc * cb * sa, cc * cb * ca,  //
      -sc * sb, sc * cb * sa, sc * cb * ca,     //
      -cb, -sb * sa, -sb * ca;
  d_c << -sc * cb, -sc * sb * sa - cc * ca, -sc * sb * ca + cc * sa,  //
      cc * cb, cc * sb * sa - sc * ca, cc * sb * ca + sc * sa,        //
      0.0, 0.0, 0.0;
  return {d_a, d_b, d_c};
}
}  // namespace

Eigen::Matrix3d rotation_from_abc(const Eigen::Vector3d& abc_rad) {
  return rotation_from(sincos_abc(abc_rad));
}

void rotation_and_derivatives_abc(const Eigen::Vector3d& abc_rad, Eigen::Matrix3d& rotation,
                                  std::array<Eigen::Matrix3d, 3>& derivatives) {
  const SinCos t = sincos_abc(abc_rad);
  rotation = rotation_from(t);
  derivatives = derivatives_from(t);
}

}  // namespace pkm::geometry
