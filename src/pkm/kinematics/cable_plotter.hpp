// Hanging two-cable plotter (Hektor): cables from anchors at (0,0) and (d,0), the tool hangs
// below them (y < 0) and gravity picks the lower of the two circle intersections.
#pragma once

#include "pkm/kinematics/kinematics.hpp"
#include "pkm/kinematics/model_config.hpp"

namespace pkm {

struct CablePlotterGeometry {
  double anchor_distance_mm = 0.0;
  // Added to each cable's geometric length to give the joint reading: where the cable's zero
  // (the limit-switch position of the homing procedure) really is.
  double left_cable_offset_mm = 0.0;
  double right_cable_offset_mm = 0.0;
};

class CablePlotterKinematics final : public Kinematics {
 public:
  explicit CablePlotterKinematics(const CablePlotterGeometry& geometry);

  std::string_view type() const override { return "cable_plotter"; }
  int joint_count() const override { return 2; }
  Dof dof() const override { return Dof::planar_xy(); }
  Status inverse(const Pose& pose, JointVector& joints) const override;
  Status forward(const JointVector& joints, Pose& pose_inout) const override;
  Status jacobian(const Pose& pose, JointJacobian& d_joints_d_pose) const override;
  std::vector<Parameter> parameters() const override;
  void set_parameters(std::span<const double> values) override;
  std::unique_ptr<Kinematics> clone() const override {
    return std::make_unique<CablePlotterKinematics>(*this);
  }

  const CablePlotterGeometry& geometry() const { return geometry_; }

 private:
  static void validate(const CablePlotterGeometry& geometry);
  CablePlotterGeometry geometry_;
};

std::unique_ptr<Kinematics> make_cable_plotter_kinematics(const ModelConfig& config);

}  // namespace pkm
