// The statics of a hanging two-cable effector (Hektor's gondola, a Maslow sled): where each
// cable leaves its pulley, how far it sags and stretches, how the effector tilts under its own
// weight and how hard each cable pulls, for a pen position and the effector's acceleration.
// Vertical plane, x right, y up, gravity along -y; mm, kg, N, rad. The equations are derived in
// docs/kinematics.md ("Cable machines as built").
#pragma once

#include <Eigen/Core>
#include <array>
#include <cmath>
#include <limits>

#include "pkm/kinematics/kinematics.hpp"

namespace pkm::kinematics {

inline constexpr double kStandardGravity_mm_per_s2 = 9806.65;

// The way each cable runs horizontally from the effector to its pulley: left -1, right +1.
inline constexpr double kCableTowardsPulley[2] = {-1.0, 1.0};

// a x b of two plane vectors (positive: b is counter-clockwise of a).
inline double planar_cross(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return a.x() * b.y() - a.y() * b.x();
}

inline Eigen::Vector2d planar_rotated(const Eigen::Vector2d& v, double angle_rad) {
  const double c = std::cos(angle_rad), s = std::sin(angle_rad);
  return {c * v.x() - s * v.y(), s * v.x() + c * v.y()};
}

// Cables closer than this (sine of the angle between them) to parallel are at a singularity
// (the pen on the line through the anchors).
inline constexpr double kMinCableAngleSine = 1e-9;

struct CablePlotterGeometry {
  // Pulley centres: left (0) and right (1). The left cable leaves its pulley on the right,
  // the right one on the left, both running over the top.
  std::array<Eigen::Vector2d, 2> anchors_mm{Eigen::Vector2d::Zero(), Eigen::Vector2d::Zero()};
  double pulley_radius_mm = 0.0;
  // Added to each cable's length to give the joint reading: where the cable's zero (the
  // limit-switch position of the homing procedure) really is.
  std::array<double, 2> cable_offsets_mm{0.0, 0.0};
  // Where each cable is tied, relative to the pen tip, in the effector's frame (level at tilt 0).
  std::array<Eigen::Vector2d, 2> attach_mm{Eigen::Vector2d::Zero(), Eigen::Vector2d::Zero()};
  double effector_mass_kg = 0.0;
  Eigen::Vector2d center_of_mass_mm = Eigen::Vector2d::Zero();  // relative to the pen tip
  bool tension_limited = false;                                 // tension_limits given
  double tension_min_N = 0.0;
  double tension_max_N = std::numeric_limits<double>::infinity();
  double cable_density_kg_per_m = 0.0;
  double cable_stretch_mm_per_m_per_N = 0.0;  // 1000 / EA; 0: the cable does not stretch
  // Each metre of cable wound on a drum adds this much to its radius (a cord on a spool);
  // pulley_radius is then the drum's radius with its cable wound in to the joint's zero.
  double spool_buildup_mm_per_m = 0.0;
  // Per-call data, not description: how much each drum's radius differs from pulley_radius for
  // the balance being solved (set by the spool build-up's iteration; zero otherwise).
  std::array<double, 2> radius_change_mm{0.0, 0.0};

  // Anchors at (0, 0) and (d, 0), the paper's Hektor.
  static CablePlotterGeometry level(double anchor_distance_mm, double left_offset_mm = 0.0,
                                    double right_offset_mm = 0.0) {
    CablePlotterGeometry geometry;
    geometry.anchors_mm[1] = Eigen::Vector2d(anchor_distance_mm, 0.0);
    geometry.cable_offsets_mm = {left_offset_mm, right_offset_mm};
    return geometry;
  }
  // Two massless, straight, unstretchable cables to the pen: Hektor as the paper models it.
  double radius_mm(int cable) const { return pulley_radius_mm + radius_change_mm[cable]; }
  bool ideal() const {
    return pulley_radius_mm == 0.0 && attach_mm[0].isZero() && attach_mm[1].isZero() &&
           cable_density_kg_per_m == 0.0 && cable_stretch_mm_per_m_per_N == 0.0 && !tension_limited;
  }
  // Joints from the geometry alone, not from the effector's balance: cables tied at the pen that
  // neither sag, stretch nor build up on their drums (pulleys allowed).
  bool rigid() const {
    return attach_mm[0].isZero() && attach_mm[1].isZero() && cable_density_kg_per_m == 0.0 &&
           cable_stretch_mm_per_m_per_N == 0.0 && spool_buildup_mm_per_m == 0.0;
  }
  // Whether the effector can turn: tied at points off the pen, or weighted off it.
  bool tilts() const {
    return !attach_mm[0].isZero() || !attach_mm[1].isZero() ||
           (!center_of_mass_mm.isZero() && effector_mass_kg > 0.0);
  }
  double compliance_per_N() const { return cable_stretch_mm_per_m_per_N * 1e-3; }
  double cable_weight_N_per_mm() const {
    return cable_density_kg_per_m * kStandardGravity_mm_per_s2 * 1e-6;
  }
};

// The contract with the planner: the quasi-static balance at one pen position.
struct CableStatics {
  double tilt_rad = 0.0;              // effector rotation, counter-clockwise
  std::array<double, 2> tension_N{};  // where each cable meets the effector
  std::array<double, 2> lowest_N{};   // the least tension along each cable
  std::array<double, 2> highest_N{};  // the greatest (at its pulley, for a sagging cable)
};

// Everything the balance found, for the joints.
struct CableBalance {
  CableStatics statics;
  std::array<double, 2> top_tension_N{};  // where the cable leaves its pulley
  std::array<double, 2> wrap_rad{};       // arc on the pulley from its top point
  std::array<double, 2> span_mm{};        // unstretched length from the pulley to the effector
  std::array<bool, 2> pulls{true, true};  // false: the cable would have to push
};

// The balance at pen position `pen_mm` under effective gravity g - a (mm/s^2) acting on the
// effector; the cables' own weight acts along -y. Without a mass the tensions are zero and only
// `pulls` means anything ("both cables pull"). A cable that would push ends the solution there:
// its sag is not solved.
// Status: unreachable (an end inside its pulley), singular (cables in line), not_converged.
Status solve_cable_balance(const CablePlotterGeometry& geometry, const Eigen::Vector2d& pen_mm,
                           const Eigen::Vector2d& effective_gravity_mm_per_s2,
                           CableBalance& balance);

// Refines `balance`, solved for straight cables, into the balance of sagging, stretching ones
// (a Newton iteration over the tilt and each cable's end forces and unstretched length).
Status solve_sagging_balance(const CablePlotterGeometry& geometry, const Eigen::Vector2d& pen_mm,
                             const Eigen::Vector2d& load_N, CableBalance& balance);

// The unstretched cable of `cable` (0 left, 1 right) past its pulley's top point: wrap and span.
double cable_past_top(const CablePlotterGeometry& geometry, const CableBalance& balance, int cable);

// The joint reading for that much cable past the top: the cable plus its offset, or with a spool
// build-up the drum's turn from the joint's zero times pulley_radius, plus the offset. NaN where
// the drum would run out of radius.
double cable_joint(const CablePlotterGeometry& geometry, double cable_past_top_mm, int cable);

}  // namespace pkm::kinematics
