#include "pkm/kinematics/matrix.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <cmath>
#include <stdexcept>
#include <string>

#include "pkm/kinematics/closed_form_text.hpp"

namespace pkm::kinematics {

namespace {
constexpr std::array<const char*, 3> kRowNames = {"x", "y", "z"};
}  // namespace

MatrixKinematics::MatrixKinematics(const Eigen::Matrix3d& coefficients,
                                   std::vector<int> passthrough_axes)
    : passthrough_(std::move(passthrough_axes), geometry::Dof::translation()),
      dof_(passthrough_.add_to(geometry::Dof::translation())) {
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

Status MatrixKinematics::inverse(const geometry::Pose& pose, JointVector& joints) const {
  if (!all_finite(pose)) return Status::failure(StatusCode::invalid_input);
  joints.resize(joint_count());
  joints.head<3>() = coefficients_ * pose.position_mm;
  passthrough_.inverse(pose, joints, 3);
  return Status::success();
}

Status MatrixKinematics::forward(const JointVector& joints, geometry::Pose& pose_inout) const {
  if (joints.size() != joint_count() || !all_finite(joints)) {
    return Status::failure(StatusCode::invalid_input);
  }
  pose_inout.position_mm = inverse_coefficients_ * joints.head<3>();
  passthrough_.forward(joints, 3, pose_inout);
  return Status::success();
}

Status MatrixKinematics::jacobian(const geometry::Pose& /*pose*/,
                                  JointJacobian& d_joints_d_pose) const {
  d_joints_d_pose.setZero(joint_count(), geometry::kPoseSize);
  d_joints_d_pose.topLeftCorner<3, 3>() = coefficients_;
  passthrough_.jacobian(d_joints_d_pose, 3);
  return Status::success();
}

std::vector<Parameter> MatrixKinematics::parameters() const {
  std::vector<Parameter> result;
  for (int row = 0; row < 3; ++row) {
    for (int col = 0; col < 3; ++col) {
      // matrixkins corrections are of the order of 1e-3 (a squareness of a millimetre per metre).
      result.push_back({std::string("C_") + kRowNames[row] + kRowNames[col],
                        coefficients_(row, col),
                        "",
                        {"a matrix coefficient", BuiltTolerance::absolute, 0.01}});
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

std::optional<std::vector<std::string>> MatrixKinematics::joint_formulas() const {
  std::vector<std::string> formulas;
  for (int row = 0; row < 3; ++row) {
    std::string e;
    for (int col = 0; col < 3; ++col) {
      if (coefficients_(row, col) == 0.0) continue;
      e += (e.empty() ? "" : " + ") + std::string("(") + plain_decimal(coefficients_(row, col)) +
           "*" + kRowNames[col] + ")";
    }
    formulas.push_back(e.empty() ? "0" : e);
  }
  return formulas;
}

std::unique_ptr<Kinematics> make_matrix_kinematics(const ModelConfig& config) {
  const Eigen::Matrix3d coefficients =
      config.has("matrix") ? config.matrix3("matrix") : Eigen::Matrix3d::Identity();
  const PassThroughAxes passthrough =
      PassThroughAxes::read(config, geometry::Dof::translation(), geometry::Dof::all());
  try {
    return std::make_unique<MatrixKinematics>(coefficients, passthrough.axes());
  } catch (const std::invalid_argument& error) {
    config.fail("matrix", error.what());
  }
}

void MatrixKinematics::write_config(ModelConfigWriter& out) const {
  out.matrix3("matrix", coefficients_);
  passthrough_.write(out);
}

}  // namespace pkm::kinematics
