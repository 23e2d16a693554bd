#include "pkm/kinematics/matrix.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <cmath>
#include <stdexcept>
#include <string>

namespace pkm {

namespace {
constexpr std::array<const char*, 3> kRowNames = {"x", "y", "z"};
}

MatrixKinematics::MatrixKinematics(const Eigen::Matrix3d& coefficients,
                                   std::vector<int> passthrough_axes)
    : passthrough_axes_(std::move(passthrough_axes)), dof_(Dof::translation()) {
  for (const int axis : passthrough_axes_) {
    if (axis < 3 || axis >= kPoseSize) {
      throw std::invalid_argument("only a, b and c can pass through a matrix machine");
    }
    dof_ = dof_.with(axis);
  }
  set_coefficients(coefficients);
}

void MatrixKinematics::set_coefficients(const Eigen::Matrix3d& coefficients) {
  if (!coefficients.allFinite()) throw std::invalid_argument("matrix has a non-finite coefficient");
  // Singular values of C are the square roots of the eigenvalues of C^T C (ascending).
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(coefficients.transpose() *
                                                              coefficients);
  const Eigen::Vector3d squared = solver.eigenvalues();
  const double condition = squared(0) <= 0.0 ? INFINITY : std::sqrt(squared(2) / squared(0));
  if (!(condition <= kMaxConditionNumber)) {
    throw std::invalid_argument("matrix is singular or ill-conditioned (condition number " +
                                std::to_string(condition) +
                                "); its inverse, the forward kinematics, would not be usable");
  }
  coefficients_ = coefficients;
  inverse_coefficients_ = coefficients.inverse();
}

Status MatrixKinematics::inverse(const Pose& pose, JointVector& joints) const {
  if (!all_finite(pose)) return Status::failure(StatusCode::invalid_input);
  joints.resize(joint_count());
  joints.head<3>() = coefficients_ * pose.position_mm;
  for (std::size_t i = 0; i < passthrough_axes_.size(); ++i) {
    joints[3 + static_cast<int>(i)] = pose.orientation_rad[passthrough_axes_[i] - 3];
  }
  return Status::success();
}

Status MatrixKinematics::forward(const JointVector& joints, Pose& pose_inout) const {
  if (joints.size() != joint_count() || !all_finite(joints)) {
    return Status::failure(StatusCode::invalid_input);
  }
  pose_inout.position_mm = inverse_coefficients_ * joints.head<3>();
  for (std::size_t i = 0; i < passthrough_axes_.size(); ++i) {
    pose_inout.orientation_rad[passthrough_axes_[i] - 3] = joints[3 + static_cast<int>(i)];
  }
  return Status::success();
}

Status MatrixKinematics::jacobian(const Pose& /*pose*/, JointJacobian& d_joints_d_pose) const {
  d_joints_d_pose.setZero(joint_count(), kPoseSize);
  d_joints_d_pose.topLeftCorner<3, 3>() = coefficients_;
  for (std::size_t i = 0; i < passthrough_axes_.size(); ++i) {
    d_joints_d_pose(3 + static_cast<int>(i), passthrough_axes_[i]) = 1.0;
  }
  return Status::success();
}

std::vector<Parameter> MatrixKinematics::parameters() const {
  std::vector<Parameter> result;
  for (int row = 0; row < 3; ++row) {
    for (int col = 0; col < 3; ++col) {
      result.push_back(
          {std::string("C_") + kRowNames[row] + kRowNames[col], coefficients_(row, col), ""});
    }
  }
  return result;
}

void MatrixKinematics::set_parameters(std::span<const double> values) {
  if (values.size() != 9) throw std::invalid_argument("matrix model takes 9 parameters");
  Eigen::Matrix3d coefficients;
  for (int i = 0; i < 9; ++i) coefficients(i / 3, i % 3) = values[i];
  set_coefficients(coefficients);
}

std::unique_ptr<Kinematics> make_matrix_kinematics(const ModelConfig& config) {
  const Eigen::Matrix3d coefficients =
      config.has("matrix") ? config.matrix3("matrix") : Eigen::Matrix3d::Identity();
  std::vector<int> passthrough;
  if (config.has("passthrough")) {
    for (const std::string& name : config.string_list("passthrough")) {
      const int axis = axis_index(name);
      if (axis < 3) config.fail("passthrough", "'" + name + "' is not one of \"a\", \"b\", \"c\"");
      passthrough.push_back(axis);
    }
  }
  try {
    return std::make_unique<MatrixKinematics>(coefficients, std::move(passthrough));
  } catch (const std::invalid_argument& error) {
    config.fail("matrix", error.what());
  }
}

}  // namespace pkm
