#include "pkm/linuxcnc/joint_rate_bound.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "pkm/motion/feed_rule.hpp"

namespace pkm::linuxcnc {

namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

// Progressive filling: every free axis j grows as ratio[j] t (t up to 1 when ratio is what the
// axis could have alone); the row (a joint over a cell) or
// axis cap that runs out first fixes the free axes it concerns; repeat until every axis is fixed.
struct Filling {
  geometry::Vector6d value = geometry::Vector6d::Zero();
  std::vector<int> limiting = std::vector<int>(geometry::kPoseSize, -1);  // the joint, -1: a cap
};

Filling fill(const bounds::JointRateBound& bound, const std::vector<double>& budget,
             const geometry::Vector6d& ratio, const geometry::Vector6d& cap, geometry::Dof moved) {
  const Eigen::MatrixXd& slope = bound.cell_slope;
  Filling result;
  std::vector<bool> free(geometry::kPoseSize, false);
  for (int axis = 0; axis < geometry::kPoseSize; ++axis)
    free[static_cast<std::size_t>(axis)] = moved.controls(axis);
  const auto any_free = [&] { return std::find(free.begin(), free.end(), true) != free.end(); };
  while (any_free()) {
    double best = kInfinity;
    Eigen::Index limiting_row = -1;
    int capped = -1;
    for (Eigen::Index r = 0; r < slope.rows(); ++r) {
      double denominator = 0.0, used = 0.0;
      for (int axis = 0; axis < geometry::kPoseSize; ++axis) {
        (free[static_cast<std::size_t>(axis)] ? denominator : used) +=
            slope(r, axis) *
            (free[static_cast<std::size_t>(axis)] ? ratio[axis] : result.value[axis]);
      }
      if (!(denominator > 0.0)) continue;
      const double t = std::max(0.0, budget[static_cast<std::size_t>(r)] - used) / denominator;
      if (t < best) best = t, limiting_row = r, capped = -1;
    }
    for (int axis = 0; axis < geometry::kPoseSize; ++axis) {
      if (free[static_cast<std::size_t>(axis)] && cap[axis] / ratio[axis] < best) {
        best = cap[axis] / ratio[axis], capped = axis, limiting_row = -1;
      }
    }
    for (int axis = 0; axis < geometry::kPoseSize; ++axis) {
      std::size_t k = static_cast<std::size_t>(axis);
      if (!free[k]) continue;
      const bool fixes =
          capped >= 0 ? axis == capped : limiting_row < 0 || slope(limiting_row, axis) > 0.0;
      if (!fixes) continue;
      result.value[axis] = std::isfinite(best) ? ratio[axis] * best : 0.0;
      result.limiting[k] =
          limiting_row < 0 ? -1 : bound.cell_joint[static_cast<std::size_t>(limiting_row)];
      free[k] = false;
    }
  }
  return result;
}

// Per axis: the most it could have alone (every other axis still), from the rows and its cap;
// the filling's ratios, so that every axis gets the same share of its own reach and a small
// coupling (a matrix mill's 0.0002) does not tie a fast axis to a slow joint.
geometry::Vector6d alone(const bounds::JointRateBound& bound, const std::vector<double>& budget,
                         const geometry::Vector6d& cap, geometry::Dof moved) {
  geometry::Vector6d result = geometry::Vector6d::Zero();
  for (const int axis : moved.axes()) {
    double most = cap[axis];
    for (Eigen::Index r = 0; r < bound.cell_slope.rows(); ++r) {
      const double slope = bound.cell_slope(r, axis);
      if (slope > 0.0)
        most = std::min(most, std::max(0.0, budget[static_cast<std::size_t>(r)]) / slope);
    }
    result[axis] = std::isfinite(most) ? most : 0.0;
  }
  return result;
}

}  // namespace

AxisRateLimits axis_rate_limits(const machine::Machine& machine,
                                const bounds::JointRateBound& bound, geometry::Dof moved) {
  const std::vector<int> controlled = machine.kinematics().dof().axes();
  const std::size_t rows = bound.cell_joint.size();
  const auto joint_of = [&](std::size_t r) {
    return machine.joints()[static_cast<std::size_t>(bound.cell_joint[r])];
  };
  geometry::Vector6d velocity_cap, acceleration_cap;
  for (int axis = 0; axis < geometry::kPoseSize; ++axis) {
    velocity_cap[axis] = axis < 3 ? machine.cartesian().max_feed_mm_per_s() : kInfinity;
    acceleration_cap[axis] = axis < 3 ? machine.cartesian().max_acceleration_mm_per_s2 : kInfinity;
  }
  std::vector<double> budget(rows);
  for (std::size_t r = 0; r < rows; ++r) budget[r] = joint_of(r).max_velocity;
  Filling velocity =
      fill(bound, budget, alone(bound, budget, velocity_cap, moved), velocity_cap, moved);
  // |v|^2 in the scaled coordinates the Hessian bound speaks, over the controlled axes.
  const auto scaled_square = [&](const geometry::Vector6d& v) {
    double sum = 0.0;
    for (const int axis : controlled) {
      sum += std::pow(v[axis] * (axis < 3 ? 1.0 : bound.angle_scale_mm), 2);
    }
    return sum;
  };
  double factor = 1.0;
  int curving = -1;
  for (std::size_t r = 0; r < rows; ++r) {
    const double term = bound.cell_curvature[r] * scaled_square(velocity.value);
    const double half = 0.5 * joint_of(r).max_acceleration;
    if (term > half && std::sqrt(half / term) < factor) {
      factor = std::sqrt(half / term);
      curving = bound.cell_joint[r];
    }
  }
  if (curving >= 0) {
    for (const int axis : controlled) {
      velocity.value[axis] *= factor;
      velocity.limiting[static_cast<std::size_t>(axis)] = curving;
    }
  }
  for (std::size_t r = 0; r < rows; ++r) {
    budget[r] =
        joint_of(r).max_acceleration - bound.cell_curvature[r] * scaled_square(velocity.value);
  }
  const Filling acceleration =
      fill(bound, budget, alone(bound, budget, acceleration_cap, moved), acceleration_cap, moved);
  // The split holds the joints at the accelerations the planner reaches: LinuxCNC gets less.
  AxisRateLimits limits;
  limits.velocity = velocity.value;
  limits.acceleration = acceleration.value / kPlannerAccelerationOvershoot;
  limits.velocity_limiting = velocity.limiting;
  limits.acceleration_limiting = acceleration.limiting;
  limits.linear_velocity =
      std::min(machine.cartesian().max_feed_mm_per_s(), limits.velocity.head<3>().norm());
  limits.linear_acceleration = std::min(machine.cartesian().max_acceleration_mm_per_s2,
                                        limits.acceleration.head<3>().norm());
  return limits;
}

double plan_speed_along(const machine::Machine& machine, const geometry::Pose& pose, int axis) {
  kinematics::JointJacobian jacobian;
  kinematics::JointVector behind, here, ahead;
  const kinematics::Kinematics& model = machine.kinematics();
  if (!model.jacobian(pose, jacobian).ok() || !model.inverse(pose, here).ok()) return 0.0;
  // The joints' rates along the move, and their curvature by central differences over the
  // planner's own step.
  constexpr double kStepMm = motion::kJointSampleStepMm;
  geometry::Vector6d step = geometry::Vector6d::Zero();
  step[axis] = kStepMm;
  const bool curved =
      model.inverse(geometry::Pose::from_vector(pose.as_vector() - step), behind).ok() &&
      model.inverse(geometry::Pose::from_vector(pose.as_vector() + step), ahead).ok();
  const kinematics::JointVector slope = jacobian.col(axis).cwiseAbs();
  const kinematics::JointVector curvature =
      curved
          ? kinematics::JointVector((ahead - 2.0 * here + behind).cwiseAbs() / (kStepMm * kStepMm))
          : kinematics::JointVector(kinematics::JointVector::Zero(jacobian.rows()));
  return motion::joint_feed_limit(machine.joints(), slope, curvature,
                                  machine.cartesian().max_feed_mm_per_s())
      .speed_mm_per_s;
}

}  // namespace pkm::linuxcnc
