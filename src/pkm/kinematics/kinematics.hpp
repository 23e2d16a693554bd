// The one interface every kinematic model answers (docs/architecture.md, "The kinematics
// interface").
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <Eigen/LU>
#include <array>
#include <cmath>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "pkm/geometry/pose.hpp"

namespace pkm::kinematics {

// What a model may answer for itself beyond its equations, each interface in its own header.
class ModelConfigWriter;  // model_config_writer.hpp
class MechanismSketch;    // mechanism_sketch.hpp
class HangingCables;      // hanging_cables.hpp
class CableTensions;      // cable_tensions.hpp
class LineSpools;         // line_spools.hpp
struct LegLimitSettings;  // leg_limits.hpp
// The proofs' capabilities (issue 28, the proofs' part).
class DerivativeBounds;    // derivative_bounds.hpp
class AssemblyModeBounds;  // assembly_mode_bounds.hpp
struct FirmwareForm;       // firmware_form.hpp

// Nine joints cover every model here (a hexapod has six, a matrix mill three plus pass-through
// rotary axes); the fixed upper bound keeps joint vectors on the stack in the per-sample path.
inline constexpr int kMaxJoints = 9;
using JointVector = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, kMaxJoints, 1>;
// d joints / d pose: one row per joint, one column per pose coordinate x y z (mm) a b c (rad).
// Columns of coordinates the model does not control are zero.
using JointJacobian =
    Eigen::Matrix<double, Eigen::Dynamic, geometry::kPoseSize, 0, kMaxJoints, geometry::kPoseSize>;

enum class StatusCode {
  ok,
  unreachable,       // the geometry cannot reach the pose (strut too short, circles do not meet)
  joint_limit,       // reachable, but a joint would leave [min, max] of the machine file
  singular,          // at or too close to a singular configuration
  not_converged,     // forward kinematics did not converge within its iteration cap
  branch_changed,    // forward kinematics converged on another assembly branch than its seed
  other_assembly,    // the pose needs another assembly mode than the machine's (home's)
  invalid_input,     // NaN or infinite input
  outside_envelope,  // a coordinate passes the machine file's [cartesian] min or max
  tension,           // a cable would go slack or pass its tension limit (joint: the cable)
  joint_angle,       // a leg passes max_joint_angle at one of its joints (joint: the leg)
  interference,      // two legs closer than leg_diameter (joint: the first of the two)
};

struct Status {
  StatusCode code = StatusCode::ok;
  int joint = -1;  // the joint (strut, leg, cable) the failure concerns; -1 when none
  int axis = -1;   // the pose coordinate (0..5 = x y z a b c) of outside_envelope; -1 when none
  // Newton iterations forward kinematics took (0 for closed forms and everything else): what
  // LinuxCNC's kinematics modules show on their fk-iterations pin.
  int iterations = 0;

  constexpr bool ok() const { return code == StatusCode::ok; }
  static constexpr Status success() { return {}; }
  static constexpr Status failure(StatusCode code, int joint = -1) { return {code, joint, -1, 0}; }
  static constexpr Status outside(int axis) { return {StatusCode::outside_envelope, -1, axis, 0}; }
};

std::string_view status_name(StatusCode code);
// The code as an identifier ("joint_limit", "other_assembly"): what JSON keys and the Python
// module's status arrays hold.
std::string_view status_identifier(StatusCode code);
// A sentence for a user: "unreachable (joint 3)" style, with the joint's name where given.
std::string describe(const Status& status, std::span<const std::string> joint_names = {});

// A limit of the mechanism beyond the joints' ranges, evaluated at a pose (leg_limits.hpp): how
// far a leg's joint end is turned, or how far apart two legs are, and the limit it must keep.
struct MechanismLimit {
  StatusCode code = StatusCode::joint_angle;  // joint_angle or interference
  int leg = -1;                               // the leg; for interference the first of the two
  int other = -1;      // joint_angle: the end (0 inner: base or carriage, 1 platform); else 2nd leg
  double value = 0.0;  // rad (the angle from the neutral axis) or mm (between the legs' axes)
  double limit = 0.0;  // rad (max_joint_angle) or mm (leg_diameter)
  // >= 0 while the limit holds, in the value's unit.
  double margin() const { return code == StatusCode::joint_angle ? limit - value : value - limit; }
};

// Where a pose stands against the plane through a hexapod's base joints, which its platform
// joints cross only by passing the singularity where the legs lie flat in it: the least margin
// over the legs (mm, on home's side of the plane; negative past it) and the leg it belongs to.
struct BasePlaneMargin {
  double margin_mm = INFINITY;
  int leg = -1;  // -1: no leg takes part
};

enum class JointKind { linear, rotary };  // linear joints in mm; rotary in rad inside, deg outside

// How far a built machine can plausibly be from its machine file at a parameter depends on what
// the parameter stands for in the hardware (docs/calibration.md's table): the model says so beside
// each parameter, so that calibration judges a fit without asking which model it fits.
enum class BuiltTolerance {
  none,          // not judged, by rank only (a formula's constants)
  machine_size,  // built and measured to 2 mm + 2 % of the machine's size: points, lengths, zeros
  own_value,     // a share of its own nominal value: a catalogue part, a weighed property
  absolute,  // a fixed deviation in the parameter's unit: a direction's component, a coefficient
};
struct BuiltAs {
  std::string_view what;  // for messages, a literal: "a pulley's radius"
  BuiltTolerance tolerance = BuiltTolerance::none;
  double amount = 0.0;  // own_value: the share (0.2 for 20 %); absolute: the deviation
};

// A named geometric parameter, the unit of calibration.
struct Parameter {
  Parameter() = default;
  Parameter(std::string name_, double value_, std::string unit_, BuiltAs built_as_ = {})
      : name(std::move(name_)), value(value_), unit(std::move(unit_)), built_as(built_as_) {}

  std::string name;
  double value = 0.0;
  std::string unit;  // "mm", "rad" or "" for dimensionless
  BuiltAs built_as;
};

// Settings of the iterative forward solvers.
struct ForwardOptions {
  double tolerance_mm = 1e-11;  // largest joint residual accepted as converged
  int max_iterations = 50;
};

// The per-call scratch of forward kinematics along a path: the model stays constant, this changes
// with every sample (Pinocchio's Model/Data split). It keeps the last solutions, to extrapolate the
// next sample's seed from, and a recent Jacobian, factorised, which Newton steps reuse while they
// keep converging. One per path and thread; a default-constructed one starts a path.
class ForwardTrack {
 public:
  // Forget the path: the next call starts from its seed, with the model's full forward().
  void restart() {
    count_ = 0;
    factored_ = false;
    det_sign_ = 0.0;
  }

 private:
  friend class Kinematics;
  std::array<geometry::Vector6d, 3> solutions_{};  // [0] the latest
  int count_ = 0;
  // The inverse of J (padded to 6x6 with identity), from its LU: a step is then one 6x6 product,
  // where the LU's triangular solves would take six dependent divisions.
  Eigen::Matrix<double, 6, 6> inverse_;
  bool factored_ = false;
  int extra_steps_ = 0;    // Newton steps beyond one per sample since the factorisation
  double det_sign_ = 0.0;  // sign of det J along the path; 0 before the first factorisation
};

class Kinematics {
 public:
  virtual ~Kinematics() = default;

  virtual std::string_view type() const = 0;
  virtual int joint_count() const = 0;
  virtual geometry::Dof dof() const = 0;
  virtual JointKind joint_kind(int /*joint*/) const { return JointKind::linear; }
  // The pose coordinate (0..5) a pass-through joint copies, or -1 for a joint of the mechanism.
  virtual int passthrough_axis(int /*joint*/) const { return -1; }

  // IK. Never writes NaN: a failed pose returns a status and leaves `joints` unspecified.
  virtual Status inverse(const geometry::Pose& pose, JointVector& joints) const = 0;
  // FK. `pose_inout` is the seed on entry (the previous pose along a path, or home); coordinates
  // the model does not control are left as seeded.
  virtual Status forward(const JointVector& joints, geometry::Pose& pose_inout) const = 0;
  virtual Status jacobian(const geometry::Pose& pose, JointJacobian& d_joints_d_pose) const = 0;
  // Both at once, sharing the work (one rotation, one set of strut vectors): what every Newton
  // iteration of FK asks for. The default calls the two.
  virtual Status inverse_and_jacobian(const geometry::Pose& pose, JointVector& joints,
                                      JointJacobian& d_joints_d_pose) const;
  // +1 or -1: which of the model's mirror-image assembly modes the pose is in, for models whose
  // IK alone cannot tell (a triaglide's platform below or above its carriages); 0 where the model
  // has a single mode or the check would cost more than it is worth in the per-sample path.
  virtual int assembly_mode(const geometry::Pose& /*pose*/) const { return 0; }
  // Why inverse() refused `pose` with `status`, in the model's own terms (which cable would push,
  // which strut is too short), for error messages; empty where the status says it all.
  virtual std::string why_refused(const geometry::Pose& /*pose*/, const Status& /*status*/) const {
    return {};
  }
  // Why forward() refused `joints` from `seed` with `status`, in the model's own terms (joints
  // that fit no pose: which cables alone explain the misfit, by how much), its joints named by
  // `joint_names` (or numbered); empty where the status says it all.
  virtual std::string why_forward_refused(const JointVector& /*joints*/,
                                          const geometry::Pose& /*seed*/, const Status& /*status*/,
                                          std::span<const std::string> /*joint_names*/) const {
    return {};
  }

  // The machine's home pose, for models whose limits refer to it (the neutral axes of joints with
  // a max_joint_angle are the legs' directions at home). Machine's constructor calls it.
  virtual void set_home(const geometry::Pose& /*home*/) {}
  // Whether inverse() checks limits of the mechanism beyond the joints' ranges (joint angles,
  // leg interference), and their values at `pose` (appended to `out`; nothing where the pose has
  // no legs, or the model has no such limits).
  virtual bool has_mechanism_limits() const { return false; }
  virtual void mechanism_limits(const geometry::Pose& /*pose*/,
                                std::vector<MechanismLimit>& /*out*/) const {}

  // What the model answers for itself beyond its equations (docs/kinematics.md, "What a model
  // answers for itself"): the rest of pkm asks these, never which class a model is.
  //
  // Its own keys of a machine file's [kinematics], as its make_*_kinematics reads them (the
  // registry writes `type` and the forward options around them). The default writes none.
  virtual void write_config(ModelConfigWriter& /*out*/) const {}
  // The mechanism's joints (not the pass-through ones) as closed formulas of the pose (x y z in mm;
  // a formula machine's own, in its file's units): muParser's syntax, numbers as plain decimals,
  // what Mach3's formula axes take. None where the model has no closed formula; throws
  // std::invalid_argument saying why where this machine of a model that has one cannot (a glide
  // that turns its platform).
  virtual std::optional<std::vector<std::string>> joint_formulas() const { return std::nullopt; }
  // The model's geometry in a form firmwares with kinematics implement, with what that form
  // leaves out (firmware_form.hpp); none where the model is no such form (the default).
  virtual std::optional<FirmwareForm> firmware_form() const;
  // The mechanism drawn to scale; none: a drawing shows the work envelope only.
  virtual const MechanismSketch* sketch() const { return nullptr; }
  // The effector's balance and the tension limits of a machine hanging from cables; none for a
  // machine without cables.
  virtual const HangingCables* hanging_cables() const { return nullptr; }
  // The tensions of an effector held by more cables than it has coordinates (their distribution
  // among the cables is chosen, not given by the geometry); none for any other machine.
  virtual const CableTensions* cable_tensions() const { return nullptr; }
  // Motor positions of joints that are lines on spools; none where no joint is.
  virtual const LineSpools* line_spools() const { return nullptr; }
  // The joint-angle and interference limits the machine file sets; none where it sets none, or
  // the model has no legs.
  virtual const LegLimitSettings* leg_limit_settings() const { return nullptr; }
  // A hexapod's platform against its base plane at `pose` (its assembly mode's measure); the
  // default, no leg, for every other model.
  virtual BasePlaneMargin base_plane_margin(const geometry::Pose& /*pose*/) const { return {}; }
  // The proofs' capabilities: bounds on the inverse kinematics' derivatives over a ball (and the
  // legs' motion, the reach over a cell), and on the assembly mode over a ball or a box; none: the
  // proofs have no bound for this model (a formula machine's).
  virtual const DerivativeBounds* derivative_bounds() const { return nullptr; }
  virtual const AssemblyModeBounds* assembly_mode_bounds() const { return nullptr; }
  // Reach box (the workspace's search box): a box (mm) holding every tool position the mechanism
  // can take with each joint j within [joint_min[j], joint_max[j]], from its geometry alone (leg,
  // strut or cable lengths about their anchors; a matrix's inverse over the joints' corners).
  // None where the model has no such box (the workspace then searches about home's extent).
  virtual std::optional<Eigen::AlignedBox3d> tool_position_box(
      const JointVector& /*joint_min*/, const JointVector& /*joint_max*/) const {
    return std::nullopt;
  }

  virtual std::vector<Parameter> parameters() const = 0;
  // Values in the order and units of parameters(); throws std::invalid_argument when the new
  // geometry is impossible (e.g. a singular matrix).
  virtual void set_parameters(std::span<const double> values) = 0;

  virtual std::unique_ptr<Kinematics> clone() const = 0;

  const ForwardOptions& forward_options() const { return forward_options_; }
  void set_forward_options(const ForwardOptions& options) { forward_options_ = options; }

  // Batch entry points. Defaults loop over the single-pose calls; models with a cheap closed form
  // override them. forward_path runs forward_along over the samples with one track.
  virtual void inverse_batch(std::span<const geometry::Pose> poses, std::span<JointVector> joints,
                             std::span<Status> statuses) const;
  void forward_path(std::span<const JointVector> joints, const geometry::Pose& seed,
                    std::span<geometry::Pose> poses, std::span<Status> statuses) const;
  // FK of the next sample along a path, samples evenly spaced in time (a servo period, a planner's
  // step). While `pose_inout` is the track's last solution (to 1e-9 mm or rad) the seed is
  // extrapolated from the last three, and Newton steps go through the track's factorised
  // Jacobian, refreshed (at the next seed) once the samples since it have taken two steps more
  // than one each, or a step cuts the residual less than tenfold: one step per sample on a
  // smooth servo-rate path. Otherwise, or when that does not converge within a few steps, or det J
  // changes sign, it is forward() from `pose_inout`, as without a track. Square models with
  // linear joints only (as many joints as controlled coordinates; rotary ones only passing
  // through); the others always take forward().
  Status forward_along(const JointVector& joints, geometry::Pose& pose_inout,
                       ForwardTrack& track) const;

 protected:
  ForwardOptions forward_options_;

 private:
  // forward_along's Newton steps from `x`; false where they do not get within the tolerance.
  bool track_steps(const JointVector& joints, geometry::Vector6d& x, ForwardTrack& track,
                   int& iterations) const;
  // The track's LU of the Jacobian at `x`; false where IK fails there or det J changed sign.
  bool factorise(const geometry::Vector6d& x, ForwardTrack& track) const;
};

// `value` printed with a printf pattern ("%.3f", "%g"): the numbers of error messages.
std::string formatted_number(const char* printf_pattern, double value);

// True when every entry is finite. Plain loops, inline: Eigen's allFinite (x - x == 0 over the
// whole vector) cost several times more, on every sample.
inline bool all_finite(const geometry::Pose& pose) {
  for (int k = 0; k < 3; ++k) {
    if (!std::isfinite(pose.position_mm[k]) || !std::isfinite(pose.orientation_rad[k]))
      return false;
  }
  return true;
}
bool all_finite(const JointVector& joints);

// Damped Newton (Levenberg-Marquardt) forward kinematics over the model's controlled
// coordinates, with the model's own inverse and jacobian. Refuses a solution on the other side of
// a singularity from the seed (sign of det J changed), which is how an iteration shows it jumped to
// another assembly branch. A square model's Newton that does not contract from the seed (a far
// seed: it could land on another solution of the same joints) is replaced by continuation along
// the straight joint path from the seed's joints, then a walk keeping det J's sign: the answer is
// the seed's branch's (docs/kinematics.md, "Forward kinematics").
Status solve_forward_newton(const Kinematics& model, const JointVector& joints,
                            geometry::Pose& pose_inout, const ForwardOptions& options);

// Central-difference Jacobian of model.inverse, for models without an analytic one.
Status numerical_jacobian(const Kinematics& model, const geometry::Pose& pose,
                          JointJacobian& d_joints_d_pose);

}  // namespace pkm::kinematics
