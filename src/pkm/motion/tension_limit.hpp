// Tension-limited motion of a hanging cable machine (a cable_plotter whose effector has a mass):
// how hard the effector may accelerate along a move, how fast it may take a curve and how fast it
// may pass a junction before a cable's tension leaves [tension_min_N, tension_max_N]. Quasi-static:
// the tensions are those of the effector hanging still under gravity minus its acceleration,
// m (g - a); its swing is not modelled (docs/motion.md, "Tension-limited acceleration").
#pragma once

#include <Eigen/Core>
#include <functional>
#include <optional>
#include <string>

#include "pkm/kinematics/hanging_cables.hpp"
#include "pkm/motion/segment.hpp"

namespace pkm::motion {

// Share of each cable's tension headroom (its distance to the limit at rest) the moves' own
// accelerations may use; the rest is left for the change of velocity at junctions passed without
// stopping, which happens within one servo period (as kMoveAccelerationShare for the joints).
inline constexpr double kTensionMoveShare = 0.8;

// The cable whose tension is nearest to its limit, or furthest beyond it.
struct TensionExcess {
  bool outside = false;    // a tension leaves its limits, or the effector has no balance
  int cable = -1;          // 0 left, 1 right; -1 without a balance (singular)
  bool slack = false;      // below tension_min_N (else above tension_max_N)
  double tension_N = 0.0;  // the cable's lowest (slack) or highest tension
  // How far that tension is from its limit (N): negative beyond it, -inf without a balance.
  double margin_N = 0.0;
};

// What the tensions allow along one move.
struct TensionBound {
  double speed_mm_per_s = 0.0;
  double acceleration_mm_per_s2 = 0.0;
  bool speed_limited = false;         // the centripetal acceleration on a curve lowered the speed
  bool acceleration_limited = false;  // the acceleration along the path was lowered
  TensionExcess excess;               // the cable that set the last limit lowered
};

class TensionLimit {
 public:
  // The limit of a machine hanging from cables (a cable_plotter) whose effector has a mass (its
  // tensions are "both cables pull", [0, inf), without tension_limits); none for any other.
  static std::optional<TensionLimit> of(const kinematics::Kinematics& kinematics,
                                        double share = kTensionMoveShare);

  // The highest speed (mm/s) and acceleration along the path (mm/s^2), at most `speed` and
  // `acceleration`, that keep the tensions within the share of their headroom at `points` + 1
  // equally spaced points of the move (`length_mm` long, as the planner measures it): there the
  // effector's acceleration is +-A along the tangent plus v^2 / r across on a curve. The
  // centripetal part takes at most half of the headroom (v^2 / r, as the joints' limit does).
  // The tensions at rest are taken to be within their limits (the inverse kinematics checks).
  TensionBound along(const Segment& segment, double length_mm, int points, double speed,
                     double acceleration) const;

  // The highest speed (mm/s, at most `speed`) at which the direction of travel may change from
  // the unit vector `out` to `in` (x y z; only x y load the cables) at `pose`, between moves of
  // which the shorter is `chord_mm` long: the change of velocity v |in - out| happens within one
  // period of `period_s`, or, where junctions follow closer than a period (a curve in short
  // chords), once per chord, v^2 |in - out| / chord. That acceleration takes at most the rest of
  // the headroom (1 - share).
  double junction_speed(const geometry::Vector6d& pose, const Eigen::Vector3d& out,
                        const Eigen::Vector3d& in, double chord_mm, double period_s,
                        double speed) const;

  // The hardest the effector may accelerate along the unit vector `direction` (x y) at `pose`,
  // up to `cap` (mm/s^2), with every tension within its limits (the whole headroom); `beyond`
  // names the cable that passes its limit just beyond it.
  double allowed_along(const geometry::Vector6d& pose, const Eigen::Vector2d& direction, double cap,
                       TensionExcess& beyond) const {
    return headroom(pose, Eigen::Vector2d::Zero(), direction, cap, 1.0, beyond);
  }

  // The cable whose tension is nearest to its limits (or furthest beyond) at `pose` under the
  // effector's acceleration (mm/s^2, x y); a pose without a balance (singular) is outside with
  // cable -1.
  TensionExcess excess(const geometry::Vector6d& pose,
                       const Eigen::Vector2d& acceleration_mm_per_s2) const;
  bool within(const geometry::Vector6d& pose, const Eigen::Vector2d& acceleration_mm_per_s2) const {
    return !excess(pose, acceleration_mm_per_s2).outside;
  }

  // How far the tensions at rest go beyond their limits along a move given as its poses for u in
  // [0, 1] (sampled 1000 times), for a refusal: "; along the move the left cable's tension
  // reaches 412.3 N", empty when they stay within.
  std::string beyond_limits_at_rest(const std::function<geometry::Vector6d(double)>& pose_at) const;

  const kinematics::HangingCables& kinematics() const { return *kinematics_; }
  double share() const { return share_; }

 private:
  TensionLimit(const kinematics::HangingCables& kinematics, double share)
      : kinematics_(&kinematics), share_(share) {}
  // The largest c in [0, cap] with the tensions within at `base` + c `direction`, scaled by
  // `scale` (1 / share of the headroom), to 1e-10 N of a limit; `excess` names what passes
  // just beyond it. 0 where they are not within at `base`.
  double headroom(const geometry::Vector6d& pose, const Eigen::Vector2d& base,
                  const Eigen::Vector2d& direction, double cap, double scale,
                  TensionExcess& excess) const;

  const kinematics::HangingCables* kinematics_;
  double share_;
};

// "the left cable would go slack (4.1 N, below tension_limits' minimum 5 N)" for a user.
std::string describe_excess(const kinematics::HangingCables& kinematics,
                            const TensionExcess& excess);

}  // namespace pkm::motion
