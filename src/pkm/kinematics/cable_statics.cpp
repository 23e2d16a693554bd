#include "pkm/kinematics/cable_statics.hpp"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>

#include "pkm/kinematics/elastic_catenary.hpp"

namespace pkm::kinematics {

namespace {

using Vector2 = Eigen::Vector2d;

// The left cable's pulley feeds to its right, the right one's to its left: +1 and -1 turn the
// tangent to the pulley's top side.
constexpr double kWrapSide[2] = {1.0, -1.0};

// A straight cable from its pulley to the point `end_mm` it is tied to.
struct StraightCable {
  Vector2 direction;  // unit, from the pulley towards the end
  double length_mm = 0.0;
  double wrap_rad = 0.0;
};

Status straight_cable(const CablePlotterGeometry& geometry, int cable, const Vector2& end_mm,
                      StraightCable& out) {
  const Vector2 from_centre = end_mm - geometry.anchors_mm[cable];
  const double r = geometry.radius_mm(cable);
  const double distance_squared = from_centre.squaredNorm();
  if (!(distance_squared > r * r * (1.0 + 1e-12)) || distance_squared == 0.0) {
    return Status::failure(StatusCode::unreachable, cable);  // the end is on the pulley
  }
  out.length_mm = std::sqrt(distance_squared - r * r);
  // The tangent turns the centre-to-end direction by asin(r / distance) towards the top.
  const Vector2 across(from_centre.y(), -from_centre.x());
  out.direction = (out.length_mm * from_centre + kWrapSide[cable] * r * across) / distance_squared;
  out.wrap_rad = std::atan2(-out.direction.y(), -kCableTowardsPulley[cable] * out.direction.x());
  return Status::success();
}

// The weight the cables carry (N): the effector's, or a unit one where it has no mass (then only
// the tensions' signs mean anything).
Vector2 carried_load_N(const CablePlotterGeometry& geometry, const Vector2& gravity_mm_per_s2) {
  if (geometry.effector_mass_kg > 0.0) return geometry.effector_mass_kg * gravity_mm_per_s2 * 1e-3;
  const double norm = gravity_mm_per_s2.norm();
  return norm > 0.0 ? Vector2(gravity_mm_per_s2 / norm) : Vector2(0.0, -1.0);
}

// Straight cables at effector tilt `tilt_rad`: their tensions from the force balance and the
// moment about the pen the forces leave unbalanced (positive turns the effector
// counter-clockwise).
struct StraightState {
  StraightCable cables[2];
  double tension_N[2] = {0.0, 0.0};
  double moment_Nmm = 0.0;
};

Status straight_balance_at(const CablePlotterGeometry& geometry, const Vector2& pen_mm,
                           const Vector2& load_N, double tilt_rad, StraightState& state) {
  Vector2 arms[2];
  for (int cable = 0; cable < 2; ++cable) {
    arms[cable] = planar_rotated(geometry.attach_mm[cable], tilt_rad);
    const Status status =
        straight_cable(geometry, cable, pen_mm + arms[cable], state.cables[cable]);
    if (!status.ok()) return status;
  }
  // The cables pull the effector towards their pulleys (-t u) against the load:
  // t0 u0 + t1 u1 = load.
  const Vector2& u0 = state.cables[0].direction;
  const Vector2& u1 = state.cables[1].direction;
  const double determinant = planar_cross(u0, u1);
  if (std::abs(determinant) < 1e-12) return Status::failure(StatusCode::singular);
  state.tension_N[0] = planar_cross(load_N, u1) / determinant;
  state.tension_N[1] = planar_cross(u0, load_N) / determinant;
  state.moment_Nmm = planar_cross(planar_rotated(geometry.center_of_mass_mm, tilt_rad), load_N);
  for (int cable = 0; cable < 2; ++cable) {
    state.moment_Nmm -=
        state.tension_N[cable] * planar_cross(arms[cable], state.cables[cable].direction);
  }
  return Status::success();
}

// The stable tilt: the moment vanishes and turns the effector back when it swings (its slope in
// the tilt is negative). Newton from level, then a scan of the half turn about level.
Status straight_balance(const CablePlotterGeometry& geometry, const Vector2& pen_mm,
                        const Vector2& load_N, double& tilt_rad, StraightState& state) {
  tilt_rad = 0.0;
  Status status = straight_balance_at(geometry, pen_mm, load_N, 0.0, state);
  if (!status.ok() || !geometry.tilts()) return status;
  constexpr double kStep = 1e-7;
  // Once a step is below 1e-13 rad (1.5e-11 mm at 150 mm from the pen), one more reaches
  // rounding level; waiting for a step below that could take every iteration.
  const auto newton = [&](double& tilt) {
    bool small = false;
    for (int iteration = 0; iteration < 60; ++iteration) {
      StraightState shifted;
      if (!straight_balance_at(geometry, pen_mm, load_N, tilt, state).ok()) return false;
      if (!straight_balance_at(geometry, pen_mm, load_N, tilt + kStep, shifted).ok()) return false;
      const double slope = (shifted.moment_Nmm - state.moment_Nmm) / kStep;
      if (!(slope < 0.0)) return false;
      const double change = -state.moment_Nmm / slope;
      tilt += std::clamp(change, -0.2, 0.2);
      if (small) break;
      small = std::abs(change) < 1e-13;
      if (!(std::abs(tilt) < 1.5)) return false;
    }
    return straight_balance_at(geometry, pen_mm, load_N, tilt, state).ok();
  };
  double tilt = 0.0;
  if (!newton(tilt)) {
    // Start again from the nearest change of sign (+ to -) of the moment.
    double best = 10.0, previous_moment = 0.0;
    constexpr int kScan = 64;
    for (int k = 0; k <= kScan; ++k) {
      const double at = -1.5 + 3.0 * k / kScan;
      if (!straight_balance_at(geometry, pen_mm, load_N, at, state).ok()) continue;
      if (k > 0 && previous_moment > 0.0 && state.moment_Nmm <= 0.0 &&
          std::abs(at) < std::abs(best))
        best = at;
      previous_moment = state.moment_Nmm;
    }
    tilt = best;
    if (best > 5.0 || !newton(tilt)) return Status::failure(StatusCode::not_converged);
  }
  tilt_rad = tilt;
  return straight_balance_at(geometry, pen_mm, load_N, tilt, state);
}

// The straight balance as a balance of straight, possibly stretching cables.
CableBalance from_straight(const CablePlotterGeometry& geometry, double tilt_rad,
                           const StraightState& state, double tension_scale) {
  CableBalance balance;
  balance.statics.tilt_rad = tilt_rad;
  const double compliance = geometry.compliance_per_N();
  for (int cable = 0; cable < 2; ++cable) {
    const double tension = state.tension_N[cable] * tension_scale;
    balance.statics.tension_N[cable] = tension;
    balance.statics.lowest_N[cable] = tension;
    balance.statics.highest_N[cable] = tension;
    balance.top_tension_N[cable] = tension;
    balance.wrap_rad[cable] = state.cables[cable].wrap_rad;
    balance.span_mm[cable] = state.cables[cable].length_mm / (1.0 + compliance * tension);
  }
  return balance;
}

}  // namespace

Status solve_cable_balance(const CablePlotterGeometry& geometry, const Eigen::Vector2d& pen_mm,
                           const Eigen::Vector2d& effective_gravity_mm_per_s2,
                           CableBalance& balance) {
  const Vector2 load = carried_load_N(geometry, effective_gravity_mm_per_s2);
  StraightState state;
  double tilt = 0.0;
  const Status status = straight_balance(geometry, pen_mm, load, tilt, state);
  if (!status.ok()) return status;
  const bool massless = !(geometry.effector_mass_kg > 0.0);
  balance = from_straight(geometry, tilt, state, massless ? 0.0 : 1.0);
  for (int cable = 0; cable < 2; ++cable) balance.pulls[cable] = state.tension_N[cable] > 0.0;
  if (massless || geometry.cable_density_kg_per_m == 0.0) return Status::success();
  if (!balance.pulls[0] || !balance.pulls[1]) return Status::success();
  return solve_sagging_balance(geometry, pen_mm, load, balance);
}

double cable_past_top(const CablePlotterGeometry& geometry, const CableBalance& balance,
                      int cable) {
  const double compliance = geometry.compliance_per_N();
  const double arc = geometry.radius_mm(cable) * balance.wrap_rad[cable] /
                     (1.0 + compliance * std::max(0.0, balance.top_tension_N[cable]));
  return arc + balance.span_mm[cable];
}

double cable_joint(const CablePlotterGeometry& geometry, double cable_past_top_mm, int cable) {
  const double k = geometry.spool_buildup_mm_per_m * 1e-3;  // mm of radius per mm of cable
  if (k == 0.0) return cable_past_top_mm + geometry.cable_offsets_mm[cable];
  // The drum's radius falls by k per mm paid out: d(turn) = d(cable) / (r0 - k cable), so the
  // turn is -(1 / k) ln(1 - k cable / r0); times r0, in mm.
  const double r0 = geometry.pulley_radius_mm;
  const double left = 1.0 - k * cable_past_top_mm / r0;
  if (!(left > 0.0)) return std::numeric_limits<double>::quiet_NaN();
  return -r0 / k * std::log1p(-k * cable_past_top_mm / r0) + geometry.cable_offsets_mm[cable];
}

}  // namespace pkm::kinematics
