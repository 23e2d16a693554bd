// Tool poses and the rotation convention shared by every model.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <string_view>
#include <vector>

namespace pkm::geometry {

using Vector6d = Eigen::Matrix<double, 6, 1>;

// Index of each Cartesian coordinate in a Vector6d pose: x y z (mm) then a b c (rad).
enum class Axis : int { x = 0, y = 1, z = 2, a = 3, b = 4, c = 5 };
inline constexpr std::array<std::string_view, 6> kAxisNames = {"x", "y", "z", "a", "b", "c"};
inline constexpr int kPoseSize = 6;

// Returns the index 0..5 of an axis letter (either case), or -1.
int axis_index(std::string_view letter);

// Which of the six pose coordinates a kinematic model controls. The others are ignored by
// inverse kinematics and left as seeded by forward kinematics.
class Dof {
 public:
  constexpr Dof() = default;
  static constexpr Dof all() { return Dof(0b111111); }
  static constexpr Dof translation() { return Dof(0b000111); }
  static constexpr Dof planar_xy() { return Dof(0b000011); }
  constexpr Dof with(int axis) const { return Dof(bits_ | (1u << axis)); }
  constexpr bool controls(int axis) const { return (bits_ >> axis) & 1u; }
  constexpr int count() const {
    int n = 0;
    for (int i = 0; i < kPoseSize; ++i) n += controls(i) ? 1 : 0;
    return n;
  }
  constexpr bool any_rotation() const { return (bits_ & 0b111000u) != 0; }
  // The controlled coordinates' indices, in pose order (the columns of a Jacobian restricted to
  // what the model controls).
  std::vector<int> axes() const {
    std::vector<int> indices;
    for (int i = 0; i < kPoseSize; ++i) {
      if (controls(i)) indices.push_back(i);
    }
    return indices;
  }
  constexpr bool operator==(const Dof&) const = default;

 private:
  constexpr explicit Dof(unsigned bits) : bits_(bits) {}
  unsigned bits_ = 0;
};

// Tool tip position (mm) and orientation as A B C (rad): rotations about the fixed X, Y and Z
// axes, composed R = Rz(C) * Ry(B) * Rx(A), the roll-pitch-yaw reading of LinuxCNC's genhexkins.
struct Pose {
  Eigen::Vector3d position_mm = Eigen::Vector3d::Zero();
  Eigen::Vector3d orientation_rad = Eigen::Vector3d::Zero();

  static Pose from_vector(const Vector6d& values);
  Vector6d as_vector() const;
  // Interface form: x y z in mm, a b c in degrees.
  static Pose from_mm_deg(double x, double y, double z, double a_deg = 0.0, double b_deg = 0.0,
                          double c_deg = 0.0);
};

constexpr double degrees_to_radians(double degrees) {
  return degrees * (3.14159265358979323846 / 180.0);
}
constexpr double radians_to_degrees(double radians) {
  return radians * (180.0 / 3.14159265358979323846);
}

// R = Rz(c) * Ry(b) * Rx(a) for angles in radians.
Eigen::Matrix3d rotation_from_abc(const Eigen::Vector3d& abc_rad);

// The rotation (rotation_from_abc) and its partial derivatives with respect to a, b and c, from
// one evaluation of the sines and cosines.
void rotation_and_derivatives_abc(const Eigen::Vector3d& abc_rad, Eigen::Matrix3d& rotation,
                                  std::array<Eigen::Matrix3d, 3>& derivatives);

}  // namespace pkm::geometry
