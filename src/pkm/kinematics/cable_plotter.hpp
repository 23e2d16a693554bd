// Hanging two-cable plotter (Hektor, polargraphs, Makelangelo, the Maslow router): two cables from
// two pulleys to an effector that hangs below them. With nothing else given, the paper's model:
// massless, straight, unstretchable cables from two points to the pen, gravity picking the lower
// of the two circle intersections, in closed form. As built (cable_statics.hpp): pulleys the
// cables leave tangentially, a gondola or sled tied at two points that tilts under its weight,
// tension limits, cables that sag and stretch; inverse kinematics then solves the effector's
// balance and forward kinematics iterates on it. Optional pass-through joints (a pen on a real Z
// axis) follow the two cables.
#pragma once

#include "pkm/kinematics/cable_statics.hpp"
#include "pkm/kinematics/derivative_bounds.hpp"
#include "pkm/kinematics/firmware_form.hpp"
#include "pkm/kinematics/hanging_cables.hpp"
#include "pkm/kinematics/kinematics.hpp"
#include "pkm/kinematics/mechanism_sketch.hpp"
#include "pkm/kinematics/model_config.hpp"
#include "pkm/kinematics/passthrough.hpp"

namespace pkm::kinematics {

class CablePlotterKinematics final : public Kinematics,
                                     public HangingCables,
                                     public MechanismSketch,
                                     public DerivativeBounds {
 public:
  explicit CablePlotterKinematics(const CablePlotterGeometry& geometry,
                                  PassThroughAxes passthrough = {});

  std::string_view type() const override { return "cable_plotter"; }
  int joint_count() const override { return 2 + passthrough_.count(); }
  geometry::Dof dof() const override { return passthrough_.add_to(geometry::Dof::planar_xy()); }
  JointKind joint_kind(int joint) const override {
    return joint < 2 ? JointKind::linear : passthrough_.kind(joint - 2);
  }
  int passthrough_axis(int joint) const override {
    return joint < 2 ? -1 : passthrough_.axes()[joint - 2];
  }
  Status inverse(const geometry::Pose& pose, JointVector& joints) const override;
  Status forward(const JointVector& joints, geometry::Pose& pose_inout) const override;
  Status jacobian(const geometry::Pose& pose, JointJacobian& d_joints_d_pose) const override;
  std::string why_refused(const geometry::Pose& pose, const Status& status) const override;
  std::vector<Parameter> parameters() const override;
  void set_parameters(std::span<const double> values) override;
  std::unique_ptr<Kinematics> clone() const override {
    return std::make_unique<CablePlotterKinematics>(*this);
  }

  // The anchors (anchor_distance where they are level from 0), pulley, offsets, effector and
  // cable keys that differ from their defaults, then the pass-through axes.
  void write_config(ModelConfigWriter& out) const override;
  // The paper's model only: each cable the distance from its anchor plus its offset. Throws for
  // pulleys, a tilting effector, tension limits, sag or stretch (a balance of forces, no formula).
  std::optional<std::vector<std::string>> joint_formulas() const override;
  // A two-cable wall plotter (cable_plotter_firmware.cpp): the anchors and offsets; pulleys, a
  // tilting effector, sag, stretch and spool build-up are what the form loses.
  std::optional<FirmwareForm> firmware_form() const override;

  // The cables as the tension checks ask them (hanging_cables.hpp).
  const HangingCables* hanging_cables() const override { return this; }
  // The proofs' capabilities (cable_plotter_bounds.cpp): the rigid cables' Hessian bounds; the
  // geometry the balance's bounds over a box take (bounds/cable_bound).
  const DerivativeBounds* derivative_bounds() const override { return this; }
  std::optional<HessianBounds> own_hessian_bounds(const geometry::Vector6d& centre,
                                                  double radius_mm, double angle_scale_mm,
                                                  const Chord& chord) const override;
  const CablePlotterGeometry& cable_geometry() const override { return geometry_; }
  double effector_mass_kg() const override { return geometry_.effector_mass_kg; }
  bool effector_tilts() const override { return geometry_.tilts(); }
  bool tension_limited() const override { return geometry_.tension_limited; }
  // The tensions' [min, max] in N: tension_limits, else [0, inf) ("both cables pull").
  double tension_min_N() const override { return geometry_.tension_min_N; }
  double tension_max_N() const override { return geometry_.tension_max_N; }
  Status statics(const geometry::Pose& pose, const Eigen::Vector2d& acceleration_mm_per_s2,
                 CableStatics& out) const override;
  // The tension map's question (hanging_cables.hpp; cable_plotter_reach.cpp).
  std::unique_ptr<Kinematics> without_tension_limits() const override;

  // The drawing: the line between the anchors and the pulleys; the cables (drawn straight: a
  // sagging cable's curve is not drawn) and the effector tilted as its balance at rest tilts it.
  const MechanismSketch* sketch() const override { return this; }
  void fixed_parts(std::span<const JointTravel> travel,
                   std::vector<SketchLine>& out) const override;
  void moving_parts(const geometry::Pose& pose, const JointVector& joints,
                    std::vector<SketchLine>& out) const override;

  // Inverse kinematics with or without the tension limits (forward kinematics iterates without:
  // the limits say where the machine may go, not where its joints put the pen).
  Status inverse_within(const geometry::Pose& pose, JointVector& joints, bool within_limits) const;

  // Reach box (kinematics.hpp; cable_plotter_reach.cpp).
  std::optional<Eigen::AlignedBox3d> tool_position_box(const JointVector& joint_min,
                                                       const JointVector& joint_max) const override;

  const CablePlotterGeometry& geometry() const { return geometry_; }
  const PassThroughAxes& passthrough() const { return passthrough_; }

 private:
  Status ideal_inverse(const Eigen::Vector2d& pen_mm, JointVector& joints) const;
  Status ideal_forward(const JointVector& joints, Eigen::Vector2d& pen_mm) const;
  std::string why_ideal_refused(const Eigen::Vector2d& pen_mm, int cable) const;
  // Where straight cables of the joints' lengths, less `wrap_turns` of each pulley's
  // circumference, meet at the effector's level attachment points.
  Status straight_guess(const JointVector& joints, double wrap_turns,
                        Eigen::Vector2d& pen_mm) const;
  // The balance, and each cable past its pulley's top point (mm), with the drums' radii of a
  // spool build-up solved along.
  Status solve_balance(const Eigen::Vector2d& pen_mm, const Eigen::Vector2d& gravity_mm_per_s2,
                       CableBalance& balance, std::array<double, 2>& past_top_mm) const;
  // At rest, with the checks: both cables pull, and (within_limits) the tension limits.
  Status balance_at(const Eigen::Vector2d& pen_mm, CableBalance& balance,
                    std::array<double, 2>& past_top_mm, bool within_limits) const;

  CablePlotterGeometry geometry_;
  PassThroughAxes passthrough_;
};

// Throws std::invalid_argument naming the machine-file key at fault.
void validate_cable_plotter_geometry(const CablePlotterGeometry& geometry);

std::unique_ptr<Kinematics> make_cable_plotter_kinematics(const ModelConfig& config);

}  // namespace pkm::kinematics
