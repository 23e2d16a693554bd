#include "pkm/kinematics/cable_robot.hpp"

#include <Eigen/Cholesky>
#include <Eigen/QR>
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>

#include "pkm/kinematics/model_config_writer.hpp"

namespace pkm::kinematics {

namespace {

// Gauss-Newton has converged once a step moves the tool less than this (mm): the steps shrink
// quadratically where the joints fit a pose, so the pose is then good to the doubles' last digits.
constexpr double kConvergedStep_mm = 1e-10;
// A cable whose joint the pose absorbs (its column of the misfit's projection shorter than this)
// cannot explain a misfit.
constexpr double kNoRedundancy = 1e-9;

std::string cable_name(int cable, std::span<const std::string> joint_names) {
  if (cable >= 0 && cable < static_cast<int>(joint_names.size())) {
    return "'" + joint_names[cable] + "'";
  }
  return std::to_string(cable + 1);
}

std::string mm(double value) {
  return formatted_number("%.3f", value) + " mm";
}

}  // namespace

CableRobotKinematics::CableRobotKinematics(CableRobotGeometry geometry, PassThroughAxes passthrough)
    : geometry_(std::move(geometry)), passthrough_(std::move(passthrough)) {
  validate_cable_robot_geometry(geometry_);
  const auto& axes = passthrough_.axes();
  if (geometry_.cables_follow_z && std::find(axes.begin(), axes.end(), 2) == axes.end()) {
    throw std::invalid_argument(
        "cables_follow_z: needs the tool's z as a pass-through joint (passthrough = [\"z\"])");
  }
  if (joint_count() > kMaxJoints) {
    throw std::invalid_argument("cables: " + std::to_string(cable_count()) + " cables and " +
                                std::to_string(passthrough_.count()) +
                                " pass-through joints make more than " +
                                std::to_string(kMaxJoints) + " joints, the most a machine has");
  }
}

void validate_cable_robot_geometry(const CableRobotGeometry& g) {
  const int needed = g.planar ? 3 : 4;
  const int count = static_cast<int>(g.cables.size());
  if (count < needed) {
    throw std::invalid_argument(std::string("cables: a ") + (g.planar ? "planar" : "spatial") +
                                " cable robot needs at least " + std::to_string(needed) +
                                " cables (one more than its " + std::to_string(needed - 1) +
                                " coordinates, so that they can pull against each other), found " +
                                std::to_string(count));
  }
  if (count > kMaxJoints) {
    throw std::invalid_argument("cables: at most " + std::to_string(kMaxJoints) +
                                " cables, found " + std::to_string(count));
  }
  for (const RobotCable& cable : g.cables) {
    if (!cable.anchor_mm.allFinite() || !cable.attach_mm.allFinite() ||
        !std::isfinite(cable.offset_mm)) {
      throw std::invalid_argument("cables: anchor, attach and offset must be finite");
    }
    if (!(cable.swivel_arm_mm >= 0.0) || !std::isfinite(cable.swivel_arm_mm)) {
      throw std::invalid_argument("swivel_arm: must be a length of 0 or more");
    }
  }
  if (!(g.effector_mass_kg >= 0.0) || !std::isfinite(g.effector_mass_kg)) {
    throw std::invalid_argument("effector_mass: must be 0 or more (kg)");
  }
  if (!g.center_of_mass_mm.allFinite()) {
    throw std::invalid_argument("center_of_mass: must be finite");
  }
  if (g.tension_limited && !(g.tension_min_N >= 0.0 && g.tension_max_N > g.tension_min_N &&
                             std::isfinite(g.tension_max_N))) {
    throw std::invalid_argument("tension_limits: must be [min, max] with 0 <= min < max (N)");
  }
  validate_cable_robot_load(g);
  validate_cable_robot_drive(g);
  validate_cable_robot_pulleys(g);
  if (g.cables_follow_z && !g.planar) {
    throw std::invalid_argument(
        "cables_follow_z: only a planar robot's tie points can ride on its tool's z");
  }
  if (!(g.misfit_tolerance_mm > 0.0) || !(g.misfit_tolerance_mm <= 100.0)) {
    throw std::invalid_argument("misfit_tolerance: must be a length above 0 and at most 100 mm");
  }
}

Eigen::Vector3d CableRobotKinematics::tool_point(const geometry::Pose& pose) const {
  // A planar robot's effector moves in the plane z = 0: its cables' z are heights above it,
  // unless its tie points ride on the tool's z (Maslow 4's arms on the spindle).
  Eigen::Vector3d tool = pose.position_mm;
  if (geometry_.planar && !geometry_.cables_follow_z) tool.z() = 0.0;
  return tool;
}

bool CableRobotKinematics::tie_point(int cable, const Eigen::Vector3d& tool_mm,
                                     Eigen::Vector3d& tie_mm) const {
  const RobotCable& c = geometry_.cables[cable];
  tie_mm = tool_mm + c.attach_mm;
  if (c.swivel_arm_mm == 0.0) return true;
  const Eigen::Vector2d towards = (c.anchor_mm - tie_mm).head<2>();
  const double plan_distance = towards.norm();
  if (!(plan_distance > c.swivel_arm_mm)) return false;
  tie_mm.head<2>() += (c.swivel_arm_mm / plan_distance) * towards;
  return true;
}

Status CableRobotKinematics::lengths(const Eigen::Vector3d& tool_mm, CableVector& length_mm,
                                     CableJacobian* d_length) const {
  const int n = cable_count();
  length_mm.resize(n);
  if (d_length != nullptr) d_length->resize(n, 3);
  for (int i = 0; i < n; ++i) {
    Eigen::Vector3d tie;
    if (!tie_point(i, tool_mm, tie)) return Status::failure(StatusCode::unreachable, i);
    if (geometry_.cables[i].pulley_radius_mm > 0.0) {
      PulleyPath path;
      const Status over = pulley_path(geometry_.cables[i], tie, path);
      if (!over.ok()) return Status::failure(over.code, i);
      length_mm[i] = path.length_mm;
      if (d_length != nullptr) d_length->row(i) = path.direction.transpose();
      continue;
    }
    const Eigen::Vector3d along = geometry_.cables[i].anchor_mm - tie;
    const double length = along.norm();
    if (!(length >= kShortestRobotCable_mm)) return Status::failure(StatusCode::singular, i);
    length_mm[i] = length;
    // d length / d tool = -(unit vector to the anchor), with or without a swivel arm: the arm's
    // end moves across the cable, which changes its length only to second order.
    if (d_length != nullptr) d_length->row(i) = -(along / length).transpose();
  }
  if (geometry_.flex_compensation) {
    // The joints are the unstretched lengths. d length / d tool stays the straight lines': the
    // stretch changes with the pose a ten-thousandth as fast, which Gauss-Newton absorbs.
    CableVector stretched;
    stretch(tool_mm, length_mm, stretched);
    length_mm -= stretched;
  }
  return Status::success();
}

Status CableRobotKinematics::inverse(const geometry::Pose& pose, JointVector& joints) const {
  if (!all_finite(pose)) return Status::failure(StatusCode::invalid_input);
  CableVector length;
  const Status status = lengths(tool_point(pose), length, nullptr);
  if (!status.ok()) return status;
  joints.resize(joint_count());
  for (int i = 0; i < cable_count(); ++i) joints[i] = length[i] + geometry_.cables[i].offset_mm;
  passthrough_.inverse(pose, joints, cable_count());
  return check_tensions(pose);
}

Status CableRobotKinematics::jacobian(const geometry::Pose& pose,
                                      JointJacobian& d_joints_d_pose) const {
  if (!all_finite(pose)) return Status::failure(StatusCode::invalid_input);
  CableVector length;
  CableJacobian d_length;
  const Status status = lengths(tool_point(pose), length, &d_length);
  if (!status.ok()) return status;
  if (geometry_.flex_compensation) flex_jacobian(tool_point(pose), d_length);
  d_joints_d_pose.setZero(joint_count(), geometry::kPoseSize);
  d_joints_d_pose.topLeftCorner(cable_count(), coordinates()) = d_length.leftCols(coordinates());
  if (geometry_.planar && geometry_.cables_follow_z) {
    d_joints_d_pose.col(2).head(cable_count()) = d_length.col(2);
  }
  passthrough_.jacobian(d_joints_d_pose, cable_count());
  return Status::success();
}

StructureMatrix CableRobotKinematics::structure_matrix(const geometry::Pose& pose) const {
  CableVector length;
  CableJacobian d_length;
  if (!all_finite(pose) || !lengths(tool_point(pose), length, &d_length).ok()) return {};
  return -d_length.leftCols(coordinates()).transpose();
}

std::string CableRobotKinematics::why_refused(const geometry::Pose& pose,
                                              const Status& status) const {
  if (status.code == StatusCode::tension) return explain_tensions(pose);
  if (status.joint < 0 || status.joint >= cable_count()) return {};
  const RobotCable& cable = geometry_.cables[status.joint];
  const Eigen::Vector3d pivot = tool_point(pose) + cable.attach_mm;
  const std::string which = "cable " + std::to_string(status.joint + 1);
  if (cable.pulley_radius_mm > 0.0) {
    PulleyPath path;
    pulley_path(cable, pivot, path);
    if (path.axis_distance_mm < kShortestRobotCable_mm) {
      return which + "'s tie point is on its pulley's swivel axis (" + mm(path.axis_distance_mm) +
             " from it): the pulley has no plane to turn to";
    }
    return which + "'s tie point is " + mm(path.rim_distance_mm) +
           " from its pulley's centre, within its pulley_radius " + mm(cable.pulley_radius_mm);
  }
  if (status.code == StatusCode::singular) {
    return which + " would have no length: its tie point on the effector is at its anchor";
  }
  if (status.code == StatusCode::unreachable) {
    return which + "'s anchor is " + mm((cable.anchor_mm - pivot).head<2>().norm()) +
           " from its arm's pivot in plan view, within the swivel arm's " + mm(cable.swivel_arm_mm);
  }
  return {};
}

CableFit CableRobotKinematics::gauss_newton(const CableVector& wanted_mm,
                                            const geometry::Pose& start) const {
  const int k = coordinates();
  CableFit fit;
  fit.pose = start;
  Eigen::Vector3d x = tool_point(start);
  CableVector length;
  CableJacobian d_length;
  fit.status = lengths(x, length, &d_length);
  if (!fit.status.ok()) return fit;
  double cost = (length - wanted_mm).squaredNorm();
  double damping = 0.0;  // Marquardt's lambda: 0 is Gauss-Newton's own step
  for (int iteration = 1; iteration <= forward_options_.max_iterations; ++iteration) {
    fit.iterations = iteration;
    const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, 3, 3> normal =
        d_length.leftCols(k).transpose() * d_length.leftCols(k);
    Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, 3, 3> damped = normal;
    damped.diagonal() *= 1.0 + damping;
    const Eigen::Matrix<double, Eigen::Dynamic, 1, 0, 3, 1> step =
        -damped.ldlt().solve(d_length.leftCols(k).transpose() * (length - wanted_mm));
    if (!step.allFinite()) break;
    Eigen::Vector3d trial = x;
    trial.head(k) += step;
    CableVector trial_length;
    CableJacobian trial_d_length;
    const bool lower = lengths(trial, trial_length, &trial_d_length).ok() &&
                       (trial_length - wanted_mm).squaredNorm() <= cost;
    if (lower) {
      x = trial;
      length = trial_length;
      d_length = trial_d_length;
      cost = (length - wanted_mm).squaredNorm();
      damping = damping < 1e-6 ? 0.0 : damping / 10.0;
    } else {
      damping = damping == 0.0 ? 1e-3 : damping * 10.0;
    }
    if (step.norm() <= kConvergedStep_mm) {
      fit.pose.position_mm.head(k) = x.head(k);
      fit.status = Status::success();
      fit.status.iterations = iteration;
      fit.misfit_mm = length - wanted_mm;
      analyse_misfit(d_length, fit);
      return fit;
    }
  }
  fit.status = Status::failure(StatusCode::not_converged);
  fit.status.iterations = fit.iterations;
  return fit;
}

void CableRobotKinematics::analyse_misfit(const CableJacobian& d_length, CableFit& fit) const {
  const int n = cable_count();
  const CableVector& misfit = fit.misfit_mm;
  fit.rms_mm = std::sqrt(misfit.squaredNorm() / n);
  fit.worst_mm = misfit.cwiseAbs().maxCoeff(&fit.worst_cable);
  // The misfits a pose cannot take up: the projection on the complement of d length / d tool's
  // columns. Cable i's joint changed by e moves the fitted misfit by -e (projection of unit i).
  // Fixed-capacity matrices: no heap in the servo thread.
  using CableSquare =
      Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kMaxJoints, kMaxJoints>;
  const CableJacobian columns = d_length.leftCols(coordinates());
  const Eigen::HouseholderQR<CableJacobian> qr(columns);
  CableSquare q = CableSquare::Identity(n, n);
  q.applyOnTheLeft(qr.householderQ());
  const CableSquare projection =
      q.rightCols(n - coordinates()) * q.rightCols(n - coordinates()).transpose();
  fit.alone_excess_mm.setZero(n);
  fit.alone_worst_mm.setConstant(n, fit.worst_mm);
  int explaining = 0;
  for (int i = 0; i < n; ++i) {
    const CableVector column = projection.col(i);
    const double reach = column.squaredNorm();
    if (reach < kNoRedundancy) continue;
    const double excess = -column.dot(misfit) / reach;
    fit.alone_excess_mm[i] = excess;
    fit.alone_worst_mm[i] = (misfit + excess * column).cwiseAbs().maxCoeff();
    if (fit.alone_worst_mm[i] <= geometry_.misfit_tolerance_mm) {
      ++explaining;
      fit.culprit = i;
    }
  }
  if (explaining != 1) fit.culprit = -1;
}

std::optional<Eigen::Vector3d> CableRobotKinematics::trilateration(const CableVector& wanted_mm,
                                                                   double tool_z_mm) const {
  // |tool - centre_i| = radius_i for each cable: subtracting the mean of the squared equations
  // leaves a linear system in the tool position (planar: in plan view, the heights taken out).
  const int n = cable_count();
  const int k = coordinates();
  CableJacobian centres(n, k);
  CableVector squares(n);
  for (int i = 0; i < n; ++i) {
    const RobotCable& c = geometry_.cables[i];
    if (c.swivel_arm_mm != 0.0 && !geometry_.planar) return std::nullopt;
    const Eigen::Vector3d centre = c.anchor_mm - c.attach_mm;
    double radius = wanted_mm[i];
    if (geometry_.planar) {
      const double height = centre.z() - tool_z_mm;
      const double flat = radius * radius - height * height;
      if (!(flat >= 0.0)) return std::nullopt;
      radius = std::sqrt(flat) + c.swivel_arm_mm;
    }
    centres.row(i) = centre.head(k).transpose();
    squares[i] = centre.head(k).squaredNorm() - radius * radius;
  }
  const Eigen::Matrix<double, 1, Eigen::Dynamic, Eigen::RowMajor, 1, 3> mean_centre =
      centres.colwise().mean();
  const CableJacobian system = 2.0 * (centres.rowwise() - mean_centre);
  const CableVector right = squares.array() - squares.mean();
  const Eigen::ColPivHouseholderQR<CableJacobian> qr(system);
  if (qr.rank() < k) return std::nullopt;
  Eigen::Vector3d tool = Eigen::Vector3d::Zero();
  tool.head(k) = qr.solve(right);
  if (!tool.allFinite()) return std::nullopt;
  return tool;
}

CableFit CableRobotKinematics::fit(const JointVector& joints, const geometry::Pose& seed) const {
  CableFit result;
  result.pose = seed;
  if (joints.size() != joint_count() || !all_finite(joints) || !all_finite(seed)) {
    result.status = Status::failure(StatusCode::invalid_input);
    return result;
  }
  CableVector wanted(cable_count());
  for (int i = 0; i < cable_count(); ++i) wanted[i] = joints[i] - geometry_.cables[i].offset_mm;
  // The pass-through joints first: a tool's z the cables ride on is its joint's.
  geometry::Pose start = seed;
  passthrough_.forward(joints, cable_count(), start);
  result = gauss_newton(wanted, start);
  const bool fits = result.status.ok() && result.worst_mm <= geometry_.misfit_tolerance_mm;
  if (!fits) {
    // The seed may have led to a local minimum (a far seed, the mirror image of the anchors'
    // plane): start again from the joints' own linear estimate, keep the better fit.
    if (const std::optional<Eigen::Vector3d> guess = trilateration(wanted, tool_point(start).z())) {
      geometry::Pose from = start;
      from.position_mm.head(coordinates()) = guess->head(coordinates());
      CableFit again = gauss_newton(wanted, from);
      again.iterations += result.iterations;
      again.status.iterations = again.iterations;
      if (again.status.ok() && (!result.status.ok() || again.rms_mm < result.rms_mm)) {
        result = std::move(again);
      }
    }
  }
  return result;
}

Status CableRobotKinematics::forward(const JointVector& joints, geometry::Pose& pose_inout) const {
  const CableFit solved = fit(joints, pose_inout);
  if (!solved.status.ok()) return solved.status;
  if (solved.worst_mm > geometry_.misfit_tolerance_mm) {
    Status refused = Status::failure(StatusCode::unreachable,
                                     solved.culprit >= 0 ? solved.culprit : solved.worst_cable);
    refused.iterations = solved.iterations;
    return refused;
  }
  pose_inout = solved.pose;
  return solved.status;
}

std::string CableRobotKinematics::why_forward_refused(
    const JointVector& joints, const geometry::Pose& seed, const Status& status,
    std::span<const std::string> joint_names) const {
  if (status.code != StatusCode::unreachable) return {};
  return explain_misfit(fit(joints, seed), joint_names);
}

std::string CableRobotKinematics::explain_misfit(const CableFit& fit,
                                                 std::span<const std::string> joint_names) const {
  if (!fit.status.ok() || fit.worst_mm <= geometry_.misfit_tolerance_mm) return {};
  std::string text = "the cables fit no pose: the nearest leaves cable " +
                     cable_name(fit.worst_cable, joint_names) + " " + mm(fit.worst_mm) +
                     " off (RMS " + mm(fit.rms_mm) + ", misfit_tolerance " +
                     mm(geometry_.misfit_tolerance_mm) + ")";
  if (fit.culprit >= 0) {
    return text + "; cable " + cable_name(fit.culprit, joint_names) +
           " alone explains it: it reads " + mm(fit.alone_excess_mm[fit.culprit]) +
           " more than the others fit (slack or mismeasured?)";
  }
  std::string alone;
  for (int i = 0; i < cable_count(); ++i) {
    if (fit.alone_worst_mm[i] > geometry_.misfit_tolerance_mm) continue;
    alone += (alone.empty() ? "" : ", ") + cable_name(i, joint_names) + " by " +
             formatted_number("%+.3f", fit.alone_excess_mm[i]) + " mm";
  }
  if (alone.empty()) return text + "; no single cable explains it";
  return text +
         "; any one cable could explain it (its reading more than the others fit): " + alone +
         "; with one cable more than coordinates the joints cannot tell which";
}

std::vector<Parameter> CableRobotKinematics::parameters() const {
  static constexpr const char* kComponent[] = {"x", "y", "z"};
  std::vector<Parameter> result;
  for (int i = 0; i < cable_count(); ++i) {
    const RobotCable& cable = geometry_.cables[i];
    const std::string prefix = "cable" + std::to_string(i + 1) + ".";
    for (int k = 0; k < 3; ++k) {
      result.push_back({prefix + "anchor." + kComponent[k],
                        cable.anchor_mm[k],
                        "mm",
                        {"a cable's anchor", BuiltTolerance::machine_size}});
    }
    for (int k = 0; k < 3; ++k) {
      result.push_back({prefix + "attach." + kComponent[k],
                        cable.attach_mm[k],
                        "mm",
                        {"a point on the effector", BuiltTolerance::machine_size}});
    }
    result.push_back({prefix + "offset",
                      cable.offset_mm,
                      "mm",
                      {"a cable's zero", BuiltTolerance::machine_size}});
    // A cable's effective radius on a catalogue pulley moves with its thickness and seating.
    if (cable.pulley_radius_mm > 0.0) {
      result.push_back({prefix + "pulley_radius",
                        cable.pulley_radius_mm,
                        "mm",
                        {"a pulley's radius", BuiltTolerance::own_value, 0.2}});
    }
  }
  return result;
}

void CableRobotKinematics::set_parameters(std::span<const double> values) {
  // Seven per cable, and its pulley's radius where it has one (parameters()).
  std::size_t count = 0;
  for (const RobotCable& cable : geometry_.cables) count += cable.pulley_radius_mm > 0.0 ? 8 : 7;
  if (values.size() != count) {
    throw std::invalid_argument("cable_robot takes " + std::to_string(count) + " parameters");
  }
  CableRobotGeometry geometry = geometry_;
  const double* v = values.data();
  for (RobotCable& cable : geometry.cables) {
    cable.anchor_mm = {v[0], v[1], v[2]};
    cable.attach_mm = {v[3], v[4], v[5]};
    cable.offset_mm = v[6];
    const bool pulley = cable.pulley_radius_mm > 0.0;
    // A pulley's radius stays above 0, so that the parameters keep their layout.
    if (pulley && !(v[7] > 0.0)) {
      throw std::invalid_argument("pulley_radius: must stay above 0 mm, got " +
                                  formatted_number("%.6g", v[7]));
    }
    if (pulley) cable.pulley_radius_mm = v[7];
    v += pulley ? 8 : 7;
  }
  validate_cable_robot_geometry(geometry);
  geometry_ = std::move(geometry);
}

namespace {

RobotCable read_cable(const ModelConfig& config) {
  RobotCable cable;
  cable.anchor_mm = config.length_vector3("anchor");
  if (config.has("attach")) cable.attach_mm = config.length_vector3("attach");
  cable.offset_mm = config.length_or("offset", 0.0);
  cable.swivel_arm_mm = config.length_or("swivel_arm", 0.0);
  if (!(cable.swivel_arm_mm >= 0.0)) config.fail("swivel_arm", "must be a length of 0 or more");
  cable.pulley_radius_mm = config.length_or("pulley_radius", 0.0);
  if (!(cable.pulley_radius_mm >= 0.0)) {
    config.fail("pulley_radius", "must be a length of 0 or more (mm)");
  }
  if (config.has("pulley_axis")) {
    const std::vector<double> axis = config.number_list("pulley_axis");
    if (axis.size() != 3) config.fail("pulley_axis", "needs 3 numbers [x, y, z] (a direction)");
    cable.pulley_axis = {axis[0], axis[1], axis[2]};
    if (!(cable.pulley_axis.norm() > 0.0)) {
      config.fail("pulley_axis",
                  "must be a non-zero direction (from the anchor towards the winch)");
    }
  } else if (cable.pulley_radius_mm > 0.0) {
    config.fail("pulley_radius",
                "needs pulley_axis = [x, y, z], the direction the cable arrives from (from the "
                "anchor towards the winch)");
  }
  if (cable.pulley_radius_mm > 0.0 && cable.swivel_arm_mm > 0.0) {
    config.fail("pulley_radius",
                "not with a swivel_arm (the arm points at the anchor, not at the pulley's "
                "tangent point)");
  }
  return cable;
}

CableRobotGeometry read_geometry(const ModelConfig& config) {
  if (config.has("pulley_radius")) {
    config.fail("pulley_radius", "is per cable: give it in each [[kinematics.cables]]");
  }
  CableRobotGeometry g;
  g.planar = config.boolean_or("planar", false);
  g.cables_follow_z = config.boolean_or("cables_follow_z", false);
  for (const auto& cable_config : config.table_list("cables")) {
    g.cables.push_back(read_cable(*cable_config));
  }
  g.effector_mass_kg = config.number_or("effector_mass", 0.0);
  if (config.has("center_of_mass")) g.center_of_mass_mm = config.length_vector3("center_of_mass");
  if (config.has("tension_limits")) {
    const std::vector<double> limits = config.number_list("tension_limits");
    if (limits.size() != 2) config.fail("tension_limits", "needs 2 numbers [min, max] (N)");
    g.tension_limited = true;
    g.tension_min_N = limits[0];
    g.tension_max_N = limits[1];
  }
  if (config.has("gravity")) {
    const std::vector<double> down = config.number_list("gravity");
    if (down.size() != 3) config.fail("gravity", "needs 3 numbers [gx, gy, gz] (a direction)");
    g.gravity_direction = {down[0], down[1], down[2]};
    g.gravity_given = true;
  }
  if (config.has("preferred_tension")) {
    g.preferred_tension_N = config.number_or("preferred_tension", 0.0);
  }
  g.misfit_tolerance_mm = config.length_or("misfit_tolerance", g.misfit_tolerance_mm);
  read_cable_robot_drive(config, g);
  return g;
}

}  // namespace

std::unique_ptr<Kinematics> make_cable_robot_kinematics(const ModelConfig& config) {
  const CableRobotGeometry geometry = read_geometry(config);
  // A router's or a pen's Z on the effector: a joint that follows the program.
  const geometry::Dof mechanism =
      geometry.planar ? geometry::Dof::planar_xy() : geometry::Dof::translation();
  PassThroughAxes passthrough = PassThroughAxes::read(config, mechanism, geometry::Dof::all());
  try {
    return std::make_unique<CableRobotKinematics>(geometry, std::move(passthrough));
  } catch (const std::invalid_argument& error) {
    // The message starts with the key at fault ("cables: ...").
    const std::string what = error.what();
    const auto colon = what.find(": ");
    std::string key = what.substr(0, colon);
    if (!config.has(key)) key = "cables";
    config.fail(key, what.substr(colon + 2));
  }
}

void CableRobotKinematics::write_config(ModelConfigWriter& out) const {
  const CableRobotGeometry& g = geometry_;
  out.boolean("planar", g.planar);
  if (g.cables_follow_z) out.boolean("cables_follow_z", true);
  if (g.effector_mass_kg != 0.0) out.number("effector_mass", g.effector_mass_kg);
  if (!g.center_of_mass_mm.isZero()) out.length_vector3("center_of_mass", g.center_of_mass_mm);
  if (g.tension_limited) {
    const double limits[2] = {g.tension_min_N, g.tension_max_N};
    out.number_list("tension_limits", limits);
  }
  if (g.gravity_given) out.vector3("gravity", g.gravity_direction);
  if (g.preferred_tension_N) out.number("preferred_tension", *g.preferred_tension_N);
  if (g.misfit_tolerance_mm != CableRobotGeometry{}.misfit_tolerance_mm) {
    out.length("misfit_tolerance", g.misfit_tolerance_mm);
  }
  write_cable_robot_drive(g, out);
  passthrough_.write(out);
  for (const RobotCable& cable : g.cables) {
    ModelConfigWriter& entry = out.table_list_entry("cables");
    entry.length_vector3("anchor", cable.anchor_mm);
    entry.length_vector3("attach", cable.attach_mm);
    if (cable.offset_mm != 0.0) entry.length("offset", cable.offset_mm);
    if (cable.swivel_arm_mm != 0.0) entry.length("swivel_arm", cable.swivel_arm_mm);
    if (cable.pulley_radius_mm != 0.0) {
      entry.length("pulley_radius", cable.pulley_radius_mm);
      entry.vector3("pulley_axis", cable.pulley_axis);
    }
    write_cable_drive(g, cable, entry);
  }
}

void CableRobotKinematics::fixed_parts(std::span<const JointTravel> /*travel*/,
                                       std::vector<SketchLine>& out) const {
  // Each anchor as a small ring in its horizontal plane.
  for (const RobotCable& cable : geometry_.cables) {
    sketch_circle(out, SketchPart::frame, cable.anchor_mm, 20.0, Eigen::Vector3d::UnitX(),
                  Eigen::Vector3d::UnitY());
  }
}

void CableRobotKinematics::moving_parts(const geometry::Pose& pose, const JointVector& /*joints*/,
                                        std::vector<SketchLine>& out) const {
  const Eigen::Vector3d tool = tool_point(pose);
  for (int i = 0; i < cable_count(); ++i) {
    Eigen::Vector3d tie;
    if (!tie_point(i, tool, tie)) continue;
    const RobotCable& cable = geometry_.cables[i];
    PulleyPath path;
    if (cable.pulley_radius_mm > 0.0 && pulley_path(cable, tie, path).ok()) {
      // The pulley turned to face the tie point, and the span from where the cable leaves it.
      const Eigen::Vector3d w = cable.pulley_axis.normalized();
      const double sine = std::sin(path.wrap_rad);
      const bool has_plane = std::abs(sine) > 1e-12;
      if (has_plane) {
        const Eigen::Vector3d e = (path.direction + std::cos(path.wrap_rad) * w) / sine;
        sketch_circle(out, SketchPart::link, cable.anchor_mm + cable.pulley_radius_mm * e,
                      cable.pulley_radius_mm, e, w);
      }
      out.push_back({SketchPart::link, tie - path.span_mm * path.direction, tie});
    } else {
      out.push_back({SketchPart::link, cable.anchor_mm, tie});
    }
    const Eigen::Vector3d pivot = tool + geometry_.cables[i].attach_mm;
    if ((tie - pivot).norm() > 0.0) out.push_back({SketchPart::platform, pivot, tie});
    if ((pivot - tool).norm() > 0.0) out.push_back({SketchPart::platform, tool, pivot});
  }
}

}  // namespace pkm::kinematics
