// LinuxCNC matrixkins: joint = C * axis for x y z; further axes pass through unchanged.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "pkm/kinematics/derivative_bounds.hpp"
#include "pkm/kinematics/kinematics.hpp"
#include "pkm/kinematics/model_config.hpp"
#include "pkm/kinematics/passthrough.hpp"

namespace pkm::kinematics {

class MatrixKinematics final : public Kinematics, public DerivativeBounds {
 public:
  // `passthrough_axes` are pose indices (3..5) appended as joints after x y z, in order.
  MatrixKinematics(const Eigen::Matrix3d& coefficients, std::vector<int> passthrough_axes);

  std::string_view type() const override { return "matrix"; }
  int joint_count() const override { return 3 + passthrough_.count(); }
  geometry::Dof dof() const override { return dof_; }
  JointKind joint_kind(int joint) const override {
    return joint < 3 ? JointKind::linear : passthrough_.kind(joint - 3);
  }
  int passthrough_axis(int joint) const override {
    return joint < 3 ? -1 : passthrough_.axes()[joint - 3];
  }
  Status inverse(const geometry::Pose& pose, JointVector& joints) const override;
  Status forward(const JointVector& joints, geometry::Pose& pose_inout) const override;
  Status jacobian(const geometry::Pose& pose, JointJacobian& d_joints_d_pose) const override;
  std::vector<Parameter> parameters() const override;
  void set_parameters(std::span<const double> values) override;
  std::unique_ptr<Kinematics> clone() const override {
    return std::make_unique<MatrixKinematics>(*this);
  }
  // matrix, passthrough.
  void write_config(ModelConfigWriter& out) const override;
  // Each joint the sum of its row's coefficients times x y z.
  std::optional<std::vector<std::string>> joint_formulas() const override;
  // The proofs' capability (matrix_bounds.cpp): linear, every second derivative zero, no limit
  // but the joints'.
  const DerivativeBounds* derivative_bounds() const override { return this; }
  std::optional<HessianBounds> own_hessian_bounds(const geometry::Vector6d& centre,
                                                  double radius_mm, double angle_scale_mm,
                                                  const Chord& chord) const override;
  bool refuses_only_joint_limits() const override { return true; }

  // Reach box (kinematics.hpp; matrix_reach.cpp).
  std::optional<Eigen::AlignedBox3d> tool_position_box(const JointVector& joint_min,
                                                       const JointVector& joint_max) const override;

  const Eigen::Matrix3d& coefficients() const { return coefficients_; }
  const std::vector<int>& passthrough_axes() const { return passthrough_.axes(); }
  // Largest ratio of singular values accepted: beyond it FK would amplify a joint error of 1 um
  // into more than 1 m of tool motion, which is a typo in the file, not a machine.
  static constexpr double kMaxConditionNumber = 1e6;

 private:
  void set_coefficients(const Eigen::Matrix3d& coefficients);

  Eigen::Matrix3d coefficients_;
  Eigen::Matrix3d inverse_coefficients_;
  PassThroughAxes passthrough_;
  geometry::Dof dof_;
};

std::unique_ptr<Kinematics> make_matrix_kinematics(const ModelConfig& config);

}  // namespace pkm::kinematics
