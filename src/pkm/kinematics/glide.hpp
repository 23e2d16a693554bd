// Fixed-length struts between a platform and carriages on straight rails: biglide (2 rails),
// triaglide and linear delta (3 rails, translating platform), hexaglide (6 rails, full pose).
// A translating glide may carry pass-through joints after its rails (a pen on a real Z axis).
#pragma once

#include <Eigen/Core>
#include <vector>

#include "pkm/kinematics/assembly_mode_bounds.hpp"
#include "pkm/kinematics/derivative_bounds.hpp"
#include "pkm/kinematics/firmware_form.hpp"
#include "pkm/kinematics/kinematics.hpp"
#include "pkm/kinematics/leg_limits.hpp"
#include "pkm/kinematics/mechanism_sketch.hpp"
#include "pkm/kinematics/model_config.hpp"
#include "pkm/kinematics/passthrough.hpp"

namespace pkm::kinematics {

struct GlideRail {
  Eigen::Vector3d origin_mm = Eigen::Vector3d::Zero();   // where the carriage reading is 0
  Eigen::Vector3d direction = Eigen::Vector3d::UnitX();  // unit vector of increasing reading
  double strut_mm = 0.0;                                 // strut length between joint centres
  Eigen::Vector3d attach_mm = Eigen::Vector3d::Zero();   // strut end, platform frame, tool tip at 0
  int branch = 1;  // +1: carriage ahead of the strut's foot along `direction`; -1: behind
};

class GlideKinematics final : public Kinematics,
                              public MechanismSketch,
                              public DerivativeBounds,
                              public AssemblyModeBounds {
 public:
  // `dof` is translation-only (2 or 3 axes, one per rail) or Dof::all() with six rails.
  // Pass-through axes, translating glides only, follow the rails as joints.
  GlideKinematics(std::vector<GlideRail> rails, geometry::Dof dof, PassThroughAxes passthrough = {},
                  const LegLimitSettings& leg_limits = {});

  std::string_view type() const override { return "glide"; }
  int joint_count() const override { return rail_count() + passthrough_.count(); }
  geometry::Dof dof() const override { return passthrough_.add_to(dof_); }
  JointKind joint_kind(int joint) const override {
    return joint < rail_count() ? JointKind::linear : passthrough_.kind(joint - rail_count());
  }
  int passthrough_axis(int joint) const override {
    return joint < rail_count() ? -1 : passthrough_.axes()[joint - rail_count()];
  }
  // The carriages' readings, then the leg limits (max_joint_angle, leg_diameter: the struts are
  // the legs) where the file sets them.
  Status inverse(const geometry::Pose& pose, JointVector& joints) const override;
  Status inverse_without_leg_limits(const geometry::Pose& pose, JointVector& joints) const;
  // jacobian and inverse_and_jacobian do not check the leg limits (see hexapod.hpp).
  Status forward(const JointVector& joints, geometry::Pose& pose_inout) const override;
  Status jacobian(const geometry::Pose& pose, JointJacobian& d_joints_d_pose) const override;
  std::string why_refused(const geometry::Pose& pose, const Status& status) const override {
    if (const std::string why = leg_limits_why(pose, status); !why.empty()) return why;
    if (status.joint < 0 || status.joint >= rail_count()) return {};
    const std::string rail = "rail " + std::to_string(status.joint + 1);
    if (status.code == StatusCode::singular) return "the strut of " + rail + " is across its rail";
    if (status.code != StatusCode::unreachable) return {};
    return "the strut of " + rail + " is too short to reach it";
  }
  Status inverse_and_jacobian(const geometry::Pose& pose, JointVector& joints,
                              JointJacobian& d_joints_d_pose) const override;
  // Translating glides: the side of the plane (line, with 2 rails) through the carriages' strut
  // ends on which the platform hangs, i.e. the sign of det[strut vectors].
  int assembly_mode(const geometry::Pose& pose) const override;
  void set_home(const geometry::Pose& home) override;
  bool has_mechanism_limits() const override { return leg_limits_.active(); }
  void mechanism_limits(const geometry::Pose& pose,
                        std::vector<MechanismLimit>& out) const override;
  std::vector<Parameter> parameters() const override;
  void set_parameters(std::span<const double> values) override;
  std::unique_ptr<Kinematics> clone() const override {
    return std::make_unique<GlideKinematics>(*this);
  }
  // Four poses at a time where AVX2 runs (lanes.hpp); the single-pose calls otherwise.
  void inverse_batch(std::span<const geometry::Pose> poses, std::span<JointVector> joints,
                     std::span<Status> statuses) const override;

  // orientation, axes, passthrough, the leg limits, then one [[kinematics.rails]] per rail.
  void write_config(ModelConfigWriter& out) const override;
  // A translating glide's carriages in closed form: q = d.w +- sqrt((d.w)^2 - w.w + strut^2), w
  // the tool tip plus the strut's attachment less the rail's origin. Throws for a hexaglide.
  std::optional<std::vector<std::string>> joint_formulas() const override;
  // A linear delta (glide_firmware.cpp) for three rails within 30 deg of vertical moving x y z:
  // rails that lean or carry their carriage below the effector are what the form loses.
  std::optional<FirmwareForm> firmware_form() const override;
  const LegLimitSettings* leg_limit_settings() const override {
    return leg_limits_.active() ? &leg_limits_.settings() : nullptr;
  }
  // The drawing: the rails over their travel; the struts from their carriages to the platform,
  // the platform and the tool.
  const MechanismSketch* sketch() const override { return this; }
  void fixed_parts(std::span<const JointTravel> travel,
                   std::vector<SketchLine>& out) const override;
  void moving_parts(const geometry::Pose& pose, const JointVector& joints,
                    std::vector<SketchLine>& out) const override;

  // The proofs' capabilities (glide_bounds.cpp): the carriages' Hessian bounds, the struts as
  // legs, each strut's reach over a cell; a translating glide's assembly mode over a ball or a
  // cell.
  const DerivativeBounds* derivative_bounds() const override { return this; }
  std::optional<HessianBounds> own_hessian_bounds(const geometry::Vector6d& centre,
                                                  double radius_mm, double angle_scale_mm,
                                                  const Chord& chord) const override;
  std::optional<double> farthest_platform_point_mm() const override;
  LegMotion leg_motion(const JointVector& joints, const JointJacobian& jacobian,
                       const HessianBounds& hessians, double radius, double scale) const override;
  std::optional<LegEnds> legs_at(const geometry::Pose& pose,
                                 const JointVector& joints) const override;
  ReachMargin reach_margin(int index) const override;
  int reach_count() const override { return rail_count(); }
  void reach_over_cell(const geometry::Vector6d& centre, double scaled_radius,
                       double position_radius_mm, double angle_scale_mm,
                       std::span<std::array<double, 2>> margins) const override;
  const AssemblyModeBounds* assembly_mode_bounds() const override {
    return dof_.any_rotation() ? nullptr : this;
  }
  std::optional<ModeBound> mode_over_ball(int home_mode, const geometry::Vector6d& centre,
                                          const JointVector& joints,
                                          std::span<const double> joint_speed) const override;
  bool has_mode_over_cell() const override { return true; }
  std::optional<ModeBound> mode_over_cell(int home_mode, const geometry::Vector6d& centre,
                                          double radius_mm) const override;
  // Reach box (kinematics.hpp; glide_reach.cpp).
  std::optional<Eigen::AlignedBox3d> tool_position_box(const JointVector& joint_min,
                                                       const JointVector& joint_max) const override;

  const std::vector<GlideRail>& rails() const { return rails_; }
  const PassThroughAxes& passthrough() const { return passthrough_; }
  const LegLimits& leg_limits() const { return leg_limits_; }
  // The struts' joint centres at a pose whose carriage readings are `joints`.
  LegEnds leg_ends(const geometry::Pose& pose, const JointVector& joints) const;
  // The axes the rails move (dof() adds the pass-through ones).
  geometry::Dof rail_dof() const { return dof_; }

 private:
  int rail_count() const { return static_cast<int>(rails_.size()); }
  // The pose as this model reads it: uncontrolled coordinates are zero.
  geometry::Pose controlled_part(const geometry::Pose& pose) const;
  // Closed-form FK of a translating platform: intersection of the spheres (3 rails) or circles
  // (2 rails) around each carriage, the candidate matching every rail's branch nearest the seed.
  Status forward_translating(const JointVector& joints, geometry::Pose& pose_inout) const;
  // forward_translating's choice between the two intersections `candidates` (tool tips): the
  // seed's pose with the one that reproduces `joints`, in the seed's assembly mode where both do.
  Status pick_candidate(const JointVector& joints, const std::array<Eigen::Vector3d, 2>& candidates,
                        const geometry::Pose& seed_pose, geometry::Pose& picked) const;
  // assembly_mode() of a translating platform whose tool tip is at `tip_mm` (controlled
  // coordinates; the others 0) on carriages at `joints`.
  int mode_of_tip(const Eigen::Vector3d& tip_mm, const JointVector& joints) const;
  static void validate(std::vector<GlideRail>& rails, geometry::Dof dof);
  std::string leg_limits_why(const geometry::Pose& pose, const Status& status) const;
  LegLimits leg_limits_;

  std::vector<GlideRail> rails_;
  geometry::Dof dof_;
  PassThroughAxes passthrough_;

 public:
  // The rails' constants side by side, rail i in slot i and the spare slots copies of the last
  // rail: one pose's readings, rails in vector lanes, read them. Rebuilt with rails_.
  struct RailsSideBySide {
    static constexpr int kSlots = 8;
    alignas(32) double origin_mm[3][kSlots];
    alignas(32) double direction[3][kSlots];
    alignas(32) double attach_mm[3][kSlots];
    alignas(32) double strut_squared_mm2[kSlots];
    alignas(32) double branch[kSlots];
    alignas(32) double singular_mm2[kSlots];  // the discriminant at or below which it is refused
  };

 private:
  void update_side_by_side();
  RailsSideBySide side_by_side_{};
};

std::unique_ptr<Kinematics> make_glide_kinematics(const ModelConfig& config);

}  // namespace pkm::kinematics
