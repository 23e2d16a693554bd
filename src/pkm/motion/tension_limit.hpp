// Tension-limited motion of a cable machine whose effector has a mass: a cable_plotter (two
// cables, hanging_cables.hpp) or a cable_robot (n cables, cable_tensions.hpp). How hard the
// effector may accelerate along a move, how fast it may take a curve and how fast it may pass a
// junction before a cable's tension leaves its limits. Quasi-static: the cables hold the effector
// under gravity minus its acceleration, m (g - a); its swing is not modelled. For n cables,
// "within the limits" is exact: the load lies in the polytope of forces the cables can exert
// (cable_force_polytope.hpp). One rule for both: kTensionMoveShare (docs/motion.md,
// "Tension-limited acceleration").
#pragma once

#include <Eigen/Core>
#include <functional>
#include <optional>
#include <string>

#include "pkm/kinematics/cable_tensions.hpp"
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
  int cable = -1;          // 0 left, 1 right (n cables: its index); -1 without a balance
  bool slack = false;      // below tension_min_N (else above tension_max_N)
  double tension_N = 0.0;  // the cable's lowest (slack) or highest tension; n cables: its limit
  // How far that tension is from its limit (N): negative beyond it, -inf without a balance. For
  // n cables, how far the load along the facet's normal is within the facet.
  double margin_N = 0.0;
  // n cables: the facet of the force polytope nearest (or furthest beyond), its side (high:
  // past high_N), the force along its normal, and the cables it holds at their limits (`cable`
  // is the first of them, slack where one is at its min).
  int facet = -1;
  bool high = false;
  double force_N = 0.0;
  kinematics::ForceFacet bounds{Eigen::Vector3d::Zero(), 0.0, 0.0, -1, -1, 0u, 0u};
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
  // The limit of a machine hanging from cables (a cable_plotter) or held by n of them (a
  // cable_robot) whose effector has a mass (without tension_limits its cables' are [0, inf): they
  // pull); none for any other.
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
    return headroom(pose, Eigen::Vector3d::Zero(),
                    Eigen::Vector3d(direction.x(), direction.y(), 0.0), cap, 1.0, beyond);
  }

  // The cable whose tension is nearest to its limits (or furthest beyond) at `pose` under the
  // effector's acceleration (mm/s^2, x y); a pose without a balance (singular) is outside with
  // cable -1.
  TensionExcess excess(const geometry::Vector6d& pose,
                       const Eigen::Vector2d& acceleration_mm_per_s2) const {
    return excess(pose,
                  Eigen::Vector3d(acceleration_mm_per_s2.x(), acceleration_mm_per_s2.y(), 0.0));
  }
  // The same for an acceleration in x y z (a plotter's cables feel x y alone).
  TensionExcess excess(const geometry::Vector6d& pose,
                       const Eigen::Vector3d& acceleration_mm_per_s2) const;
  bool within(const geometry::Vector6d& pose, const Eigen::Vector2d& acceleration_mm_per_s2) const {
    return !excess(pose, acceleration_mm_per_s2).outside;
  }
  // n cables: what `excess` says where the load sits on `facet`'s `high` (or low) side at `pose`
  // (the grid's rows are the facets: this names the cables of the one that bound).
  TensionExcess on_facet(const geometry::Vector6d& pose, int facet, bool high) const;

  // How far the tensions at rest go beyond their limits along a move given as its poses for u in
  // [0, 1] (sampled 1000 times), for a refusal: "; along the move the left cable's tension
  // reaches 412.3 N", empty when they stay within.
  std::string beyond_limits_at_rest(const std::function<geometry::Vector6d(double)>& pose_at) const;

  // "the left cable would go slack ..." (tension_limit.cpp's describe_excess), or for n cables
  // the facet's cables at their limits and the force the effector would need along its normal.
  std::string describe(const TensionExcess& excess) const;

  // The plotter's cables (only where robot() is none).
  const kinematics::HangingCables& kinematics() const { return *kinematics_; }
  // The n cables, where the machine is a cable robot (else none).
  const kinematics::CableTensions* robot() const { return robot_; }
  // The grid's rows per point (path_grid.hpp): the plotter's 4 (each cable's lowest and highest
  // tension); n cables, one two-sided row per facet pair of the force polytope (at most
  // n (n - 1) / 2 in space, n in the plane).
  int rows_per_point() const;
  double share() const { return share_; }

 private:
  TensionLimit(const kinematics::HangingCables& kinematics, double share)
      : kinematics_(&kinematics), share_(share) {}
  TensionLimit(const kinematics::CableTensions& robot, double share)
      : robot_(&robot), share_(share) {}
  TensionExcess plotter_excess(const geometry::Vector6d& pose,
                               const Eigen::Vector2d& acceleration_mm_per_s2) const;
  TensionExcess robot_excess(const geometry::Vector6d& pose,
                             const Eigen::Vector3d& acceleration_mm_per_s2) const;
  std::string robot_beyond_limits_at_rest(
      const std::function<geometry::Vector6d(double)>& pose_at) const;
  // The largest c in [0, cap] with the tensions within at `base` + c `direction`, scaled by
  // `scale` (1 / share of the headroom), to 1e-10 N of a limit; `excess` names what passes
  // just beyond it. 0 where they are not within at `base`.
  double headroom(const geometry::Vector6d& pose, const Eigen::Vector3d& base,
                  const Eigen::Vector3d& direction, double cap, double scale,
                  TensionExcess& excess) const;
  // The part of an acceleration the cables feel: x y for the plotter, all of it for n cables.
  Eigen::Vector3d felt(Eigen::Vector3d acceleration) const {
    if (robot_ == nullptr) acceleration.z() = 0.0;
    return acceleration;
  }

  const kinematics::HangingCables* kinematics_ = nullptr;
  const kinematics::CableTensions* robot_ = nullptr;
  double share_;
};

// "the left cable would go slack (4.1 N, below tension_limits' minimum 5 N)" for a user.
std::string describe_excess(const kinematics::HangingCables& kinematics,
                            const TensionExcess& excess);

}  // namespace pkm::motion
