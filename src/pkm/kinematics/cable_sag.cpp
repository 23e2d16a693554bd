// The balance of sagging, stretching cables: a Newton iteration over seven unknowns, the tilt and
// each cable's horizontal tension, vertical force at the effector and unstretched length, seeded
// with the balance of straight cables.
#include <Eigen/LU>
#include <cmath>

#include "pkm/kinematics/cable_statics.hpp"
#include "pkm/kinematics/elastic_catenary.hpp"

namespace pkm::kinematics {

namespace {

using Vector2 = Eigen::Vector2d;
using Unknowns = Eigen::Matrix<double, 7, 1>;
using Residuals = Eigen::Matrix<double, 7, 1>;

// Unknowns: tilt, then per cable H (N), V (N, upwards on the effector), L (mm).
// Residuals: per cable, where the catenary's upper end misses the point at which it would leave
// the pulley tangentially (mm, 2); the forces on the effector (N, 2); their moment about the pen
// (N mm).
Residuals balance_residuals(const CablePlotterGeometry& geometry, const Vector2& pen_mm,
                            const Vector2& load_N, const Unknowns& x) {
  const double weight = geometry.cable_weight_N_per_mm();
  const double compliance = geometry.compliance_per_N();
  Residuals residuals;
  Vector2 force_sum = load_N;
  double moment = planar_cross(planar_rotated(geometry.center_of_mass_mm, x[0]), load_N);
  for (int cable = 0; cable < 2; ++cable) {
    const double h = x[1 + 3 * cable], v = x[2 + 3 * cable], length = x[3 + 3 * cable];
    const Vector2 arm = planar_rotated(geometry.attach_mm[cable], x[0]);
    const CatenarySpan span = catenary_span(h, v, length, weight, compliance);
    const Vector2 top =
        pen_mm + arm + Vector2(kCableTowardsPulley[cable] * span.across_mm, span.rise_mm);
    const double top_vertical = v + weight * length;
    const Vector2 normal =
        Vector2(-kCableTowardsPulley[cable] * top_vertical, h) / std::hypot(h, top_vertical);
    residuals.segment<2>(3 * cable) =
        top - (geometry.anchors_mm[cable] + geometry.radius_mm(cable) * normal);
    const Vector2 force(kCableTowardsPulley[cable] * h, v);
    force_sum += force;
    moment += planar_cross(arm, force);
  }
  residuals[2] = force_sum.x();
  residuals[5] = force_sum.y();
  residuals[6] = moment;
  return residuals;
}

Vector2 turned_quarter(const Vector2& v) {
  return {-v.y(), v.x()};
}  // d(R v)/d(tilt) = R' v

// The residuals' Jacobian in the unknowns, from the catenary's derivatives.
Eigen::Matrix<double, 7, 7> balance_jacobian(const CablePlotterGeometry& geometry,
                                             const Vector2& load_N, const Unknowns& x) {
  const double weight = geometry.cable_weight_N_per_mm();
  Eigen::Matrix<double, 7, 7> jacobian = Eigen::Matrix<double, 7, 7>::Zero();
  jacobian(6, 0) =
      planar_cross(turned_quarter(planar_rotated(geometry.center_of_mass_mm, x[0])), load_N);
  for (int cable = 0; cable < 2; ++cable) {
    const double sigma = kCableTowardsPulley[cable], r = geometry.radius_mm(cable);
    const int column = 1 + 3 * cable, row = 3 * cable;
    const double h = x[column], v = x[column + 1], length = x[column + 2];
    const Vector2 arm = planar_rotated(geometry.attach_mm[cable], x[0]);
    const CatenarySpanDerivatives d =
        catenary_span_derivatives(h, v, length, weight, geometry.compliance_per_N());
    // The normal n = (-sigma Vt, H) / Tt at the top, Vt = V + w L.
    const double top_vertical = v + weight * length;
    const double tension = std::hypot(h, top_vertical), cubed = tension * tension * tension;
    const Vector2 unnormalised(-sigma * top_vertical, h);
    const Vector2 normal_by_h = Vector2(0.0, 1.0) / tension - unnormalised * h / cubed;
    const Vector2 normal_by_vt =
        Vector2(-sigma, 0.0) / tension - unnormalised * top_vertical / cubed;
    jacobian.block<2, 1>(row, 0) = turned_quarter(arm);
    jacobian.block<2, 1>(row, column) =
        Vector2(sigma * d.across_by_horizontal, d.rise_by_horizontal) - r * normal_by_h;
    jacobian.block<2, 1>(row, column + 1) =
        Vector2(sigma * d.across_by_vertical, d.rise_by_vertical) - r * normal_by_vt;
    jacobian.block<2, 1>(row, column + 2) =
        Vector2(sigma * d.across_by_length, d.rise_by_length) - r * weight * normal_by_vt;
    jacobian(2, column) = sigma;  // the forces
    jacobian(5, column + 1) = 1.0;
    const Vector2 force(sigma * h, v);  // the moment
    jacobian(6, 0) += planar_cross(turned_quarter(arm), force);
    jacobian(6, column) = -sigma * arm.y();
    jacobian(6, column + 1) = arm.x();
  }
  if (!geometry.tilts()) {
    // Cables tied at the pen: no moment, the tilt stays where it is.
    jacobian.row(6).setZero();
    jacobian.col(0).setZero();
    jacobian(6, 0) = 1.0;
  }
  return jacobian;
}

bool admissible(const Unknowns& x) {
  return x[1] > 0.0 && x[4] > 0.0 && x[3] > 0.0 && x[6] > 0.0;
}

// A tilt step of 1e-13 rad moves a cable end 150 mm off the pen by 1.5e-11 mm.
bool small_step(const Unknowns& change, const Unknowns& x) {
  bool small = std::abs(change[0]) < 1e-13;
  for (int cable = 0; cable < 2; ++cable) {
    for (int k = 1; k <= 2; ++k) {
      const int i = k + 3 * cable;
      small = small && std::abs(change[i]) < 1e-9 * std::max(1.0, std::abs(x[i]));
    }
    small = small && std::abs(change[3 + 3 * cable]) < 1e-10;
  }
  return small;
}

}  // namespace

Status solve_sagging_balance(const CablePlotterGeometry& geometry, const Eigen::Vector2d& pen_mm,
                             const Eigen::Vector2d& load_N, CableBalance& balance) {
  // Seed: the straight cables' forces at the effector, their unstretched lengths.
  Unknowns x;
  x[0] = balance.statics.tilt_rad;
  for (int cable = 0; cable < 2; ++cable) {
    const double tension = balance.statics.tension_N[cable];
    const double angle = balance.wrap_rad[cable];  // below horizontal, leaving the pulley
    x[1 + 3 * cable] = tension * std::cos(angle);
    x[2 + 3 * cable] = tension * std::sin(angle);
    x[3 + 3 * cable] = balance.span_mm[cable];
  }
  if (!admissible(x)) return Status::failure(StatusCode::singular);
  Residuals residuals = balance_residuals(geometry, pen_mm, load_N, x);
  // Newton converges quadratically: once a step is at the tolerance, one more takes the unknowns
  // to rounding level, which forward kinematics (Newton on this) needs of its joints.
  bool converged = false, polished = false;
  for (int iteration = 0; iteration < 40 && !polished; ++iteration) {
    const Eigen::Matrix<double, 7, 7> jacobian = balance_jacobian(geometry, load_N, x);
    if (!geometry.tilts()) residuals[6] = 0.0;
    Unknowns change = jacobian.partialPivLu().solve(-residuals);
    if (!change.allFinite()) return Status::failure(StatusCode::singular);
    // Halve a step that would make a tension or a length negative.
    for (int halving = 0; halving < 40 && !admissible(x + change); ++halving) change *= 0.5;
    if (!admissible(x + change)) return Status::failure(StatusCode::not_converged);
    x += change;
    residuals = balance_residuals(geometry, pen_mm, load_N, x);
    polished = converged;
    converged = converged || small_step(change, x);
  }
  if (!converged || !residuals.allFinite()) return Status::failure(StatusCode::not_converged);

  const double weight = geometry.cable_weight_N_per_mm();
  balance.statics.tilt_rad = x[0];
  for (int cable = 0; cable < 2; ++cable) {
    const double h = x[1 + 3 * cable], v = x[2 + 3 * cable], length = x[3 + 3 * cable];
    const double top_vertical = v + weight * length;
    const double end = std::hypot(h, v), top = std::hypot(h, top_vertical);
    balance.statics.tension_N[cable] = end;
    // The tension is least where the cable is level: inside the span when it dips first.
    balance.statics.lowest_N[cable] = v < 0.0 && top_vertical > 0.0 ? h : std::min(end, top);
    balance.statics.highest_N[cable] = std::max(end, top);
    balance.top_tension_N[cable] = top;
    balance.wrap_rad[cable] = std::atan2(top_vertical, h);
    balance.span_mm[cable] = length;
  }
  return Status::success();
}

}  // namespace pkm::kinematics
