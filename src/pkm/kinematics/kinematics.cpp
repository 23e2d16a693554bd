#include "pkm/kinematics/kinematics.hpp"

#include "pkm/kinematics/cable_tensions.hpp"

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace pkm::kinematics {

std::string formatted_number(const char* printf_pattern, double value) {
  char text[64];
  std::snprintf(text, sizeof text, printf_pattern, value);
  return text;
}

std::string_view status_name(StatusCode code) {
  switch (code) {
    case StatusCode::ok:
      return "ok";
    case StatusCode::unreachable:
      return "unreachable";
    case StatusCode::joint_limit:
      return "joint limit";
    case StatusCode::singular:
      return "singular";
    case StatusCode::not_converged:
      return "forward kinematics did not converge";
    case StatusCode::branch_changed:
      return "forward kinematics jumped to another assembly branch";
    case StatusCode::other_assembly:
      return "unreachable without passing a singularity (another assembly mode than home's)";
    case StatusCode::invalid_input:
      return "invalid input (NaN or infinite)";
    case StatusCode::outside_envelope:
      return "outside the work envelope";
    case StatusCode::tension:
      return "tension";
    case StatusCode::joint_angle:
      return "joint_angle";
    case StatusCode::interference:
      return "interference";
  }
  return "unknown";
}

// A switch without default: a code added to StatusCode without an identifier fails the build
// (-Wswitch, warnings are errors).
std::string_view status_identifier(StatusCode code) {
  switch (code) {
    case StatusCode::ok:
      return "ok";
    case StatusCode::unreachable:
      return "unreachable";
    case StatusCode::joint_limit:
      return "joint_limit";
    case StatusCode::singular:
      return "singular";
    case StatusCode::not_converged:
      return "not_converged";
    case StatusCode::branch_changed:
      return "branch_changed";
    case StatusCode::other_assembly:
      return "other_assembly";
    case StatusCode::invalid_input:
      return "invalid_input";
    case StatusCode::outside_envelope:
      return "outside_envelope";
    case StatusCode::tension:
      return "tension";
    case StatusCode::joint_angle:
      return "joint_angle";
    case StatusCode::interference:
      return "interference";
  }
  return "unknown";
}

std::string describe(const Status& status, std::span<const std::string> joint_names) {
  std::string text(status_name(status.code));
  if (status.joint >= 0) {
    text += " (joint ";
    if (status.joint < static_cast<int>(joint_names.size())) {
      text += "'" + joint_names[status.joint] + "'";
    } else {
      text += std::to_string(status.joint + 1);
    }
    text += ")";
  }
  if (status.axis >= 0 && status.axis < geometry::kPoseSize) {
    text += " (axis " + std::string(geometry::kAxisNames[status.axis]) + ")";
  }
  return text;
}

bool all_finite(const JointVector& joints) {
  for (int j = 0; j < joints.size(); ++j) {
    if (!std::isfinite(joints[j])) return false;
  }
  return true;
}

Status Kinematics::inverse_and_jacobian(const geometry::Pose& pose, JointVector& joints,
                                        JointJacobian& d_joints_d_pose) const {
  const Status status = inverse(pose, joints);
  if (!status.ok()) return status;
  return jacobian(pose, d_joints_d_pose);
}

void Kinematics::inverse_batch(std::span<const geometry::Pose> poses, std::span<JointVector> joints,
                               std::span<Status> statuses) const {
  if (joints.size() < poses.size() || statuses.size() < poses.size()) {
    throw std::invalid_argument("inverse_batch: output spans shorter than the input");
  }
  for (std::size_t i = 0; i < poses.size(); ++i) statuses[i] = inverse(poses[i], joints[i]);
}

namespace {

using ReducedJacobian = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kMaxJoints, 6>;
using ReducedSquare = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, 6, 6>;
using ReducedVector = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, 6, 1>;

struct ControlledAxes {
  std::array<int, geometry::kPoseSize> index{};
  int count = 0;
  explicit ControlledAxes(geometry::Dof dof) {
    for (int axis = 0; axis < geometry::kPoseSize; ++axis) {
      if (dof.controls(axis)) index[count++] = axis;
    }
  }
};

ReducedJacobian reduce(const JointJacobian& full, const ControlledAxes& axes) {
  ReducedJacobian reduced(full.rows(), axes.count);
  for (int k = 0; k < axes.count; ++k) reduced.col(k) = full.col(axes.index[k]);
  return reduced;
}

// LU of a square Jacobian, for Newton steps J step = -residual. Six-by-six (every 6-DOF model)
// goes through Eigen's fixed-size LU, faster than the dynamic one.
struct Factorization {
  Eigen::PartialPivLU<Eigen::Matrix<double, 6, 6>> six;
  Eigen::PartialPivLU<ReducedSquare> other;
  bool is_six = false;
  bool valid = false;
  double det_sign = 0.0;

  void compute(const JointJacobian& jacobian, const ControlledAxes& axes) {
    is_six = axes.count == geometry::kPoseSize;
    if (is_six) {
      six.compute(Eigen::Matrix<double, 6, 6>(jacobian.topRows<6>()));
      det_sign = std::copysign(1.0, six.determinant());
    } else {
      other.compute(reduce(jacobian, axes));
      det_sign = std::copysign(1.0, other.determinant());
    }
    valid = true;
  }
  ReducedVector solve(const JointVector& residual) const {
    if (is_six) return six.solve(-residual.head<6>());
    return other.solve(-residual);
  }
};

double determinant_sign(const JointJacobian& jacobian, const ControlledAxes& axes) {
  if (axes.count == geometry::kPoseSize) {
    return std::copysign(1.0, Eigen::Matrix<double, 6, 6>(jacobian.topRows<6>()).determinant());
  }
  return std::copysign(1.0, reduce(jacobian, axes).determinant());
}

double max_abs(const JointVector& v) {
  return v.size() == 0 ? 0.0 : v.cwiseAbs().maxCoeff();
}

}  // namespace

void Kinematics::forward_path(std::span<const JointVector> joints, const geometry::Pose& seed,
                              std::span<geometry::Pose> poses, std::span<Status> statuses) const {
  if (poses.size() < joints.size() || statuses.size() < joints.size()) {
    throw std::invalid_argument("forward_path: output spans shorter than the input");
  }
  ForwardTrack track;
  geometry::Pose previous = seed;
  for (std::size_t i = 0; i < joints.size(); ++i) {
    geometry::Pose pose = previous;
    statuses[i] = forward_along(joints[i], pose, track);
    poses[i] = pose;
    if (statuses[i].ok()) previous = pose;
  }
}

namespace {
// A seed this close (mm or rad) to the track's last solution continues the path: a pose that went
// through a machine's units and back may differ in its last digits.
constexpr double kTrackContinues = 1e-9;
// Newton steps a sample may take along a track before it is handed to forward().
constexpr int kTrackSteps = 4;
// Steps beyond one per sample, since the last factorisation, that call for a new one.
constexpr int kRefreshAfterExtraSteps = 2;

// The next sample's seed from the last solutions, for samples evenly spaced in time: constant,
// linear, then quadratic extrapolation as they accumulate.
geometry::Vector6d extrapolated(const std::array<geometry::Vector6d, 3>& solutions, int count) {
  if (count >= 3) return 3.0 * (solutions[0] - solutions[1]) + solutions[2];
  if (count == 2) return 2.0 * solutions[0] - solutions[1];
  return solutions[0];
}
}  // namespace

Status Kinematics::forward_along(const JointVector& joints, geometry::Pose& pose_inout,
                                 ForwardTrack& track) const {
  const geometry::Dof controlled = dof();
  const ControlledAxes axes(controlled);
  bool trackable = axes.count == joint_count() && joints.size() == joint_count();
  for (int j = 0; trackable && j < joint_count(); ++j) {
    // A rotary joint of the mechanism: its residual is in rad, and the tolerance then leaves the
    // tool 1e-9 mm off (an arm's lever), where forward()'s closed forms and fresh Newton steps
    // land nearer. Pass-through rotary joints are exact.
    trackable = joint_kind(j) == JointKind::linear || passthrough_axis(j) >= 0;
  }
  const geometry::Vector6d given = pose_inout.as_vector();
  const bool continues = track.count_ > 0 && all_finite(pose_inout) &&
                         (given - track.solutions_[0]).cwiseAbs().maxCoeff() <= kTrackContinues;
  int iterations = 0;
  if (trackable && continues && all_finite(joints)) {
    geometry::Vector6d x = extrapolated(track.solutions_, track.count_);
    // Coordinates the model does not control stay as seeded, as forward() leaves them.
    for (int axis = 0; axis < geometry::kPoseSize; ++axis) {
      if (!controlled.controls(axis)) x[axis] = given[axis];
    }
    if (track_steps(joints, x, track, iterations)) {
      track.solutions_[2] = track.solutions_[1];
      track.solutions_[1] = track.solutions_[0];
      track.solutions_[0] = x;
      track.count_ = std::min(track.count_ + 1, 3);
      pose_inout = geometry::Pose::from_vector(x);
      Status status = Status::success();
      status.iterations = iterations;
      return status;
    }
  }
  track.restart();
  Status status = forward(joints, pose_inout);
  status.iterations += iterations;
  if (status.ok()) {
    track.solutions_[0] = pose_inout.as_vector();
    track.count_ = 1;
  }
  return status;
}

bool Kinematics::track_steps(const JointVector& joints, geometry::Vector6d& x, ForwardTrack& track,
                             int& iterations) const {
  const ControlledAxes axes(dof());
  const int joint_total = joint_count();
  JointVector at_x(joint_total);
  const auto residual_at = [&](const geometry::Vector6d& pose, geometry::Vector6d& residual) {
    if (!inverse(geometry::Pose::from_vector(pose), at_x).ok()) return false;
    residual.setZero();
    for (int j = 0; j < joint_total; ++j) residual[j] = at_x[j] - joints[j];
    return true;
  };
  geometry::Vector6d residual;
  if (!residual_at(x, residual)) return false;
  double error = residual.cwiseAbs().maxCoeff();
  int factored_at = -1;  // the step whose Jacobian this sample factorised, if any
  for (iterations = 0; error > forward_options_.tolerance_mm; ++iterations) {
    if (iterations == kTrackSteps) return false;
    if (!track.factored_) {
      if (!factorise(x, track)) return false;
      factored_at = iterations;
    }
    const geometry::Vector6d step = -(track.inverse_ * residual);
    geometry::Vector6d trial = x;
    for (int k = 0; k < axes.count; ++k) trial[axes.index[k]] += step[k];
    geometry::Vector6d trial_residual;
    if (!step.allFinite() || !residual_at(trial, trial_residual)) return false;
    const double trial_error = trial_residual.cwiseAbs().maxCoeff();
    if (!(trial_error < error)) return false;
    // A step that cuts the residual less than tenfold, short of the tolerance (below it rounding
    // decides the ratio): the Jacobian has moved on.
    if (trial_error > forward_options_.tolerance_mm && trial_error > 0.1 * error) {
      track.factored_ = false;
    }
    x = trial;
    residual = trial_residual;
    error = trial_error;
  }
  // Steps beyond one per sample pay for a fresh factorisation (about two steps' work) once they
  // add up to it: rent or buy. The next seed gets it.
  const int extra = std::max(0, iterations - (factored_at >= 0 ? factored_at : 0) - 1);
  track.extra_steps_ = (factored_at >= 0 ? 0 : track.extra_steps_) + extra;
  if (track.extra_steps_ >= kRefreshAfterExtraSteps) track.factored_ = false;
  return true;
}

bool Kinematics::factorise(const geometry::Vector6d& x, ForwardTrack& track) const {
  const ControlledAxes axes(dof());
  JointVector at_x(joint_count());
  JointJacobian jacobian(joint_count(), geometry::kPoseSize);
  if (!inverse_and_jacobian(geometry::Pose::from_vector(x), at_x, jacobian).ok()) return false;
  // Padded with identity, so that every square model (2 to 6 coordinates) has one 6x6 LU.
  Eigen::Matrix<double, 6, 6> padded = Eigen::Matrix<double, 6, 6>::Identity();
  for (int k = 0; k < axes.count; ++k) {
    padded.col(k).head(joint_count()) = jacobian.col(axes.index[k]);
  }
  const Eigen::PartialPivLU<Eigen::Matrix<double, 6, 6>> lu(padded);
  const double det_sign = std::copysign(1.0, lu.determinant());
  // Across a singularity from the path so far: forward() decides, from the last solution.
  if (track.det_sign_ != 0.0 && det_sign != track.det_sign_) return false;
  // Column by column: the fixed-size vector solves, where inverse() takes Eigen's blocked paths.
  for (int k = 0; k < 6; ++k) track.inverse_.col(k) = lu.solve(geometry::Vector6d::Unit(k));
  if (!track.inverse_.allFinite()) return false;
  track.det_sign_ = det_sign;
  track.factored_ = true;
  return true;
}

namespace {

// The state of one damped-Newton solve (newton_from_seed): the iterate, what is known at it,
// and the trial buffers, all fixed-capacity so that a solve allocates nothing.
struct NewtonIterate {
  NewtonIterate(const geometry::Vector6d& seed, int joint_count)
      : x(seed),
        at_x(joint_count),
        jacobian_at_x(joint_count, geometry::kPoseSize),
        at_trial(joint_count),
        jacobian_at_trial(joint_count, geometry::kPoseSize) {}

  geometry::Vector6d x;
  JointVector at_x;
  JointJacobian jacobian_at_x;
  bool jacobian_current = true;  // jacobian_at_x belongs to x (not to an earlier iterate)
  JointVector residual;
  double cost = 0.0;
  // Square systems take Newton steps through an LU of J, kept while it keeps paying: a step that
  // cuts the residual tenfold or more does not need a new factorisation (the chord method). That
  // halves the work along paths, where the seed is a servo step from the answer. A step that
  // fails falls back to Marquardt-damped normal equations.
  Factorization factorization;
  double seed_det_sign = 0.0;
  double last_det_sign = 0.0;
  JointVector at_trial;
  JointJacobian jacobian_at_trial;
  double lambda = 0.0;  // Marquardt damping; 0 while Newton steps are taken
};

// Recomputes the joints and Jacobian at the iterate; false where x is outside the workspace.
bool jacobian_at_iterate(const Kinematics& model, NewtonIterate& it) {
  if (!model.inverse_and_jacobian(geometry::Pose::from_vector(it.x), it.at_x, it.jacobian_at_x)
           .ok()) {
    return false;
  }
  it.jacobian_current = true;
  return true;
}

// The undamped Newton step, through the kept factorisation (computed here when there is none).
ReducedVector newton_step(NewtonIterate& it, const ControlledAxes& axes) {
  if (!it.factorization.valid) {
    it.factorization.compute(it.jacobian_at_x, axes);
    it.last_det_sign = it.factorization.det_sign;
    if (it.seed_det_sign == 0.0) it.seed_det_sign = it.last_det_sign;
  }
  return it.factorization.solve(it.residual);
}

// The Marquardt step: normal equations with the diagonal scaled by 1 + lambda.
ReducedVector damped_step(const NewtonIterate& it, const ControlledAxes& axes) {
  const ReducedJacobian reduced = reduce(it.jacobian_at_x, axes);
  ReducedSquare damped = reduced.transpose() * reduced;
  damped.diagonal() += it.lambda * damped.diagonal();
  return damped.ldlt().solve(-(reduced.transpose() * it.residual));
}

// Moves the iterate to a trial that lowered the cost, and decides what of the Jacobian and its
// factorisation still holds there.
void accept_trial(const Kinematics& model, const JointVector& joints,
                  const geometry::Vector6d& trial, double trial_cost, bool newton,
                  NewtonIterate& it) {
  const bool fast = trial_cost <= 0.01 * it.cost;  // residual cut at least tenfold
  it.x = trial;
  it.residual = it.at_trial - joints;
  it.cost = trial_cost;
  if (!newton) {
    it.jacobian_at_x = it.jacobian_at_trial;
    it.jacobian_current = true;
    it.factorization.valid = false;
    it.lambda = it.lambda < 1e-9 ? 0.0 : it.lambda * 0.1;
  } else if (!fast) {
    it.jacobian_current = false;
    it.factorization.valid = false;
  } else {
    it.jacobian_current = false;  // the factorisation stays, from an earlier iterate
  }
  // Where this fails, jacobian_current stays false and the next step starts from the old one.
  if (!it.jacobian_current && !it.factorization.valid) jacobian_at_iterate(model, it);
}

enum class TrialOutcome { stepped, retry, stuck };

// One trial step from the iterate: Newton while the system is square and undamped, Marquardt
// otherwise. A trial that does not lower the cost refreshes a stale Jacobian or raises the damping
// for the next trial. Clears `contracted` unless the step was Newton's and halved the residual.
TrialOutcome try_step(const Kinematics& model, const JointVector& joints,
                      const ControlledAxes& axes, bool square, NewtonIterate& it,
                      bool& contracted) {
  const bool newton = square && it.lambda == 0.0;
  if (!newton && !it.jacobian_current) {
    if (!jacobian_at_iterate(model, it)) return TrialOutcome::stuck;
    it.factorization.valid = false;
  }
  const ReducedVector step = newton ? newton_step(it, axes) : damped_step(it, axes);
  geometry::Vector6d trial = it.x;
  for (int k = 0; k < axes.count; ++k) trial[axes.index[k]] += step[k];
  const geometry::Pose trial_pose = geometry::Pose::from_vector(trial);
  const bool reached =
      step.allFinite() &&
      (newton ? model.inverse(trial_pose, it.at_trial)
              : model.inverse_and_jacobian(trial_pose, it.at_trial, it.jacobian_at_trial))
          .ok();
  const double trial_cost = reached ? (it.at_trial - joints).squaredNorm() : INFINITY;
  if (!newton || !(trial_cost <= 0.25 * it.cost)) contracted = false;
  if (trial_cost < it.cost) {
    accept_trial(model, joints, trial, trial_cost, newton, it);
    return TrialOutcome::stepped;
  }
  if (newton && !it.jacobian_current) {
    // A stale factorisation may be all that failed: refresh it before damping.
    if (!jacobian_at_iterate(model, it)) return TrialOutcome::stuck;
    it.factorization.valid = false;
  } else {
    it.lambda = it.lambda == 0.0 ? 1e-6 : it.lambda * 10.0;
  }
  return TrialOutcome::retry;
}

// Up to 40 trials from the iterate; true once one of them lowered the cost.
bool step_once(const Kinematics& model, const JointVector& joints, const ControlledAxes& axes,
               bool square, NewtonIterate& it, bool& contracted) {
  for (int attempt = 0; attempt < 40; ++attempt) {
    const TrialOutcome outcome = try_step(model, joints, axes, square, it, contracted);
    if (outcome == TrialOutcome::stepped) return true;
    if (outcome == TrialOutcome::stuck) return false;
  }
  return false;
}

// The last factorisation is from at most a few converging steps before the solution; a change
// of sign of det J between seed and there means the iteration crossed a singularity.
bool crossed_singularity(const NewtonIterate& it, const ControlledAxes& axes) {
  if (it.seed_det_sign == 0.0) return false;
  const double final_sign =
      it.factorization.valid
          ? it.last_det_sign
          : (it.jacobian_current ? determinant_sign(it.jacobian_at_x, axes) : it.last_det_sign);
  return final_sign != it.seed_det_sign;
}

// Damped Newton from the seed `pose_inout`. `contracted`: every step was an undamped Newton
// step that at least halved the residual (Deuflhard's test of the region where the linear model
// holds): a solution reached so leaves no doubt that it is the seed's own.
Status newton_from_seed(const Kinematics& model, const JointVector& joints,
                        geometry::Pose& pose_inout, const ForwardOptions& options,
                        bool& contracted) {
  contracted = true;
  const ControlledAxes axes(model.dof());
  const int joint_count = model.joint_count();
  const bool square = axes.count == joint_count;
  NewtonIterate it(pose_inout.as_vector(), joint_count);
  if (!model.inverse_and_jacobian(geometry::Pose::from_vector(it.x), it.at_x, it.jacobian_at_x)
           .ok()) {
    return Status::failure(StatusCode::not_converged);  // the seed itself is outside the workspace
  }
  it.residual = it.at_x - joints;
  it.cost = it.residual.squaredNorm();

  bool converged = false;
  int iterations = 0;
  const auto counted = [&iterations](Status status) {
    status.iterations = iterations;
    return status;
  };
  for (; iterations < options.max_iterations; ++iterations) {
    if (max_abs(it.residual) <= options.tolerance_mm) {
      converged = true;
      break;
    }
    if (!step_once(model, joints, axes, square, it, contracted)) break;
  }
  if (!converged && max_abs(it.residual) > options.tolerance_mm) {
    return counted(Status::failure(StatusCode::not_converged));
  }
  if (square && crossed_singularity(it, axes)) {
    return counted(Status::failure(StatusCode::branch_changed));
  }
  pose_inout = geometry::Pose::from_vector(it.x);
  return counted(Status::success());
}

// Continuation along the straight joint path from the seed's joints: its shortest stretch (of
// the path, 1), its most stretches tried (a pose near a fold of the path, where the pose moves
// as the square root of the joints, takes a few dozen), and Newton corrections per stretch.
constexpr double kShortestStretch = 1e-12;
constexpr int kMostStretches = 200;
constexpr int kCorrections = 8;

// Newton steps from `x` (the solution at the previous joints along the path) to `target`, each
// with a fresh Jacobian whose determinant keeps `det_sign`, each at least halving the residual:
// the steps stay on the branch they start on, or fail (the caller halves the stretch).
bool corrected(const Kinematics& model, const JointVector& target, double tolerance,
               double det_sign, const ControlledAxes& axes, geometry::Vector6d& x,
               int& iterations) {
  const int joint_count = model.joint_count();
  JointVector at_x(joint_count);
  JointJacobian jacobian(joint_count, geometry::kPoseSize);
  double error = INFINITY;
  for (int step = 0; step <= kCorrections; ++step) {
    if (!model.inverse_and_jacobian(geometry::Pose::from_vector(x), at_x, jacobian).ok())
      return false;
    const JointVector residual = at_x - target;
    const double trial_error = max_abs(residual);
    if (!(trial_error <= 0.5 * error) && trial_error > tolerance) return false;
    error = trial_error;
    if (error <= tolerance) return true;
    if (step == kCorrections) return false;
    Factorization factorization;
    factorization.compute(jacobian, axes);
    if (factorization.det_sign != det_sign) return false;
    const ReducedVector delta = factorization.solve(residual);
    if (!delta.allFinite()) return false;
    for (int k = 0; k < axes.count; ++k) x[axes.index[k]] += delta[k];
    ++iterations;
  }
  return false;
}

// FK by continuation: the joints move in a straight line from the seed's own to `joints`, and
// the pose follows in steps short enough for Newton to stay on the seed's branch (halved where
// it would not, doubled where it does). Fails where the line meets a singularity of the seed's
// branch, or the seed has no joints.
Status traced_from_seed(const Kinematics& model, const JointVector& joints,
                        geometry::Pose& pose_inout, const ForwardOptions& options) {
  const ControlledAxes axes(model.dof());
  const int joint_count = model.joint_count();
  JointVector start(joint_count);
  JointJacobian jacobian(joint_count, geometry::kPoseSize);
  if (!model.inverse_and_jacobian(pose_inout, start, jacobian).ok()) {
    return Status::failure(StatusCode::not_converged);
  }
  const double det_sign = determinant_sign(jacobian, axes);
  // A stretch's end is solved to this joint residual (mm or rad): near enough for the next.
  const double loose = std::max(options.tolerance_mm, 1e-9);
  geometry::Vector6d x = pose_inout.as_vector();
  double done = 0.0;
  double stretch = 0.25;
  int iterations = 0;
  for (int tried = 0; done < 1.0; ++tried) {
    const double next = std::min(1.0, done + stretch);
    const JointVector target = start + next * (joints - start);
    geometry::Vector6d trial = x;
    if (corrected(model, next == 1.0 ? joints : target, next == 1.0 ? options.tolerance_mm : loose,
                  det_sign, axes, trial, iterations)) {
      x = trial;
      done = next;
      stretch = std::min(1.0, 2.0 * stretch);
    } else if (stretch < kShortestStretch || tried == kMostStretches) {
      Status failed = Status::failure(StatusCode::branch_changed);
      failed.iterations = iterations;
      return failed;
    } else {
      stretch *= 0.5;
    }
  }
  pose_inout = geometry::Pose::from_vector(x);
  Status status = Status::success();
  status.iterations = iterations;
  return status;
}

// Newton steps from the seed, each shortened (halved) until it cuts the residual without det J
// changing sign: a walk in pose space that keeps to the seed's side of the singularities, for the
// poses whose straight joint path from the seed folds back at one (a hexaglide's corners).
Status walked_from_seed(const Kinematics& model, const JointVector& joints,
                        geometry::Pose& pose_inout, const ForwardOptions& options) {
  constexpr int kMostSteps = 100;
  constexpr int kMostHalvings = 30;
  const ControlledAxes axes(model.dof());
  const int joint_count = model.joint_count();
  JointVector at_x(joint_count);
  JointJacobian jacobian(joint_count, geometry::kPoseSize);
  geometry::Vector6d x = pose_inout.as_vector();
  if (!model.inverse_and_jacobian(geometry::Pose::from_vector(x), at_x, jacobian).ok()) {
    return Status::failure(StatusCode::not_converged);
  }
  const double det_sign = determinant_sign(jacobian, axes);
  double error = max_abs(at_x - joints);
  Status status = Status::failure(StatusCode::branch_changed);
  for (int step = 0; step < kMostSteps && error > options.tolerance_mm; ++step) {
    Factorization factorization;
    factorization.compute(jacobian, axes);
    const ReducedVector delta = factorization.solve(at_x - joints);
    if (!delta.allFinite()) return status;
    double length = 1.0;
    bool moved = false;
    for (int halving = 0; halving < kMostHalvings && !moved; ++halving, length *= 0.5) {
      geometry::Vector6d trial = x;
      for (int k = 0; k < axes.count; ++k) trial[axes.index[k]] += length * delta[k];
      JointVector at_trial(joint_count);
      JointJacobian jacobian_at_trial(joint_count, geometry::kPoseSize);
      if (!model
               .inverse_and_jacobian(geometry::Pose::from_vector(trial), at_trial,
                                     jacobian_at_trial)
               .ok()) {
        continue;
      }
      const double trial_error = max_abs(at_trial - joints);
      if (!(trial_error < error) || determinant_sign(jacobian_at_trial, axes) != det_sign) {
        continue;
      }
      x = trial;
      at_x = at_trial;
      jacobian = jacobian_at_trial;
      error = trial_error;
      moved = true;
    }
    status.iterations = step + 1;
    if (!moved) return status;
  }
  if (error > options.tolerance_mm) return status;
  pose_inout = geometry::Pose::from_vector(x);
  const int iterations = status.iterations;
  status = Status::success();
  status.iterations = iterations;
  return status;
}

// Whether the straight pose segment from `seed` to `end` stays where IK answers with det J of
// the seed's sign, at 64 points along it.
bool on_seeds_side(const Kinematics& model, const geometry::Pose& seed, const geometry::Pose& end) {
  constexpr int kPoints = 64;
  const ControlledAxes axes(model.dof());
  JointVector at(model.joint_count());
  JointJacobian jacobian(model.joint_count(), geometry::kPoseSize);
  if (!model.inverse_and_jacobian(seed, at, jacobian).ok()) return false;
  const double det_sign = determinant_sign(jacobian, axes);
  const geometry::Vector6d from = seed.as_vector();
  const geometry::Vector6d span = end.as_vector() - from;
  for (int k = 1; k <= kPoints; ++k) {
    const geometry::Pose point =
        geometry::Pose::from_vector(from + (static_cast<double>(k) / kPoints) * span);
    if (!model.inverse_and_jacobian(point, at, jacobian).ok() ||
        determinant_sign(jacobian, axes) != det_sign) {
      return false;
    }
  }
  return true;
}

}  // namespace

Status solve_forward_newton(const Kinematics& model, const JointVector& joints,
                            geometry::Pose& pose_inout, const ForwardOptions& options) {
  if (!all_finite(joints) || !all_finite(pose_inout)) {
    return Status::failure(StatusCode::invalid_input);
  }
  geometry::Pose direct = pose_inout;
  bool contracted = false;
  const Status status = newton_from_seed(model, joints, direct, options, contracted);
  const bool square = ControlledAxes(model.dof()).count == model.joint_count();
  if ((status.ok() && contracted) || !square) {
    if (status.ok()) pose_inout = direct;
    return status;
  }
  // From a far seed Newton may land on another solution of the same joints (a hexapod has up to
  // 40) without det J changing sign, or refuse one it could reach: the seed's own solution is
  // the one continuation reaches.
  Status traced = traced_from_seed(model, joints, pose_inout, options);
  if (traced.code == StatusCode::branch_changed) {
    const int iterations = traced.iterations;
    traced = walked_from_seed(model, joints, pose_inout, options);
    traced.iterations += iterations;
  }
  traced.iterations += status.iterations;
  if (traced.ok()) return traced;
  // Neither reaches the joints from the seed. Newton's pose, where it found one, is still the
  // seed's if the straight segment between them keeps to the seed's side of the singularities;
  // else it is another branch's. Without one the joints are most often beyond every branch.
  if (status.ok() && on_seeds_side(model, pose_inout, direct)) {
    pose_inout = direct;
    return status;
  }
  traced.code = status.ok() ? StatusCode::branch_changed : status.code;
  return traced;
}

Status numerical_jacobian(const Kinematics& model, const geometry::Pose& pose,
                          JointJacobian& d_joints_d_pose) {
  const int joints = model.joint_count();
  d_joints_d_pose.setZero(joints, geometry::kPoseSize);
  const geometry::Vector6d x = pose.as_vector();
  JointVector plus(joints), minus(joints);
  for (int axis = 0; axis < geometry::kPoseSize; ++axis) {
    if (!model.dof().controls(axis)) continue;
    // Steps near the cube root of machine epsilon balance truncation and rounding error.
    const double step = axis < 3 ? 1e-5 * std::max(1.0, std::abs(x[axis])) : 1e-6;
    geometry::Vector6d shifted = x;
    shifted[axis] = x[axis] + step;
    Status status = model.inverse(geometry::Pose::from_vector(shifted), plus);
    if (!status.ok()) return status;
    shifted[axis] = x[axis] - step;
    status = model.inverse(geometry::Pose::from_vector(shifted), minus);
    if (!status.ok()) return status;
    d_joints_d_pose.col(axis) = (plus - minus) / (2.0 * step);
  }
  return Status::success();
}

std::unique_ptr<Kinematics> joint_geometry(const Kinematics& model) {
  if (const CableTensions* cables = model.cable_tensions()) return cables->geometry_only();
  return model.clone();
}

}  // namespace pkm::kinematics
