#include "pkm/kinematics/rotary_delta.hpp"

#include <Eigen/LU>
#include <array>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>
#include <utility>

namespace pkm::kinematics {

namespace {

// An arm whose forearm is this close (sine of the angle, squared) to in line with it, seen along
// the pivot axis, is at its singularity: the arm's motion no longer moves the platform joint.
constexpr double kMinRelativeLever = 1e-12;
// Forward kinematics' sphere centres this close (relative to the forearm) to one line, or its two
// solutions this close to each other (the three forearms in one plane): singular.
constexpr double kMinRelativeHeight = 1e-9;
// Joint angles forward kinematics accepts as the ones inverse kinematics gives back (rad).
constexpr double kSameAngle = 1e-6;
// Joint residuals of forward kinematics at the level of rounding (rad): no further step.
constexpr double kRoundingAngle = 1e-15;

constexpr double kTwoPi = 2.0 * std::numbers::pi;

// An angle in (-pi, pi], the range rotarydeltakins' arms read in.
double wrapped(double angle_rad) {
  const double angle = std::remainder(angle_rad, kTwoPi);
  return angle <= -std::numbers::pi ? angle + kTwoPi : angle;
}

const std::array<Eigen::Vector3d, RotaryDeltaKinematics::kArms> kArmDirections = {
    Eigen::Vector3d(0.0, -1.0, 0.0),                        // -90 deg: the YZ plane
    Eigen::Vector3d(std::numbers::sqrt3 / 2.0, 0.5, 0.0),   // 30 deg
    Eigen::Vector3d(-std::numbers::sqrt3 / 2.0, 0.5, 0.0),  // 150 deg
};

// The platform joint of an arm seen from the arm's pivot: `out` along the arm's direction, `side`
// along its pivot axis, `up` along z.
struct ArmFrame {
  double out = 0.0;
  double side = 0.0;
  double up = 0.0;
};

ArmFrame arm_frame(const RotaryDeltaGeometry& g, const Eigen::Vector3d& direction,
                   const Eigen::Vector3d& tip) {
  return {tip.dot(direction) + g.platform_radius_mm - g.base_radius_mm,
          direction.x() * tip.y() - direction.y() * tip.x(), tip.z()};
}

}  // namespace

Eigen::Vector3d RotaryDeltaKinematics::arm_direction(int arm) {
  return kArmDirections[static_cast<std::size_t>(arm)];
}

RotaryDeltaKinematics::RotaryDeltaKinematics(const RotaryDeltaGeometry& geometry,
                                             PassThroughAxes passthrough)
    : geometry_(geometry), passthrough_(std::move(passthrough)) {
  validate(geometry_);
  for (const int axis : passthrough_.axes()) {
    if (axis < 3) {
      throw std::invalid_argument("the arms move " + std::string(geometry::kAxisNames[axis]) +
                                  " themselves");
    }
  }
}

void RotaryDeltaKinematics::validate(const RotaryDeltaGeometry& g) {
  if (!(g.base_radius_mm >= 0.0) || !std::isfinite(g.base_radius_mm)) {
    throw std::invalid_argument("base_radius must be a finite length >= 0");
  }
  if (!(g.arm_length_mm > 0.0) || !std::isfinite(g.arm_length_mm)) {
    throw std::invalid_argument("arm_length must be a positive length");
  }
  if (!(g.forearm_length_mm > 0.0) || !std::isfinite(g.forearm_length_mm)) {
    throw std::invalid_argument("forearm_length must be a positive length");
  }
  if (!(g.platform_radius_mm >= 0.0) || !std::isfinite(g.platform_radius_mm)) {
    throw std::invalid_argument("platform_radius must be a finite length >= 0");
  }
}

Status RotaryDeltaKinematics::solve_arm(int arm, const Eigen::Vector3d& tip,
                                        ArmSolution& solution) const {
  const double arm_length = geometry_.arm_length_mm;
  const double forearm = geometry_.forearm_length_mm;
  const ArmFrame p = arm_frame(geometry_, kArmDirections[arm], tip);
  // The elbow is arm_length * (cos q, 0, -sin q) from the pivot, forearm from the platform joint
  // p: |p - elbow|^2 = forearm^2 gives p.out cos q - p.up sin q = reach, a line meeting the
  // elbow's circle where its distance from the pivot, reach, is at most rho = |(p.out, p.up)|.
  const double in_plane_squared = p.out * p.out + p.up * p.up;
  const double reach =
      (arm_length * arm_length + in_plane_squared + p.side * p.side - forearm * forearm) /
      (2.0 * arm_length);
  const double discriminant = in_plane_squared - reach * reach;
  // Written to refuse NaN too: a pose far enough away overflows the squares (inf - inf).
  if (!(discriminant >= 0.0)) return Status::failure(StatusCode::unreachable, arm);
  if (discriminant <= kMinRelativeLever * forearm * forearm) {
    return Status::failure(StatusCode::singular, arm);
  }
  const double root = std::sqrt(discriminant);
  // rho cos(q - alpha) = reach with alpha the direction of p: q = alpha -+ beta, cos beta =
  // reach / rho. The minus sign turns the elbow outward of the pivot-to-joint line
  // (rotarydeltakins' choice wherever the platform is below the pivots, and continuous
  // everywhere). cos q and sin q by the difference formula: one atan2, no sine or cosine, and q
  // in (-pi, pi] as rotarydeltakins reads it.
  const double cos_q = (p.out * reach - p.up * root) / in_plane_squared;
  const double sin_q = (-p.up * reach - p.out * root) / in_plane_squared;
  solution.angle_rad = std::atan2(sin_q, cos_q);
  const Eigen::Vector3d& direction = kArmDirections[arm];
  const Eigen::Vector3d elbow = (geometry_.base_radius_mm + arm_length * cos_q) * direction -
                                Eigen::Vector3d(0.0, 0.0, arm_length * sin_q);
  solution.forearm_mm = tip + geometry_.platform_radius_mm * direction - elbow;
  // forearm . d(elbow)/dq = arm_length * sqrt(discriminant) on the outward branch.
  solution.lever_mm2 = arm_length * root;
  return Status::success();
}

Status RotaryDeltaKinematics::solve_arms(const geometry::Pose& pose,
                                         std::array<ArmSolution, kArms>& arms) const {
  if (!all_finite(pose)) return Status::failure(StatusCode::invalid_input);
  for (int arm = 0; arm < kArms; ++arm) {
    const Status status = solve_arm(arm, pose.position_mm, arms[arm]);
    if (!status.ok()) return status;
  }
  return Status::success();
}

Status RotaryDeltaKinematics::inverse(const geometry::Pose& pose, JointVector& joints) const {
  std::array<ArmSolution, kArms> arms;
  const Status status = solve_arms(pose, arms);
  if (!status.ok()) return status;
  joints.resize(joint_count());
  for (int arm = 0; arm < kArms; ++arm) joints[arm] = arms[arm].angle_rad;
  passthrough_.inverse(pose, joints, kArms);
  return Status::success();
}

Status RotaryDeltaKinematics::inverse_and_jacobian(const geometry::Pose& pose, JointVector& joints,
                                                   JointJacobian& d_joints_d_pose) const {
  std::array<ArmSolution, kArms> arms;
  const Status status = solve_arms(pose, arms);
  if (!status.ok()) return status;
  joints.resize(joint_count());
  d_joints_d_pose.setZero(joint_count(), geometry::kPoseSize);
  for (int arm = 0; arm < kArms; ++arm) {
    joints[arm] = arms[arm].angle_rad;
    // Differentiating |platform joint - elbow(q)|^2 = forearm^2: forearm . (dtip - elbow' dq) = 0.
    d_joints_d_pose.block<1, 3>(arm, 0) = arms[arm].forearm_mm.transpose() / arms[arm].lever_mm2;
  }
  passthrough_.inverse(pose, joints, kArms);
  passthrough_.jacobian(d_joints_d_pose, kArms);
  return Status::success();
}

Status RotaryDeltaKinematics::jacobian(const geometry::Pose& pose,
                                       JointJacobian& d_joints_d_pose) const {
  JointVector joints;
  return inverse_and_jacobian(pose, joints, d_joints_d_pose);
}

int RotaryDeltaKinematics::assembly_mode(const geometry::Pose& pose) const {
  std::array<ArmSolution, kArms> arms;
  if (!solve_arms(pose, arms).ok()) return 0;
  const double determinant = arms[0].forearm_mm.dot(arms[1].forearm_mm.cross(arms[2].forearm_mm));
  return determinant < 0.0 ? 1 : -1;
}

Eigen::Vector3d RotaryDeltaKinematics::shifted_elbow(int arm, double angle_rad) const {
  const RotaryDeltaGeometry& g = geometry_;
  return (g.base_radius_mm - g.platform_radius_mm + g.arm_length_mm * std::cos(angle_rad)) *
             kArmDirections[arm] -
         Eigen::Vector3d(0.0, 0.0, g.arm_length_mm * std::sin(angle_rad));
}

namespace {

// The lower of the two points at distance `radius` from all three centres (rotarydeltakins'
// choice): in the frame ex (centre 0 to 1), ey, ez = ex x ey they are centre 0 + x ex + y ey +-
// h ez. Centres (nearly) on one line, or the two points (nearly) one: singular; no such point:
// unreachable.
Status lower_meeting_point(const std::array<Eigen::Vector3d, 3>& centre, double radius,
                           Eigen::Vector3d& point) {
  const Eigen::Vector3d span_01 = centre[1] - centre[0];
  const double d = span_01.norm();
  if (!(d > kMinRelativeHeight * radius)) return Status::failure(StatusCode::singular);
  const Eigen::Vector3d ex = span_01 / d;
  const Eigen::Vector3d span_02 = centre[2] - centre[0];
  const double i = ex.dot(span_02);
  Eigen::Vector3d ey = span_02 - i * ex;
  const double j = ey.norm();
  if (!(j > kMinRelativeHeight * radius)) return Status::failure(StatusCode::singular);
  ey /= j;
  const Eigen::Vector3d ez = ex.cross(ey);
  const double x = 0.5 * d;
  const double y = (i * i + j * j - i * d) / (2.0 * j);
  const double h_squared = radius * radius - x * x - y * y;
  if (!(h_squared >= 0.0)) return Status::failure(StatusCode::unreachable);  // too far apart
  const double h = std::sqrt(h_squared);
  if (h <= kMinRelativeHeight * radius) return Status::failure(StatusCode::singular);
  point = centre[0] + x * ex + y * ey - std::copysign(h, ez.z()) * ez;
  return Status::success();
}

}  // namespace

Status RotaryDeltaKinematics::forward(const JointVector& joints, geometry::Pose& pose_inout) const {
  if (joints.size() != joint_count() || !all_finite(joints)) {
    return Status::failure(StatusCode::invalid_input);
  }
  Eigen::Vector3d angles;
  std::array<Eigen::Vector3d, kArms> centre;
  for (int arm = 0; arm < kArms; ++arm) {
    angles[arm] = wrapped(joints[arm]);
    centre[arm] = shifted_elbow(arm, angles[arm]);
  }
  geometry::Pose solved = pose_inout;
  const Status met = lower_meeting_point(centre, geometry_.forearm_length_mm, solved.position_mm);
  if (!met.ok()) return met;
  passthrough_.forward(joints, kArms, solved);
  // Both meeting points satisfy the forearms; the joints are those of inverse kinematics only if
  // every elbow is the outer one reaching that point. Then Newton steps on the three arms with
  // the analytic Jacobian restore the digits the closed form loses to cancellation (two steps
  // from its 1e-12 or so; a third only where the Jacobian magnifies rounding).
  Eigen::Vector3d last_good = solved.position_mm;
  for (int step = 0; step < 3; ++step) {
    Eigen::Vector3d residual;
    Eigen::Matrix3d jacobian;
    for (int arm = 0; arm < kArms; ++arm) {
      ArmSolution solution;
      const Status status = solve_arm(arm, solved.position_mm, solution);
      if (!status.ok() && step == 0) return status;
      if (!status.ok()) {
        solved.position_mm = last_good;  // a step into a singular rim: the point before it
        pose_inout = solved;
        return Status::success();
      }
      residual[arm] = wrapped(solution.angle_rad - angles[arm]);
      if (step == 0 && std::abs(residual[arm]) > kSameAngle) {
        return Status::failure(StatusCode::other_assembly, arm);
      }
      jacobian.row(arm) = solution.forearm_mm.transpose() / solution.lever_mm2;
    }
    if (residual.cwiseAbs().maxCoeff() <= kRoundingAngle) break;
    last_good = solved.position_mm;
    solved.position_mm -= jacobian.partialPivLu().solve(residual);
  }
  pose_inout = solved;
  return Status::success();
}

std::string RotaryDeltaKinematics::why_refused(const geometry::Pose& pose,
                                               const Status& status) const {
  if (status.joint < 0 || status.joint >= kArms || !all_finite(pose)) return {};
  const std::string arm = "arm " + std::to_string(status.joint + 1);
  if (status.code == StatusCode::singular) {
    return arm +
           " and its forearm are in line, seen along the arm's pivot axis (the edge of "
           "the reach)";
  }
  if (status.code != StatusCode::unreachable) return {};
  // The elbow's circle comes as near to the platform joint as (rho - arm, side) and goes as far
  // as (rho + arm, side); the forearm's length must lie between. No lengths in the text: the
  // machine file may speak inches, and the pose before it says where.
  const ArmFrame p = arm_frame(geometry_, kArmDirections[status.joint], pose.position_mm);
  const double rho = std::hypot(p.out, p.up);
  const double nearest = std::hypot(rho - geometry_.arm_length_mm, p.side);
  if (geometry_.forearm_length_mm < nearest) {
    return arm +
           " cannot reach it: the platform joint is farther than the forearm's length from "
           "every point of the elbow's circle";
  }
  return arm +
         " cannot reach it: the platform joint is nearer than the forearm's length to "
         "every point of the elbow's circle";
}

std::vector<Parameter> RotaryDeltaKinematics::parameters() const {
  const BuiltAs link{"a link's length", BuiltTolerance::machine_size};
  return {{"base_radius", geometry_.base_radius_mm, "mm", link},
          {"arm_length", geometry_.arm_length_mm, "mm", link},
          {"forearm_length", geometry_.forearm_length_mm, "mm", link},
          {"platform_radius", geometry_.platform_radius_mm, "mm", link}};
}

void RotaryDeltaKinematics::set_parameters(std::span<const double> values) {
  if (values.size() != 4) throw std::invalid_argument("rotary delta takes 4 parameters");
  const RotaryDeltaGeometry geometry{values[0], values[1], values[2], values[3]};
  validate(geometry);
  geometry_ = geometry;
}

std::unique_ptr<Kinematics> make_rotary_delta_kinematics(const ModelConfig& config) {
  RotaryDeltaGeometry geometry;
  geometry.base_radius_mm = config.length("base_radius");
  geometry.arm_length_mm = config.length("arm_length");
  geometry.forearm_length_mm = config.length("forearm_length");
  geometry.platform_radius_mm = config.length("platform_radius");
  const std::pair<const char*, double> checks[] = {
      {"base_radius", geometry.base_radius_mm},
      {"arm_length", geometry.arm_length_mm},
      {"forearm_length", geometry.forearm_length_mm},
      {"platform_radius", geometry.platform_radius_mm}};
  for (const auto& [key, value] : checks) {
    const bool radius = std::string_view(key).ends_with("radius");
    if (!std::isfinite(value) || (radius ? value < 0.0 : value <= 0.0)) {
      config.fail(key, radius ? "must be a length >= 0" : "must be a positive length");
    }
  }
  // A rotary C on the platform (Clavel's fourth axis) is a joint that follows the program.
  PassThroughAxes passthrough =
      PassThroughAxes::read(config, geometry::Dof::translation(), geometry::Dof::all());
  try {
    return std::make_unique<RotaryDeltaKinematics>(geometry, std::move(passthrough));
  } catch (const std::invalid_argument& error) {
    config.fail("base_radius", error.what());
  }
}

void RotaryDeltaKinematics::write_config(ModelConfigWriter& out) const {
  out.length("base_radius", geometry_.base_radius_mm);
  out.length("arm_length", geometry_.arm_length_mm);
  out.length("forearm_length", geometry_.forearm_length_mm);
  out.length("platform_radius", geometry_.platform_radius_mm);
  passthrough_.write(out);
}

void RotaryDeltaKinematics::fixed_parts(std::span<const JointTravel> /*travel*/,
                                        std::vector<SketchLine>& out) const {
  sketch_circle(out, SketchPart::frame, Eigen::Vector3d::Zero(), geometry_.base_radius_mm,
                Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitY());
}

void RotaryDeltaKinematics::moving_parts(const geometry::Pose& pose, const JointVector& joints,
                                         std::vector<SketchLine>& out) const {
  for (int arm = 0; arm < kArms; ++arm) {
    const Eigen::Vector3d outward = arm_direction(arm);
    const Eigen::Vector3d pivot = geometry_.base_radius_mm * outward;
    const Eigen::Vector3d elbow =
        pivot + geometry_.arm_length_mm * (std::cos(joints[arm]) * outward -
                                           std::sin(joints[arm]) * Eigen::Vector3d::UnitZ());
    out.push_back({SketchPart::link, pivot, elbow});
    out.push_back(
        {SketchPart::link, elbow, pose.position_mm + geometry_.platform_radius_mm * outward});
  }
  sketch_circle(out, SketchPart::platform, pose.position_mm, geometry_.platform_radius_mm,
                Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitY());
}

}  // namespace pkm::kinematics
