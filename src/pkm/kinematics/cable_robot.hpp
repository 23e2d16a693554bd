// A robot hung on N straight cables (issue 31): Hangprinter (spatial, four cables from anchors
// around the bed and one on the ceiling), Maslow 4 (planar, four belts on swivelling arms to the
// corners of a frame), Klipper's winch. The effector translates with its orientation held fixed,
// as these machines' firmwares take it (in reality the cables hold it only approximately). One
// joint per cable: its length from the anchor to the point where it is tied on the effector
// (straight, or over a swivelling pulley: cable_robot_pulley.cpp), plus an offset. With more cables
// than coordinates, forward kinematics is a least-squares fit over all cables, and joints that fit
// no pose (a slack or mismeasured cable) are refused with the misfit (docs/kinematics.md, "Cable
// robot"). Its derivative bounds and reach over a cell, the wrench-feasibility margin among them,
// are cable_robot_bounds.cpp's (docs/cable-machines.md, "The wrench-feasible workspace").
#pragma once

#include <Eigen/Core>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "pkm/kinematics/cable_tensions.hpp"
#include "pkm/kinematics/derivative_bounds.hpp"
#include "pkm/kinematics/firmware_form.hpp"
#include "pkm/kinematics/kinematics.hpp"
#include "pkm/kinematics/line_spools.hpp"
#include "pkm/kinematics/mechanism_sketch.hpp"
#include "pkm/kinematics/model_config.hpp"
#include "pkm/kinematics/passthrough.hpp"
#include "pkm/kinematics/tension_distribution.hpp"

namespace pkm::kinematics {

// A cable shorter than this has no direction: its tie point is at its anchor (inverse() refuses
// it as singular).
inline constexpr double kShortestRobotCable_mm = 1e-9;

// Per-cable values and d length / d tool position, on the stack (at most kMaxJoints cables).
using CableVector = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, kMaxJoints, 1>;
using CableJacobian = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kMaxJoints, 3>;

// The spool a cable winds on, as RepRapFirmware's Hangprinter drives it (M666 R U O L H J;
// cable_robot_spool.cpp): pkmkit's joint stays the cable's length; the spool turns it into motor
// steps, for the firmware export and for a controller counting motor steps.
struct CableSpool {
  // At line position 0: the cable as long as with the tool at x 0 y 0 z 0 (M666 R, "incl
  // buildup, when homed").
  double radius_mm = 0.0;
  int mechanical_advantage = 1;  // strands between anchor and effector (M666 U)
  int lines_per_spool = 1;       // M666 O
  int motor_gear_teeth = 1;      // M666 L
  int spool_gear_teeth = 1;      // M666 H
  int full_steps_per_rev = 200;  // M666 J
};

struct RobotCable {
  Eigen::Vector3d anchor_mm = Eigen::Vector3d::Zero();  // where it leaves the frame (world)
  Eigen::Vector3d attach_mm = Eigen::Vector3d::Zero();  // on the effector (tool point at 0)
  double offset_mm = 0.0;                               // joint = length + offset
  // A Maslow 4 arm: the cable is tied this far from `attach`, at the end of an arm turning freely
  // about the effector's z axis through `attach`, so that it points at the anchor in plan view.
  double swivel_arm_mm = 0.0;
  std::optional<CableSpool> spool;
  // Flex compensation: the line from its spool to the anchor (M666 Y), which stretches too.
  double guy_wire_mm = 0.0;
  // A swivelling pulley (cable_robot_pulley.cpp; docs/kinematics.md, "Cable robot: pulleys"):
  // the cable arrives along `pulley_axis` (a direction from `anchor` towards where it comes from,
  // its length ignored) and first touches the pulley at `anchor`; the pulley turns about that
  // axis to face the tie point and the cable wraps it before its straight span. 0: no pulley.
  double pulley_radius_mm = 0.0;
  Eigen::Vector3d pulley_axis = Eigen::Vector3d::Zero();
};

// A cable over its pulley at one pose (cable_robot_pulley.cpp). The length is wrap_mm + span_mm;
// its gradient in the tie point is `direction`, the span's unit vector from the pulley to the tie
// point (the tangent point moves along it).
struct PulleyPath {
  double length_mm = 0.0;
  double span_mm = 0.0;           // the straight span from the tangent point to the tie point
  double wrap_rad = 0.0;          // the angle the cable turns on the pulley, in [0, 2 pi)
  double rim_distance_mm = 0.0;   // from the tie point to the pulley's centre
  double axis_distance_mm = 0.0;  // from the tie point to the swivel axis
  double along_axis_mm = 0.0;     // (tie - anchor) . axis: > 0 back towards the winch
  Eigen::Vector3d direction = Eigen::Vector3d::Zero();
};
// Success, or `unreachable` where the tie point is on the swivel axis (the pulley has no plane
// to turn to) or on or within the pulley (no tangent): one clearance, the nearer of the two.
Status pulley_path(const RobotCable& cable, const Eigen::Vector3d& tie_mm, PulleyPath& path);

struct CableRobotGeometry {
  std::vector<RobotCable> cables;
  bool planar = false;  // x y only (N >= 3); else x y z (N >= 4)
  // A planar robot whose tie points ride on the tool's z (a pass-through joint): Maslow 4's arms
  // on its spindle. Otherwise the sled stays in z = 0 whatever the tool's z.
  bool cables_follow_z = false;
  double effector_mass_kg = 0.0;
  // Effector frame. The tension distribution balances forces only (the orientation held fixed by
  // assumption): the centre of mass would enter only the moments.
  Eigen::Vector3d center_of_mass_mm = Eigen::Vector3d::Zero();
  // Which way is down in machine coordinates: a direction (its length ignored), g = 9.80665 m/s^2
  // along it. A planar robot with a mass must give it (its sheet may be vertical, level or
  // tilted); a spatial one defaults to -z.
  Eigen::Vector3d gravity_direction = -Eigen::Vector3d::UnitZ();
  bool gravity_given = false;
  bool tension_limited = false;
  double tension_min_N = 0.0;
  double tension_max_N = 0.0;
  // The tension the distribution aims for (N); none: the middle of tension_limits (0 without).
  std::optional<double> preferred_tension_N;
  // Forward kinematics refuses joints whose least-squares fit leaves a cable further off (mm).
  double misfit_tolerance_mm = 0.01;
  // M666 Q (mm): how fast a spool's radius grows with the line wound on it; 0: constant radius.
  double spool_buildup_mm = 0.0;
  // RepRapFirmware's flex compensation (M666 F1; cable_robot_flex.cpp): each joint is the
  // unstretched length that the forces RRF plans stretch to the straight length.
  bool flex_compensation = false;
  // M666 S (N): a line of L mm stretches F L / S mm under F N.
  double line_stiffness_N = 20000.0;
  // Whether inverse() refuses the poses no tensions within tension_limits hold; not a machine-file
  // key: false only in geometry_only()'s copy.
  bool refuses_unheld_poses = true;
};

// RepRapFirmware's planned forces (N) and its gravity (m/s^2) for flex compensation.
inline constexpr double kRrfGravity_m_per_s2 = 9.81;
inline constexpr double kRrfForceRidge = 1e-3;

// Forward kinematics' least-squares fit of the joints, whatever its misfit. On the stack: the
// LinuxCNC module fits in its servo thread, where nothing may allocate.
struct CableFit {
  geometry::Pose pose;
  Status status;          // of the solve itself (not of the misfit)
  int iterations = 0;     // Gauss-Newton steps
  CableVector misfit_mm;  // per cable: its length at `pose` less the joint's (mm)
  double rms_mm = 0.0;
  double worst_mm = 0.0;  // the largest |misfit|
  int worst_cable = -1;
  // Per cable: how much its joint reads more than the value that, the others as they are, fits
  // the joints best, and the worst misfit left then (mm; the worst above where the cable cannot
  // change the misfit). A cable that leaves none beyond the tolerance explains the misfit alone;
  // with one cable more than coordinates every cable the fit depends on does.
  CableVector alone_excess_mm;
  CableVector alone_worst_mm;
  // The one cable that alone explains the misfit; -1 where none or several do.
  int culprit = -1;
};

class CableRobotKinematics final : public Kinematics,
                                   public MechanismSketch,
                                   public CableTensions,
                                   public DerivativeBounds,
                                   public LineSpools {
 public:
  // Throws std::invalid_argument ("key: message", key a machine-file key) for a bad geometry.
  explicit CableRobotKinematics(CableRobotGeometry geometry, PassThroughAxes passthrough = {});

  std::string_view type() const override { return "cable_robot"; }
  int joint_count() const override { return cable_count() + passthrough_.count(); }
  int cable_count() const { return static_cast<int>(geometry_.cables.size()); }
  geometry::Dof dof() const override { return passthrough_.add_to(mechanism_dof()); }
  JointKind joint_kind(int joint) const override {
    return joint < cable_count() ? JointKind::linear : passthrough_.kind(joint - cable_count());
  }
  int passthrough_axis(int joint) const override {
    return joint < cable_count() ? -1 : passthrough_.axes()[joint - cable_count()];
  }

  Status inverse(const geometry::Pose& pose, JointVector& joints) const override;
  // The least-squares fit (fit()), refused where it leaves a cable more than misfit_tolerance off:
  // `unreachable`, the joint the culprit cable (or the worst misfit where no single cable
  // explains it). explain_misfit() says it in numbers.
  Status forward(const JointVector& joints, geometry::Pose& pose_inout) const override;
  Status jacobian(const geometry::Pose& pose, JointJacobian& d_joints_d_pose) const override;
  std::string why_refused(const geometry::Pose& pose, const Status& status) const override;
  // A refused forward(): explain_misfit() of the fit from `seed`.
  std::string why_forward_refused(const JointVector& joints, const geometry::Pose& seed,
                                  const Status& status,
                                  std::span<const std::string> joint_names) const override;

  // Gauss-Newton over all cables from the seed, and from the trilateration's linear estimate where
  // the seed's fit misfits; the better of the two.
  CableFit fit(const JointVector& joints, const geometry::Pose& seed) const;
  // "the cables fit no pose: ..." with the RMS, the worst cable and the cables that alone explain
  // the misfit, named by `joint_names` (or numbered); empty where the fit is within the tolerance.
  std::string explain_misfit(const CableFit& fit, std::span<const std::string> joint_names) const;

  // The wrench matrix the tension distribution takes: one column per cable, the unit vector from
  // its tie point on the effector towards its anchor (2 rows for a planar robot: the plane's
  // components, the sheet taking the rest; 3 for a spatial one). Empty where a cable has no
  // direction (zero length).
  StructureMatrix structure_matrix(const geometry::Pose& pose) const;

  // A cable robot, its tie points folded into the anchors; Maslow 4's swivel arms and tie points
  // riding on z are losses (cable_robot_firmware.cpp).
  std::optional<FirmwareForm> firmware_form() const override;
  // The tension distribution (cable_robot_tensions.cpp; docs/cable-machines.md, "N cables").
  // The load the cables must balance: m (g - a) in N, forces only (x y for a planar robot, the
  // sheet taking the rest), the acceleration in mm/s^2.
  WrenchVector wrench_N(const Eigen::Vector3d& acceleration_mm_per_s2) const;
  // Per cable: tension_limits ([0, inf) without) and preferred_tension (their middle without).
  TensionTargets tension_targets() const override;
  // The tensions at `pose` while the effector accelerates; none where a cable has no direction.
  // Without tension_limits: the tensions of [0, inf) nearest the preferred ones (0: the least).
  std::optional<TensionDistribution> tensions(
      const geometry::Pose& pose,
      const Eigen::Vector3d& acceleration_mm_per_s2 = Eigen::Vector3d::Zero()) const override;
  // The same, as the rest of pkm asks them (cable_tensions.hpp).
  const CableTensions* cable_tensions() const override { return this; }
  int tension_count() const override { return cable_count(); }
  double effector_mass_kg() const override { return geometry_.effector_mass_kg; }
  bool tension_limited() const override { return geometry_.tension_limited; }
  Eigen::Vector3d cable_force_N(const Eigen::Vector3d& acceleration_mm_per_s2) const override {
    return -load_N(acceleration_mm_per_s2);
  }
  bool force_polytope(const geometry::Pose& pose, CableForcePolytope& polytope) const override;
  std::unique_ptr<Kinematics> geometry_only() const override;

  std::vector<Parameter> parameters() const override;
  void set_parameters(std::span<const double> values) override;
  std::unique_ptr<Kinematics> clone() const override {
    return std::make_unique<CableRobotKinematics>(*this);
  }
  void write_config(ModelConfigWriter& out) const override;

  // The drawing: the anchors joined as the frame, the cables and the effector's tie points.
  const MechanismSketch* sketch() const override { return this; }
  void fixed_parts(std::span<const JointTravel> travel,
                   std::vector<SketchLine>& out) const override;
  void moving_parts(const geometry::Pose& pose, const JointVector& joints,
                    std::vector<SketchLine>& out) const override;

  // Reach box (kinematics.hpp; cable_robot_reach.cpp).
  std::optional<Eigen::AlignedBox3d> tool_position_box(const JointVector& joint_min,
                                                       const JointVector& joint_max) const override;

  // Derivative bounds and reach (cable_robot_bounds.cpp; docs/kinematics.md, "Cable robot").
  const DerivativeBounds* derivative_bounds() const override { return this; }
  // Each cable's Hessian (I - u u^T) / l, a swivel arm's dominated by it (its own length l), a
  // pulley's by it with its span for l while the wrap stays within half a turn.
  std::optional<HessianBounds> own_hessian_bounds(const geometry::Vector6d& centre,
                                                  double radius_mm, double angle_scale_mm,
                                                  const Chord& chord) const override;
  // Per cable its clearance (mm): the straight cable's length, a swivel arm's plan distance to
  // its anchor less the arm, a pulley's the nearer of the rim and the swivel axis; then, with
  // tension_limits, the wrench-feasibility margin (N): the largest m for which tensions within [min
  // + m, max - m] hold the effector at rest.
  int reach_count() const override { return cable_count() + (geometry_.tension_limited ? 1 : 0); }
  void reach_over_cell(const geometry::Vector6d& centre, double scaled_radius,
                       double position_radius_mm, double angle_scale_mm,
                       std::span<std::array<double, 2>> margins) const override;
  ReachMargin reach_margin(int index) const override;
  // The wrench-feasibility margin at one pose (N) and the tensions that keep it; none where a
  // cable has no direction or the cables do not span the coordinates.
  struct WrenchMargin {
    double margin_N = 0.0;  // tension_N's least distance from a limit (< 0: past one)
    // No tensions holding the effector keep further from the limits (margin_N plus the
    // distribution's tolerance).
    double upper_N = 0.0;
    TensionVector tension_N;         // holds the effector, within residual_N
    double residual_N = 0.0;         // |A t + w|
    double smallest_singular = 0.0;  // of the structure matrix
  };
  std::optional<WrenchMargin> wrench_margin(const geometry::Pose& pose) const;

  const CableRobotGeometry& geometry() const { return geometry_; }

  // The motor position of cable `cable` for joint `joint_mm` in full steps (one microstep per
  // step) from line position 0, as RRF's spool model turns it (cable_robot_spool.cpp); none
  // without a spool or where the spool would unwind past its core.
  std::optional<double> motor_full_steps(int cable, double joint_mm) const override;
  // Its inverse, in closed form: the joint (mm) whose motor position is `full_steps`; none
  // without a spool or for a position no line length gives (more line paid out than it holds).
  std::optional<double> joint_from_motor_full_steps(int cable, double full_steps) const override;
  // The spools as the rest of pkm asks them (line_spools.hpp): this model where a cable has one.
  const LineSpools* line_spools() const override;
  bool has_spool(int joint) const override {
    return joint < cable_count() && geometry_.cables[joint].spool.has_value();
  }
  int full_steps_per_rev(int joint) const override {
    return has_spool(joint) ? geometry_.cables[joint].spool->full_steps_per_rev : 0;
  }
  // Full steps per mm of line at line position 0 (RRF's steps per mm over the microstepping).
  std::optional<double> full_steps_per_mm(int cable) const;
  // The joint at line position 0: with the tool at x 0 y 0 z 0 and the line unstretched (RRF's
  // distancesOrigin; over a pulley, its wrap and span there), plus the offset; none where the
  // pulley cannot reach the tie point there.
  std::optional<double> joint_at_line_origin_mm(int cable) const;
  // Flex compensation: the forces RRF plans for the tool at `tool_mm` (N, per cable; M666 F1's
  // least squares of the weight within tension_limits) and each cable's stretch under them (mm).
  void planned_forces(const Eigen::Vector3d& tool_mm, CableVector& force_N) const;
  void stretch(const Eigen::Vector3d& tool_mm, const CableVector& length_mm,
               CableVector& stretch_mm) const;

 private:
  geometry::Dof mechanism_dof() const {
    return geometry_.planar ? geometry::Dof::planar_xy() : geometry::Dof::translation();
  }
  int coordinates() const { return geometry_.planar ? 2 : 3; }
  // Where cable i is tied at tool position p: the arm's end (or `attach` without an arm); false
  // where the arm cannot point at its anchor (the anchor within the arm's reach in plan view).
  bool tie_point(int cable, const Eigen::Vector3d& tool_mm, Eigen::Vector3d& tie_mm) const;
  // The cables' lengths and d length / d tool position x y z (rows), with the first failure.
  Status lengths(const Eigen::Vector3d& tool_mm, CableVector& length_mm,
                 CableJacobian* d_length) const;
  // The most a cable whose unstretched length is `unstretched_mm` stretches (mm; 0 without flex
  // compensation, cable_robot_reach.cpp).
  double most_stretch(const RobotCable& cable, double unstretched_mm) const;
  // With flex compensation, d unstretched length / d tool: the stretch's part by Richardson-
  // extrapolated central differences (RRF's forces have no closed-form derivative).
  void flex_jacobian(const Eigen::Vector3d& tool_mm, CableJacobian& d_length) const;
  // Gauss-Newton (Marquardt-damped where a step does not lower the misfit) from `start`.
  CableFit gauss_newton(const CableVector& cable_lengths_mm, const geometry::Pose& start) const;
  // A start from the joints alone: the trilateration's linear least squares; none where the
  // cables' centres do not span the coordinates.
  std::optional<Eigen::Vector3d> trilateration(const CableVector& cable_lengths_mm,
                                               double tool_z_mm) const;
  void analyse_misfit(const CableJacobian& d_length, CableFit& fit) const;
  Eigen::Vector3d tool_point(const geometry::Pose& pose) const;
  // inverse()'s tension check at rest: `tension` and the worst cable where tension_limits are
  // given and no tensions within them hold the effector; success otherwise.
  Status check_tensions(const geometry::Pose& pose) const;
  // m (g - a) in N, all three components.
  Eigen::Vector3d load_N(const Eigen::Vector3d& acceleration_mm_per_s2) const;
  // Whether p projected onto the balance keeps every limit (then it is the distribution).
  bool projection_held(const geometry::Pose& pose) const;
  std::string explain_tensions(const geometry::Pose& pose) const;

  CableRobotGeometry geometry_;
  PassThroughAxes passthrough_;
};

// Throws std::invalid_argument ("key: message") naming the machine-file key at fault.
void validate_cable_robot_geometry(const CableRobotGeometry& geometry);
// The part of it about the load: gravity, the tension limits and the preferred tension
// (cable_robot_tensions.cpp).
void validate_cable_robot_load(const CableRobotGeometry& geometry);

// The spools and flex compensation (cable_robot_spool.cpp): throws std::invalid_argument ("key:
// message") for a bad value.
void validate_cable_robot_drive(const CableRobotGeometry& geometry);
// The pulleys: throws std::invalid_argument ("key: message").
void validate_cable_robot_pulleys(const CableRobotGeometry& geometry);
// Their machine-file keys: spool keys in [kinematics] hold for every cable that does not give its
// own; spool_buildup, flex_compensation and line_stiffness only there, guy_wire_length per cable.
void read_cable_robot_drive(const ModelConfig& kinematics, CableRobotGeometry& geometry);
void write_cable_robot_drive(const CableRobotGeometry& geometry, ModelConfigWriter& kinematics);
void write_cable_drive(const CableRobotGeometry& geometry, const RobotCable& cable,
                       ModelConfigWriter& entry);

std::unique_ptr<Kinematics> make_cable_robot_kinematics(const ModelConfig& config);

}  // namespace pkm::kinematics
