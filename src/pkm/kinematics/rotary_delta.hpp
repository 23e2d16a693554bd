// Rotary (Clavel) delta: three motor arms turning about horizontal pivot axes on a fixed base,
// each carrying a parallelogram forearm down to a platform that only translates. The
// conventions are LinuxCNC's rotarydeltakins, so a rotarydeltakins configuration means the same
// machine here (docs/kinematics.md, "Rotary delta"):
// - the origin is the centre of the plane of the three pivot axes, z up: the tool is at z < 0;
// - arm i's pivot axis is base_radius from the centre in the direction -90 + 120 i deg from +X
//   (arm 0 swings in the YZ plane at y < 0, arms 1 and 2 at 30 and 150 deg);
// - a joint reads 0 with its arm horizontal and pointing outward, positive with the elbow down;
// - of the two elbow positions that reach a platform joint, the arm takes the outer one.
// Optional pass-through joints (a rotary C on the platform) follow the three arms.
#pragma once

#include <Eigen/Core>
#include <array>

#include "pkm/kinematics/assembly_mode_bounds.hpp"
#include "pkm/kinematics/derivative_bounds.hpp"
#include "pkm/kinematics/firmware_form.hpp"
#include "pkm/kinematics/kinematics.hpp"
#include "pkm/kinematics/mechanism_sketch.hpp"
#include "pkm/kinematics/model_config.hpp"
#include "pkm/kinematics/passthrough.hpp"

namespace pkm::kinematics {

struct RotaryDeltaGeometry {
  double base_radius_mm = 0.0;  // centre to each arm's pivot axis (rotarydeltakins' platformradius)
  double arm_length_mm = 0.0;   // pivot axis to elbow (thighlength)
  double forearm_length_mm = 0.0;   // elbow to platform joint, the parallelogram (shinlength)
  double platform_radius_mm = 0.0;  // tool point to each forearm's platform joint (footradius)
};

class RotaryDeltaKinematics final : public Kinematics,
                                    public MechanismSketch,
                                    public DerivativeBounds,
                                    public AssemblyModeBounds {
 public:
  static constexpr int kArms = 3;

  explicit RotaryDeltaKinematics(const RotaryDeltaGeometry& geometry,
                                 PassThroughAxes passthrough = {});

  std::string_view type() const override { return "rotary_delta"; }
  int joint_count() const override { return kArms + passthrough_.count(); }
  geometry::Dof dof() const override { return passthrough_.add_to(geometry::Dof::translation()); }
  JointKind joint_kind(int joint) const override {
    return joint < kArms ? JointKind::rotary : passthrough_.kind(joint - kArms);
  }
  int passthrough_axis(int joint) const override {
    return joint < kArms ? -1 : passthrough_.axes()[joint - kArms];
  }
  Status inverse(const geometry::Pose& pose, JointVector& joints) const override;
  // The elbow of arm `arm` at `angle_rad`, shifted inward by the platform radius: where the tool
  // point would be if the forearm had zero length (the forearm is tip - this).
  Eigen::Vector3d shifted_elbow(int arm, double angle_rad) const;
  // Closed form: the tool point is where three spheres meet, one of radius forearm_length around
  // each elbow shifted inward by platform_radius; of their two meeting points the lower one, as
  // rotarydeltakins takes. Joints whose elbows are not the outer ones reaching that point are
  // refused (`other_assembly`, naming the arm). The seed only supplies uncontrolled coordinates.
  Status forward(const JointVector& joints, geometry::Pose& pose_inout) const override;
  Status jacobian(const geometry::Pose& pose, JointJacobian& d_joints_d_pose) const override;
  Status inverse_and_jacobian(const geometry::Pose& pose, JointVector& joints,
                              JointJacobian& d_joints_d_pose) const override;
  // +1 where the platform hangs on the side of the plane through the three shifted elbows that
  // forward kinematics returns (the forearms' determinant negative: below them, on every
  // machine whose elbows stay outside the platform joints), -1 on the mirror side.
  int assembly_mode(const geometry::Pose& pose) const override;
  std::string why_refused(const geometry::Pose& pose, const Status& status) const override;
  // base_radius, arm_length, forearm_length, platform_radius (mm): the three arms share them.
  std::vector<Parameter> parameters() const override;
  void set_parameters(std::span<const double> values) override;
  std::unique_ptr<Kinematics> clone() const override {
    return std::make_unique<RotaryDeltaKinematics>(*this);
  }
  // base_radius, arm_length, forearm_length, platform_radius, passthrough.
  void write_config(ModelConfigWriter& out) const override;
  // The drawing: the circle of the pivots; each arm from its pivot to its elbow (joint 0:
  // horizontal and outward, positive: elbow down), the forearm on to its platform joint, the
  // platform as the circle of its joints.
  const MechanismSketch* sketch() const override { return this; }
  void fixed_parts(std::span<const JointTravel> travel,
                   std::vector<SketchLine>& out) const override;
  void moving_parts(const geometry::Pose& pose, const JointVector& joints,
                    std::vector<SketchLine>& out) const override;

  // The proofs' capabilities (rotary_delta_bounds.cpp): the arms' Hessian bounds and turns per
  // mm; the assembly mode (det of the forearms) over a ball.
  const DerivativeBounds* derivative_bounds() const override { return this; }
  std::optional<HessianBounds> own_hessian_bounds(const geometry::Vector6d& centre,
                                                  double radius_mm, double angle_scale_mm,
                                                  const Chord& chord) const override;
  LegMotion leg_motion(const JointVector& joints, const JointJacobian& jacobian,
                       const HessianBounds& hessians, double radius, double scale) const override;
  const AssemblyModeBounds* assembly_mode_bounds() const override { return this; }
  std::optional<ModeBound> mode_over_ball(int home_mode, const geometry::Vector6d& centre,
                                          const JointVector& joints,
                                          std::span<const double> joint_speed) const override;

  // A rotary delta, exactly: the form's conventions are this model's (firmware_form.hpp).
  std::optional<FirmwareForm> firmware_form() const override;
  const RotaryDeltaGeometry& geometry() const { return geometry_; }
  const PassThroughAxes& passthrough() const { return passthrough_; }
  // Horizontal unit vector from the centre towards arm `arm`'s pivot axis.
  static Eigen::Vector3d arm_direction(int arm);

 private:
  // One arm's inverse kinematics at tool point `tip`.
  struct ArmSolution {
    double angle_rad = 0.0;
    Eigen::Vector3d forearm_mm = Eigen::Vector3d::Zero();  // elbow to platform joint
    // forearm . d(elbow)/d(angle): how much the forearm's far end moves per radian of the arm;
    // 0 at the arm's singularity (forearm in line with the arm, seen along the pivot axis).
    double lever_mm2 = 0.0;
  };
  Status solve_arm(int arm, const Eigen::Vector3d& tip, ArmSolution& solution) const;
  Status solve_arms(const geometry::Pose& pose, std::array<ArmSolution, kArms>& arms) const;
  static void validate(const RotaryDeltaGeometry& geometry);

  RotaryDeltaGeometry geometry_;
  PassThroughAxes passthrough_;
};

std::unique_ptr<Kinematics> make_rotary_delta_kinematics(const ModelConfig& config);

}  // namespace pkm::kinematics
