// What a model proves about its inverse kinematics over a ball of poses, in a scaled pose norm
// (angles weighed in mm per rad): bounds on the second (and, for hexapods, third) derivatives,
// how its legs move, where its legs are, and the edge of its reach over a cell. Kinematics::
// derivative_bounds() gives it; bounds/ (post's deviation bound, the certified check, the
// workspace, the pose-box joint-rate bound) asks it, whatever the model (docs/post.md, "The
// bound"; docs/kinematics.md, "What a model answers for itself").
#pragma once

#include <array>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "pkm/kinematics/kinematics.hpp"
#include "pkm/kinematics/leg_limits.hpp"

namespace pkm::kinematics {

// A straight move in pose space: its position change (mm, zero in the coordinates the model
// does not control) and the norm of its angle change (scaled).
struct Chord {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  double angle = 0.0;
};

// Per joint, over every pose within `radius_mm` of a centre in the model's controlled
// coordinates with rotations scaled by `angle_scale_mm`: `norm`, an upper bound on the operator
// norm of the Hessian of the joint's inverse kinematics, and `along`, on |H[v, v]| for v = the
// chord. Infinity where the ball reaches a singularity of the model. `third`, where the model
// gives one, bounds |D3 IK_i[v, v, v]| on the ball (empty otherwise).
struct HessianBounds {
  std::vector<double> norm, along, third;
  void add(double norm_bound, double along_bound) {
    norm.push_back(norm_bound);
    along.push_back(along_bound);
  }
};

// How each leg's ends move per unit of the scaled pose norm over a ball, and how short the leg
// can get there: what the joint-angle and clearance bounds take. Empty for models without legs.
struct LegMotion {
  std::vector<double> inner_speed, platform_speed, shortest_mm;
  // Each leg's platform joint's distance from the pose's point (mm): how far a turn moves it.
  std::vector<double> platform_arm_mm;
  double platform_turn = 0.0;  // rad per scaled unit: how fast a platform-fixed axis turns
};

// The operator norm, over the scaled pose ball, of the map from pose to a platform point b (mm
// from the tool tip): the identity on the position and at most |b| / scale per scaled angle.
double platform_point_gain(double b_norm_mm, double angle_scale_mm);
// Every second derivative of R(a, b, c) b is a product of rotations and unit skew matrices, so
// |d2(R b)| <= |b| per entry; a 3 x 3 block of them has norm <= 3 |b| (per scaled angle squared).
double rotation_curvature(double b_norm_mm, double angle_scale_mm);
// How far a platform point b (mm from the tool tip) moves for a pose change `position` mm and
// `chord.angle` scaled (each angle's derivative of R b has norm <= |b|).
double platform_point_change(double position, const Chord& chord, double b_norm_mm,
                             double angle_scale_mm);

// One of DerivativeBounds' reach margins, for findings and the workspace's "limited by".
struct ReachMargin {
  std::string name;      // "strut 2's reach of its rail", "the tensions' margin within ..."
  bool newtons = false;  // N (a force); else mm
  Status failure;        // what inverse() says where the margin is negative
};

class DerivativeBounds {
 public:
  virtual ~DerivativeBounds() = default;

  // The Hessian bounds of the model's own joints (its pass-through joints after them are
  // bounds/'s) over the ball of `radius_mm` about `centre` (mm, rad); none where this machine
  // has no such bound (cables that sag, stretch or tilt the effector).
  virtual std::optional<HessianBounds> own_hessian_bounds(const geometry::Vector6d& centre,
                                                          double radius_mm, double angle_scale_mm,
                                                          const Chord& chord) const = 0;
  // The distance of the farthest platform point from the tool tip (mm), for models whose
  // rotations swing platform points (the scale of angles is twice it); none: 100 mm per rad.
  virtual std::optional<double> farthest_platform_point_mm() const { return std::nullopt; }
  // Over the ball of `radius` (scaled, angles weighing `scale` mm per rad) about the pose whose
  // joints and Jacobian are given, `hessians` this model's bounds on that ball. Nothing for
  // models without legs (a rotary delta: each arm's turn per mm, for its assembly-mode bound).
  virtual LegMotion leg_motion(const JointVector& /*joints*/, const JointJacobian& /*jacobian*/,
                               const HessianBounds& /*hessians*/, double /*radius*/,
                               double /*scale*/) const {
    return {};
  }
  // The legs at a pose whose joints are `joints`; none for models without legs.
  virtual std::optional<LegEnds> legs_at(const geometry::Pose& /*pose*/,
                                         const JointVector& /*joints*/) const {
    return std::nullopt;
  }
  // The edge of the mechanism's reach over a cell of poses, beyond its joints and assembly mode
  // (a glide's struts reaching their rails, a cable robot's cables clear of their anchors and its
  // tensions holding the effector): reach_count() values, each [low, high] bounds on its margin,
  // in the margin's own unit (reach_margin()), over every pose within `scaled_radius` (angles
  // weighing `angle_scale_mm`) and `position_radius_mm` of `centre`. A margin is >= 0 where
  // inverse() does not refuse by it: low > 0 proves the cell keeps it, high < 0 that inverse()
  // refuses every pose of it. None where the joint bounds and the assembly mode say it all. The
  // workspace bounds cells with it, the certified check the ball about each piece of a move.
  virtual int reach_count() const { return 0; }
  virtual void reach_over_cell(const geometry::Vector6d& /*centre*/, double /*scaled_radius*/,
                               double /*position_radius_mm*/, double /*angle_scale_mm*/,
                               std::span<std::array<double, 2>> /*margins*/) const {}
  // What reach margin `index` is: its name in a finding, its unit and inverse()'s refusal where
  // it is negative. By default a length (mm) whose refusal is `unreachable` for joint `index`.
  virtual ReachMargin reach_margin(int index) const;
  // True where inverse() refuses no pose of the controlled coordinates beyond the joint limits (a
  // linear model): a workspace needs nothing else proven.
  virtual bool refuses_only_joint_limits() const { return false; }
};

}  // namespace pkm::kinematics
