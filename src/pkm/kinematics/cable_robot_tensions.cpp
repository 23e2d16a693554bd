// The cable robot's tension distribution: the load its cables must balance at a pose (the
// effector's weight, and its inertia while it accelerates), the limits and preferred tension
// from the machine file, and inverse kinematics' refusal of a pose no tensions within the limits
// hold. The distribution itself is tension_distribution.cpp's; the conventions are in
// docs/cable-machines.md ("N cables: the tension distribution").
#include <Eigen/Cholesky>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "pkm/kinematics/cable_robot.hpp"
#include "pkm/kinematics/cable_statics.hpp"

namespace pkm::kinematics {

namespace {

// A pose found by bisection along a move sits on the border, past a limit by less than the
// tensions' printed digits ("would need -0.000 N"): say by how much.
std::string border_note(const TensionDistribution& distribution) {
  if (distribution.outcome != TensionOutcome::out_of_limits ||
      !(distribution.largest_violation_N < 0.0005)) {
    return {};
  }
  return " (past the limits by " + formatted_number("%.2g", distribution.largest_violation_N) +
         " N: on the border of the poses the cables hold)";
}

}  // namespace

void validate_cable_robot_load(const CableRobotGeometry& g) {
  const Eigen::Vector3d& down = g.gravity_direction;
  if (!down.allFinite() || !(down.norm() > 0.0)) {
    throw std::invalid_argument("gravity: must be a direction [gx, gy, gz], finite and not zero");
  }
  if (g.planar && down.z() > 0.0) {
    throw std::invalid_argument(
        "gravity: a planar robot's sheet (below its plane, z < 0) can only push the effector: "
        "gravity's z must be 0 or less");
  }
  if (g.planar && g.effector_mass_kg > 0.0 && !g.gravity_given) {
    throw std::invalid_argument(
        "effector_mass: a planar robot's weight needs `gravity = [gx, gy, gz]`, which way is "
        "down on its sheet: [0, -1, 0] for a vertical sheet with y up, [0, 0, -1] for a level "
        "one, [0, -sin a, -cos a] for one tilted a from level with y up the slope");
  }
  if (!g.preferred_tension_N) return;
  const double preferred = *g.preferred_tension_N;
  const double low = g.tension_limited ? g.tension_min_N : 0.0;
  const double high = g.tension_limited ? g.tension_max_N : std::numeric_limits<double>::infinity();
  if (!std::isfinite(preferred) || preferred < low || preferred > high) {
    throw std::invalid_argument(
        "preferred_tension: must be within tension_limits (N), 0 or more without them, got " +
        formatted_number("%g", preferred));
  }
}

Eigen::Vector3d CableRobotKinematics::load_N(const Eigen::Vector3d& acceleration_mm_per_s2) const {
  const Eigen::Vector3d gravity_mm_per_s2 =
      kStandardGravity_mm_per_s2 * geometry_.gravity_direction.normalized();
  // kg mm/s^2 is 1e-3 N.
  return geometry_.effector_mass_kg * 1e-3 * (gravity_mm_per_s2 - acceleration_mm_per_s2);
}

WrenchVector CableRobotKinematics::wrench_N(const Eigen::Vector3d& acceleration_mm_per_s2) const {
  return load_N(acceleration_mm_per_s2).head(coordinates());
}

TensionTargets CableRobotKinematics::tension_targets() const {
  const int n = cable_count();
  if (!geometry_.tension_limited) {
    return TensionTargets::uniform(n, 0.0, std::numeric_limits<double>::infinity(),
                                   geometry_.preferred_tension_N.value_or(0.0));
  }
  if (geometry_.preferred_tension_N) {
    return TensionTargets::uniform(n, geometry_.tension_min_N, geometry_.tension_max_N,
                                   *geometry_.preferred_tension_N);
  }
  return TensionTargets::middle(n, geometry_.tension_min_N, geometry_.tension_max_N);
}

std::optional<TensionDistribution> CableRobotKinematics::tensions(
    const geometry::Pose& pose, const Eigen::Vector3d& acceleration_mm_per_s2) const {
  const StructureMatrix structure = structure_matrix(pose);
  if (structure.size() == 0 || !acceleration_mm_per_s2.allFinite()) return std::nullopt;
  return distribute_tensions(structure, wrench_N(acceleration_mm_per_s2), tension_targets());
}

bool CableRobotKinematics::force_polytope(const geometry::Pose& pose,
                                          CableForcePolytope& polytope) const {
  polytope.count = 0;
  const StructureMatrix structure = structure_matrix(pose);
  if (structure.size() == 0) return false;
  return cable_force_polytope(structure, tension_targets(), polytope);
}

bool CableRobotKinematics::projection_held(const geometry::Pose& pose) const {
  // Pott's closed form: p projected onto the balance, t = p - A^T (A A^T)^-1 (A p + w). Where it
  // keeps every limit it is the distribution's answer (the nearest of all balancing tensions), so
  // the pose is held; else the full method decides. On the stack: inverse() allocates nothing.
  CableVector length;
  CableJacobian d_length;
  if (!lengths(tool_point(pose), length, &d_length).ok()) return false;
  const int k = coordinates();
  using Small = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, 3, 3>;
  using SmallVector = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, 3, 1>;
  const CableJacobian a_transposed = -d_length.leftCols(k);  // n x k: the unit vectors as rows
  const double preferred = geometry_.preferred_tension_N.value_or(
      0.5 * (geometry_.tension_min_N + geometry_.tension_max_N));
  const CableVector p = CableVector::Constant(cable_count(), preferred);
  const SmallVector w = load_N(Eigen::Vector3d::Zero()).head(k);
  const Small normal = a_transposed.transpose() * a_transposed;
  const SmallVector excess = a_transposed.transpose() * p + w;
  const Eigen::LDLT<Small> factor(normal);
  if (factor.info() != Eigen::Success) return false;
  const CableVector t = p - a_transposed * factor.solve(excess);
  const double scale = 1.0 + w.lpNorm<Eigen::Infinity>() + geometry_.tension_max_N;
  if (!t.allFinite() || (a_transposed.transpose() * t + w).norm() > 1e-9 * scale) return false;
  return (t.array() >= geometry_.tension_min_N).all() &&
         (t.array() <= geometry_.tension_max_N).all();
}

Status CableRobotKinematics::check_tensions(const geometry::Pose& pose) const {
  if (!geometry_.tension_limited || !geometry_.refuses_unheld_poses || projection_held(pose)) {
    return Status::success();
  }
  const std::optional<TensionDistribution> at_rest = tensions(pose);
  if (!at_rest) return Status::failure(StatusCode::singular);
  if (at_rest->held()) return Status::success();
  return Status::failure(StatusCode::tension,
                         at_rest->violations.empty() ? -1 : at_rest->violations.front().cable);
}

std::unique_ptr<Kinematics> CableRobotKinematics::geometry_only() const {
  auto copy = std::make_unique<CableRobotKinematics>(*this);
  copy->geometry_.refuses_unheld_poses = false;
  return copy;
}

std::string CableRobotKinematics::explain_tensions(const geometry::Pose& pose) const {
  const std::optional<TensionDistribution> at_rest = tensions(pose);
  if (!at_rest || at_rest->held()) return {};
  return "no tensions within tension_limits [" + formatted_number("%.3f", geometry_.tension_min_N) +
         ", " + formatted_number("%.3f", geometry_.tension_max_N) + "] N hold the " +
         formatted_number("%.3f", geometry_.effector_mass_kg) +
         " kg effector here: " + describe_refusal(*at_rest) + border_note(*at_rest);
}

}  // namespace pkm::kinematics
