// Hanging two-cable plotter (Hektor): cables from anchors at (0,0) and (d,0), the tool hangs
// below them (y < 0) and gravity picks the lower of the two circle intersections. A cable can
// only pull: the pen hangs between the anchors (0 < x < d), elsewhere one cable would push.
// Optional pass-through joints (a pen on a real Z axis) follow the two cables.
#pragma once

#include "pkm/kinematics/kinematics.hpp"
#include "pkm/kinematics/model_config.hpp"
#include "pkm/kinematics/passthrough.hpp"

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
  explicit CablePlotterKinematics(const CablePlotterGeometry& geometry,
                                  PassThroughAxes passthrough = {});

  std::string_view type() const override { return "cable_plotter"; }
  int joint_count() const override { return 2 + passthrough_.count(); }
  Dof dof() const override { return passthrough_.add_to(Dof::planar_xy()); }
  JointKind joint_kind(int joint) const override {
    return joint < 2 ? JointKind::linear : passthrough_.kind(joint - 2);
  }
  int passthrough_axis(int joint) const override {
    return joint < 2 ? -1 : passthrough_.axes()[joint - 2];
  }
  Status inverse(const Pose& pose, JointVector& joints) const override;
  Status forward(const JointVector& joints, Pose& pose_inout) const override;
  Status jacobian(const Pose& pose, JointJacobian& d_joints_d_pose) const override;
  std::string why_refused(const Pose& pose, const Status& status) const override;
  std::vector<Parameter> parameters() const override;
  void set_parameters(std::span<const double> values) override;
  std::unique_ptr<Kinematics> clone() const override {
    return std::make_unique<CablePlotterKinematics>(*this);
  }

  const CablePlotterGeometry& geometry() const { return geometry_; }
  const PassThroughAxes& passthrough() const { return passthrough_; }

 private:
  static void validate(const CablePlotterGeometry& geometry);
  CablePlotterGeometry geometry_;
  PassThroughAxes passthrough_;
};

std::unique_ptr<Kinematics> make_cable_plotter_kinematics(const ModelConfig& config);

}  // namespace pkm
