#include "pkm/kinematics/cable_plotter.hpp"

#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <stdexcept>

#include "pkm/kinematics/closed_form_text.hpp"

namespace pkm::kinematics {

namespace {
// Below this sine of the angle between the cables they are nearly collinear: the pen's height is
// then ill-defined and the tension unbounded.

std::string format(const char* pattern, double a, double b = 0.0, double c = 0.0) {
  char text[256];
  std::snprintf(text, sizeof text, pattern, a, b, c);
  return text;
}

const char* const kCableNames[2] = {"left", "right"};

// A machine-file key and what is wrong with it.
struct GeometryFault : std::invalid_argument {
  GeometryFault(std::string key_name, const std::string& message)
      : std::invalid_argument(message), key(std::move(key_name)) {}
  std::string key;
};
}  // namespace

void validate_cable_plotter_geometry(const CablePlotterGeometry& g) {
  const auto finite = [](const Eigen::Vector2d& v) { return v.allFinite(); };
  if (!finite(g.anchors_mm[0]) || !finite(g.anchors_mm[1])) {
    throw GeometryFault("anchors", "anchors must be finite");
  }
  const double span = g.anchors_mm[1].x() - g.anchors_mm[0].x();
  if (!(span > 0.0)) {
    throw GeometryFault("anchors",
                        span < 0.0 ? format("the right anchor is %g mm left of the left one: list "
                                            "the left anchor first (anchor distance must be a "
                                            "positive length)",
                                            -span)
                                   : format("both anchors are at x %g mm: the cables pull along "
                                            "one line and cannot hold the pen anywhere (anchor "
                                            "distance must be a positive length)",
                                            g.anchors_mm[0].x()));
  }
  if (!std::isfinite(g.cable_offsets_mm[0]) || !std::isfinite(g.cable_offsets_mm[1])) {
    throw GeometryFault("cable_offsets", "cable offsets must be finite");
  }
  if (!(g.pulley_radius_mm >= 0.0) || !(g.pulley_radius_mm < 0.5 * span)) {
    throw GeometryFault(
        "pulley_radius",
        format("%g mm: must be from 0 to less than half the anchors' distance (%g mm); a "
               "20-tooth GT2 pulley is 6.366 mm",
               g.pulley_radius_mm, 0.5 * span));
  }
  if (!finite(g.attach_mm[0]) || !finite(g.attach_mm[1]) || !finite(g.center_of_mass_mm)) {
    throw GeometryFault("effector_attach", "attachment points must be finite");
  }
  if (!(g.effector_mass_kg >= 0.0) || !std::isfinite(g.effector_mass_kg)) {
    throw GeometryFault("effector_mass", "must be a mass of 0 kg or more");
  }
  std::string needing_weight;
  const auto needs = [&](bool given, const char* key) {
    if (given) needing_weight += (needing_weight.empty() ? "" : ", ") + std::string(key);
  };
  needs(!g.attach_mm[0].isZero() || !g.attach_mm[1].isZero(), "effector_attach");
  needs(g.cable_density_kg_per_m > 0.0, "cable_density");
  needs(g.tension_limited, "tension_limits");
  if (!needing_weight.empty() && !(g.effector_mass_kg > 0.0)) {
    throw GeometryFault(
        "effector_mass",
        "must be more than 0 kg: the effector's weight is needed for " + needing_weight);
  }
  if (g.tension_limited && !(g.tension_min_N >= 0.0 && g.tension_min_N < g.tension_max_N)) {
    throw GeometryFault("tension_limits", format("needs 0 <= min < max (N), got [%g, %g]",
                                                 g.tension_min_N, g.tension_max_N));
  }
  // Each cable holds at most the max, so the two hold up at most twice it.
  const double weight_N = g.effector_mass_kg * kStandardGravity_mm_per_s2 * 1e-3;
  if (g.tension_limited && weight_N > 2.0 * g.tension_max_N) {
    throw GeometryFault("effector_mass",
                        format("%g kg weighs %g N, more than two cables at tension_limits' max "
                               "%g N can hold anywhere (is it in grams? the unit is kg)",
                               g.effector_mass_kg, weight_N, g.tension_max_N));
  }
  if (!(g.cable_density_kg_per_m >= 0.0) || !std::isfinite(g.cable_density_kg_per_m)) {
    throw GeometryFault("cable_density", "must be 0 kg/m or more");
  }
  if (!(g.spool_buildup_mm_per_m >= 0.0) || !std::isfinite(g.spool_buildup_mm_per_m)) {
    throw GeometryFault("spool_buildup", "must be 0 mm/m or more");
  }
  if (g.spool_buildup_mm_per_m > 0.0 && !(g.pulley_radius_mm > 0.0)) {
    throw GeometryFault("spool_buildup", "needs the drum's radius: give pulley_radius");
  }
  if (!(g.cable_stretch_mm_per_m_per_N >= 0.0) || !std::isfinite(g.cable_stretch_mm_per_m_per_N)) {
    throw GeometryFault("cable_stiffness", "must be a positive force (EA, N)");
  }
}

CablePlotterKinematics::CablePlotterKinematics(const CablePlotterGeometry& geometry,
                                               PassThroughAxes passthrough)
    : geometry_(geometry), passthrough_(std::move(passthrough)) {
  validate_cable_plotter_geometry(geometry_);
}

Status CablePlotterKinematics::ideal_inverse(const Eigen::Vector2d& pen_mm,
                                             JointVector& joints) const {
  Eigen::Vector2d direction[2];
  for (int cable = 0; cable < 2; ++cable) {
    const Eigen::Vector2d from_anchor = pen_mm - geometry_.anchors_mm[cable];
    const double length = from_anchor.norm();
    if (length == 0.0) return Status::failure(StatusCode::singular);
    direction[cable] = from_anchor / length;
    joints[cable] = length + geometry_.cable_offsets_mm[cable];
  }
  // A cable only pulls: the tensions holding up a weight, t0 u0 + t1 u1 = (0, -1), must both be
  // positive. Above the anchors both would push; outside them one would.
  const double determinant = planar_cross(direction[0], direction[1]);
  const Eigen::Vector2d down(0.0, -1.0);
  const double left = planar_cross(down, direction[1]), right = planar_cross(direction[0], down);
  if (std::abs(determinant) < kMinCableAngleSine) {
    return left * right > 0.0 ? Status::failure(StatusCode::singular)
                              : Status::failure(StatusCode::unreachable);
  }
  if (!(left / determinant > 0.0) && !(right / determinant > 0.0)) {
    return Status::failure(StatusCode::unreachable);
  }
  if (!(right / determinant > 0.0)) return Status::failure(StatusCode::unreachable, 1);
  if (!(left / determinant > 0.0)) return Status::failure(StatusCode::unreachable, 0);
  return Status::success();
}

Status CablePlotterKinematics::solve_balance(const Eigen::Vector2d& pen_mm,
                                             const Eigen::Vector2d& gravity_mm_per_s2,
                                             CableBalance& balance,
                                             std::array<double, 2>& past_top_mm) const {
  // With a spool build-up each drum's radius depends on the cable paid out, which depends on
  // the radius: a fixed point, contracting by about k times the wrap per step.
  CablePlotterGeometry geometry = geometry_;
  const double k = geometry_.spool_buildup_mm_per_m * 1e-3;
  for (int round = 0; round < 30; ++round) {
    const Status status = solve_cable_balance(geometry, pen_mm, gravity_mm_per_s2, balance);
    if (!status.ok()) return status;
    bool settled = true;
    for (int cable = 0; cable < 2; ++cable) {
      past_top_mm[cable] = cable_past_top(geometry, balance, cable);
      const double change = -k * past_top_mm[cable];
      settled = settled && std::abs(change - geometry.radius_change_mm[cable]) <=
                               1e-14 * geometry_.pulley_radius_mm;
      geometry.radius_change_mm[cable] = change;
    }
    if (settled) return Status::success();
    if (!(geometry.radius_mm(0) > 0.0) || !(geometry.radius_mm(1) > 0.0)) break;
  }
  return Status::failure(StatusCode::unreachable, geometry.radius_mm(0) > 0.0 ? 1 : 0);
}

Status CablePlotterKinematics::balance_at(const Eigen::Vector2d& pen_mm, CableBalance& balance,
                                          std::array<double, 2>& past_top_mm,
                                          bool within_limits) const {
  const Status status = solve_balance(pen_mm, Eigen::Vector2d(0.0, -kStandardGravity_mm_per_s2),
                                      balance, past_top_mm);
  // No balance found: the effector cannot hang here (why_refused says why).
  if (status.code == StatusCode::not_converged) return Status::failure(StatusCode::unreachable);
  if (!status.ok()) return status;
  const bool weighed = geometry_.effector_mass_kg > 0.0;
  const StatusCode pushing = weighed ? StatusCode::tension : StatusCode::unreachable;
  if (!balance.pulls[0] && !balance.pulls[1]) return Status::failure(pushing);
  for (int cable = 0; cable < 2; ++cable) {
    if (!balance.pulls[cable]) return Status::failure(pushing, cable);
  }
  for (int cable = 0; cable < 2 && within_limits; ++cable) {
    if (balance.statics.lowest_N[cable] < geometry_.tension_min_N ||
        balance.statics.highest_N[cable] > geometry_.tension_max_N) {
      return Status::failure(StatusCode::tension, cable);
    }
  }
  return Status::success();
}

Status CablePlotterKinematics::inverse(const geometry::Pose& pose, JointVector& joints) const {
  return inverse_within(pose, joints, true);
}

Status CablePlotterKinematics::inverse_within(const geometry::Pose& pose, JointVector& joints,
                                              bool within_limits) const {
  if (!all_finite(pose)) return Status::failure(StatusCode::invalid_input);
  const Eigen::Vector2d pen = pose.position_mm.head<2>();
  joints.resize(joint_count());
  if (geometry_.ideal()) {
    const Status status = ideal_inverse(pen, joints);
    if (!status.ok()) return status;
  } else {
    CableBalance balance;
    std::array<double, 2> past_top{};
    const Status status = balance_at(pen, balance, past_top, within_limits);
    if (!status.ok()) return status;
    for (int cable = 0; cable < 2; ++cable) {
      joints[cable] = cable_joint(geometry_, past_top[cable], cable);
      // The drum would run out of radius before paying out this much.
      if (!std::isfinite(joints[cable])) return Status::failure(StatusCode::unreachable, cable);
    }
  }
  passthrough_.inverse(pose, joints, 2);
  return Status::success();
}

namespace {
// The model as forward kinematics iterates on it: inverse kinematics without the tension
// limits, which say where the machine may go, not where joints put the pen.
class WithoutTensionLimits final : public Kinematics {
 public:
  explicit WithoutTensionLimits(const CablePlotterKinematics& model) : model_(model) {}
  std::string_view type() const override { return model_.type(); }
  int joint_count() const override { return model_.joint_count(); }
  geometry::Dof dof() const override { return model_.dof(); }
  Status inverse(const geometry::Pose& pose, JointVector& joints) const override {
    return model_.inverse_within(pose, joints, false);
  }
  Status forward(const JointVector&, geometry::Pose&) const override {
    return Status::failure(StatusCode::not_converged);
  }
  Status jacobian(const geometry::Pose& pose, JointJacobian& d_joints_d_pose) const override {
    return numerical_jacobian(*this, pose, d_joints_d_pose);
  }
  std::vector<Parameter> parameters() const override { return {}; }
  void set_parameters(std::span<const double>) override {}
  std::unique_ptr<Kinematics> clone() const override {
    return std::make_unique<WithoutTensionLimits>(*this);
  }

 private:
  const CablePlotterKinematics& model_;
};
}  // namespace

namespace {
// Where circles of radii `left` and `right` about `centres` meet on the side gravity picks
// (below the line from the left centre to the right one).
Status lower_intersection(const std::array<Eigen::Vector2d, 2>& centres, double left, double right,
                          Eigen::Vector2d& pen_mm) {
  if (left <= 0.0) return Status::failure(StatusCode::unreachable, 0);
  if (right <= 0.0) return Status::failure(StatusCode::unreachable, 1);
  const Eigen::Vector2d between = centres[1] - centres[0];
  const double d = between.norm();
  if (!(d > 0.0)) return Status::failure(StatusCode::singular);
  const Eigen::Vector2d along = between / d;
  const Eigen::Vector2d below(along.y(), -along.x());
  const double x = (left * left - right * right + d * d) / (2.0 * d);
  const double depth_squared = left * left - x * x;
  if (depth_squared < 0.0) {
    return Status::failure(StatusCode::unreachable, left > right ? 0 : 1);  // circles do not meet
  }
  const double depth = std::sqrt(depth_squared);
  if (depth <= kMinCableAngleSine * d) return Status::failure(StatusCode::singular);
  pen_mm = centres[0] + x * along + depth * below;
  return Status::success();
}
}  // namespace

Status CablePlotterKinematics::ideal_forward(const JointVector& joints,
                                             Eigen::Vector2d& pen_mm) const {
  return lower_intersection(geometry_.anchors_mm, joints[0] - geometry_.cable_offsets_mm[0],
                            joints[1] - geometry_.cable_offsets_mm[1], pen_mm);
}

Status CablePlotterKinematics::forward(const JointVector& joints,
                                       geometry::Pose& pose_inout) const {
  if (joints.size() != joint_count() || !all_finite(joints)) {
    return Status::failure(StatusCode::invalid_input);
  }
  // No refusal outside the anchors here: calibration solves FK with a geometry still slightly
  // off, and the pose the joints imply is the answer it needs; inverse() says what is reachable.
  if (geometry_.ideal()) {
    Eigen::Vector2d pen;
    const Status status = ideal_forward(joints, pen);
    if (!status.ok()) return status;
    pose_inout.position_mm.head<2>() = pen;
    passthrough_.forward(joints, 2, pose_inout);
    return Status::success();
  }
  // As built: Newton on the balance. Newton needs a start where the balance holds, which near a
  // pulley neither the seed nor one guess may be: the seed when it is near where straight cables
  // of the joints' lengths less a quarter turn of wrap meet at the effector's level attachment
  // points (the previous pose along a path), that meeting point, the one without the wrap, then
  // the meeting point lowered by growing steps.
  passthrough_.forward(joints, 2, pose_inout);
  std::array<geometry::Pose, 9> starts;
  int count = 0;
  Eigen::Vector2d wrapped, unwrapped;
  const bool guessed = straight_guess(joints, 0.25, wrapped).ok();
  const bool met = straight_guess(joints, 0.0, unwrapped).ok();
  const Eigen::Vector2d meeting = guessed ? wrapped : unwrapped;
  constexpr double kNearGuess_mm = 50.0;
  const auto add = [&](const Eigen::Vector2d& pen_mm) {
    starts[count] = pose_inout;
    starts[count++].position_mm.head<2>() = pen_mm;
  };
  const Eigen::Vector2d seed = pose_inout.position_mm.head<2>();
  const bool seed_first = !(guessed || met) || (meeting - seed).norm() < kNearGuess_mm;
  if (seed_first) add(seed);
  if (guessed) add(wrapped);
  if (met) add(unwrapped);
  if (!seed_first) add(seed);
  const double lower_step = std::max(1.0, 2.0 * geometry_.pulley_radius_mm);
  for (int k = 0; (guessed || met) && k < 5; ++k) {
    add(meeting - Eigen::Vector2d(0.0, lower_step * std::ldexp(1.0, k)));
  }
  const WithoutTensionLimits unlimited(*this);
  Status result = Status::failure(StatusCode::not_converged);
  for (int k = 0; k < count && !result.ok(); ++k) {
    geometry::Pose start = starts[k];
    result = solve_forward_newton(unlimited, joints, start, forward_options_);
    if (result.ok()) pose_inout = start;
  }
  // Cables too short to meet even straight: say which, as the closed form does.
  if (!result.ok() && !met) return straight_guess(joints, 0.0, unwrapped);
  return result;
}

Status CablePlotterKinematics::straight_guess(const JointVector& joints, double wrap_turns,
                                              Eigen::Vector2d& pen_mm) const {
  const double wrap = geometry_.pulley_radius_mm * wrap_turns * 2.0 * std::numbers::pi;
  // The pen is where the attachment points' circles meet, shifted back by the attachments.
  const std::array<Eigen::Vector2d, 2> centres{geometry_.anchors_mm[0] - geometry_.attach_mm[0],
                                               geometry_.anchors_mm[1] - geometry_.attach_mm[1]};
  if (!(centres[1].x() > centres[0].x())) return Status::failure(StatusCode::singular);
  return lower_intersection(centres, joints[0] - geometry_.cable_offsets_mm[0] - wrap,
                            joints[1] - geometry_.cable_offsets_mm[1] - wrap, pen_mm);
}

Status CablePlotterKinematics::jacobian(const geometry::Pose& pose,
                                        JointJacobian& d_joints_d_pose) const {
  if (!geometry_.ideal()) return numerical_jacobian(*this, pose, d_joints_d_pose);
  d_joints_d_pose.setZero(joint_count(), geometry::kPoseSize);
  passthrough_.jacobian(d_joints_d_pose, 2);
  for (int cable = 0; cable < 2; ++cable) {
    const Eigen::Vector2d from_anchor = pose.position_mm.head<2>() - geometry_.anchors_mm[cable];
    const double length = from_anchor.norm();
    if (length == 0.0) return Status::failure(StatusCode::singular);
    d_joints_d_pose(cable, 0) = from_anchor.x() / length;
    d_joints_d_pose(cable, 1) = from_anchor.y() / length;
  }
  return Status::success();
}

Status CablePlotterKinematics::statics(const geometry::Pose& pose,
                                       const Eigen::Vector2d& acceleration_mm_per_s2,
                                       CableStatics& out) const {
  if (!all_finite(pose) || !acceleration_mm_per_s2.allFinite()) {
    return Status::failure(StatusCode::invalid_input);
  }
  const Eigen::Vector2d gravity =
      Eigen::Vector2d(0.0, -kStandardGravity_mm_per_s2) - acceleration_mm_per_s2;
  CableBalance balance;
  std::array<double, 2> past_top{};
  const Status status = solve_balance(pose.position_mm.head<2>(), gravity, balance, past_top);
  if (!status.ok()) return status;
  out = balance.statics;
  for (int cable = 0; cable < 2; ++cable) {
    if (!balance.pulls[cable]) return Status::failure(StatusCode::tension, cable);
  }
  return Status::success();
}

std::string CablePlotterKinematics::why_refused(const geometry::Pose& pose,
                                                const Status& status) const {
  const Eigen::Vector2d pen = pose.position_mm.head<2>();
  const int cable = status.joint;
  const bool named = cable == 0 || cable == 1;
  switch (status.code) {
    case StatusCode::singular:
      return "on the line through the anchors the cables pull only sideways";
    case StatusCode::unreachable:
    case StatusCode::tension:
      break;
    default:
      return {};
  }
  if (geometry_.ideal()) return why_ideal_refused(pen, cable);
  CableBalance balance;
  std::array<double, 2> past_top{};
  const Status balanced =
      solve_balance(pen, Eigen::Vector2d(0.0, -kStandardGravity_mm_per_s2), balance, past_top);
  if (balanced.code == StatusCode::not_converged) {
    return "the effector finds no balance here (no stable tilt within 86 deg of level): the pen "
           "is above the anchors, or the effector's centre of mass is above its cables";
  }
  if (!named) return why_ideal_refused(pen, cable);
  const std::string name = kCableNames[cable], other = kCableNames[1 - cable];
  if (balanced.code == StatusCode::unreachable) {
    return "the " + name + " cable's end would be on its pulley " +
           format("(radius %g mm), or its drum would run out of cord", geometry_.radius_mm(cable));
  }
  if (!balanced.ok() || !balance.pulls[cable]) {
    return "the " + name + " cable would have to push: the pen is too far " + other +
           " (outside the anchors, seen from the cables' ends)";
  }
  const double lowest = balance.statics.lowest_N[cable], highest = balance.statics.highest_N[cable];
  if (lowest < geometry_.tension_min_N) {
    return "the " + name + " cable would go slack: " +
           format("%.3f N, below tension_limits' min %g N", lowest, geometry_.tension_min_N) +
           " (move the pen away from the " + other + " side or lower, or lower the min)";
  }
  return "the " + name + " cable would be overloaded: " +
         format("%.2f N, above tension_limits' max %g N", highest, geometry_.tension_max_N) +
         " (move the pen lower, away from the top)";
}

std::string CablePlotterKinematics::why_ideal_refused(const Eigen::Vector2d& pen_mm,
                                                      int cable) const {
  const double left_x = geometry_.anchors_mm[0].x(), right_x = geometry_.anchors_mm[1].x();
  if (cable == 1) {
    return format("left of the left anchor (x <= %g) the right cable would have to push", left_x);
  }
  if (cable == 0) {
    return format("right of the right anchor (x >= %g mm) the left cable would have to push",
                  right_x);
  }
  const double lowest = std::min(geometry_.anchors_mm[0].y(), geometry_.anchors_mm[1].y());
  return pen_mm.y() > lowest ? format("the pen would hang above the anchors (y > %g)", lowest)
                             : "both cables would have to push";
}

std::vector<Parameter> CablePlotterKinematics::parameters() const {
  const CablePlotterGeometry& g = geometry_;
  const BuiltAs anchor{"an anchor's position", BuiltTolerance::machine_size};
  // The belt's or cable's effective radius on a catalogue pulley moves with its thickness and
  // how it sits in the teeth: a 20-tooth GT2's pitch radius is 6.37 mm, over the belt 7 mm.
  const BuiltAs pulley{"a pulley's radius", BuiltTolerance::own_value, 0.2};
  const BuiltAs zero{"a cable's zero", BuiltTolerance::machine_size};
  const BuiltAs effector{"a point on the effector", BuiltTolerance::machine_size};
  const BuiltAs property{"a physical property", BuiltTolerance::own_value, 0.5};
  return {{"anchor_left_x", g.anchors_mm[0].x(), "mm", anchor},
          {"anchor_left_y", g.anchors_mm[0].y(), "mm", anchor},
          {"anchor_right_x", g.anchors_mm[1].x(), "mm", anchor},
          {"anchor_right_y", g.anchors_mm[1].y(), "mm", anchor},
          {"pulley_radius", g.pulley_radius_mm, "mm", pulley},
          {"cable_offset_left", g.cable_offsets_mm[0], "mm", zero},
          {"cable_offset_right", g.cable_offsets_mm[1], "mm", zero},
          {"attach_left_x", g.attach_mm[0].x(), "mm", effector},
          {"attach_left_y", g.attach_mm[0].y(), "mm", effector},
          {"attach_right_x", g.attach_mm[1].x(), "mm", effector},
          {"attach_right_y", g.attach_mm[1].y(), "mm", effector},
          {"center_of_mass_x", g.center_of_mass_mm.x(), "mm", effector},
          {"center_of_mass_y", g.center_of_mass_mm.y(), "mm", effector},
          {"effector_mass", g.effector_mass_kg, "kg", property},
          {"cable_density", g.cable_density_kg_per_m, "kg/m", property},
          {"cable_stretch", g.cable_stretch_mm_per_m_per_N, "mm/m/N", property},
          {"spool_buildup", g.spool_buildup_mm_per_m, "mm/m", property}};
}

void CablePlotterKinematics::set_parameters(std::span<const double> values) {
  if (values.size() != 17) throw std::invalid_argument("cable plotter takes 17 parameters");
  CablePlotterGeometry g = geometry_;
  g.anchors_mm[0] = {values[0], values[1]};
  g.anchors_mm[1] = {values[2], values[3]};
  g.pulley_radius_mm = values[4];
  g.cable_offsets_mm = {values[5], values[6]};
  g.attach_mm[0] = {values[7], values[8]};
  g.attach_mm[1] = {values[9], values[10]};
  g.center_of_mass_mm = {values[11], values[12]};
  g.effector_mass_kg = values[13];
  g.cable_density_kg_per_m = values[14];
  g.cable_stretch_mm_per_m_per_N = values[15];
  g.spool_buildup_mm_per_m = values[16];
  validate_cable_plotter_geometry(g);
  geometry_ = g;
}

namespace {

std::array<Eigen::Vector2d, 2> read_pair(const ModelConfig& config, std::string_view key) {
  const std::vector<Eigen::Vector2d> points = config.length_vector2_list(key);
  if (points.size() != 2) config.fail(key, "needs two points: [[left x, y], [right x, y]]");
  return {points[0], points[1]};
}

std::array<double, 2> read_two(const ModelConfig& config, std::string_view key, bool lengths,
                               std::string_view shape) {
  const std::vector<double> values = lengths ? config.length_list(key) : config.number_list(key);
  if (values.size() != 2) config.fail(key, "needs two values: " + std::string(shape));
  return {values[0], values[1]};
}

CablePlotterGeometry read_geometry(const ModelConfig& config) {
  CablePlotterGeometry g;
  if (config.has("anchors") && config.has("anchor_distance")) {
    config.fail("anchors", "give anchors or anchor_distance, not both");
  }
  if (config.has("anchors")) {
    g.anchors_mm = read_pair(config, "anchors");
  } else {
    g.anchors_mm[1] = {config.length("anchor_distance"), 0.0};
  }
  g.pulley_radius_mm = config.length_or("pulley_radius", 0.0);
  if (config.has("cable_offsets")) {
    g.cable_offsets_mm = read_two(config, "cable_offsets", true, "[left, right]");
  }
  if (config.has("effector_attach")) g.attach_mm = read_pair(config, "effector_attach");
  g.effector_mass_kg = config.number_or("effector_mass", 0.0);
  if (config.has("center_of_mass")) {
    const std::array<double, 2> com = read_two(config, "center_of_mass", true, "[x, y]");
    g.center_of_mass_mm = {com[0], com[1]};
  }
  if (config.has("tension_limits")) {
    const std::array<double, 2> limits = read_two(config, "tension_limits", false, "[min, max] N");
    g.tension_limited = true;
    g.tension_min_N = limits[0];
    g.tension_max_N = limits[1];
  }
  g.cable_density_kg_per_m = config.number_or("cable_density", 0.0);
  g.spool_buildup_mm_per_m = config.number_or("spool_buildup", 0.0);
  if (config.has("cable_stiffness")) {
    const double stiffness = config.number("cable_stiffness");
    if (!(stiffness > 0.0)) config.fail("cable_stiffness", "must be a positive force (EA, N)");
    g.cable_stretch_mm_per_m_per_N = 1000.0 / stiffness;
  }
  return g;
}

}  // namespace

std::unique_ptr<Kinematics> make_cable_plotter_kinematics(const ModelConfig& config) {
  const CablePlotterGeometry geometry = read_geometry(config);
  // A pen on a real Z axis (or a drag knife's C) is a joint that follows the program.
  PassThroughAxes passthrough =
      PassThroughAxes::read(config, geometry::Dof::planar_xy(), geometry::Dof::all());
  try {
    return std::make_unique<CablePlotterKinematics>(geometry, std::move(passthrough));
  } catch (const GeometryFault& fault) {
    std::string key = fault.key;
    if (key == "anchors" && !config.has("anchors")) key = "anchor_distance";
    if (key == "effector_attach" && !config.has("effector_attach")) key = "center_of_mass";
    // A missing mass: name the key that needs it.
    for (const char* needs_mass : {"effector_attach", "cable_density", "tension_limits"}) {
      if (key == "effector_mass" && !config.has("effector_mass") && config.has(needs_mass)) {
        key = needs_mass;
      }
    }
    config.fail(key, fault.what());
  }
}

void CablePlotterKinematics::write_config(ModelConfigWriter& out) const {
  const CablePlotterGeometry& g = geometry_;
  if (g.anchors_mm[0].isZero() && g.anchors_mm[1].y() == 0.0) {
    out.length("anchor_distance", g.anchors_mm[1].x());
  } else {
    out.length_vector2_list("anchors", g.anchors_mm);
  }
  if (g.pulley_radius_mm != 0.0) out.length("pulley_radius", g.pulley_radius_mm);
  out.length_list("cable_offsets", g.cable_offsets_mm);
  if (!g.attach_mm[0].isZero() || !g.attach_mm[1].isZero()) {
    out.length_vector2_list("effector_attach", g.attach_mm);
  }
  if (g.effector_mass_kg != 0.0) out.number("effector_mass", g.effector_mass_kg);
  if (!g.center_of_mass_mm.isZero()) {
    out.length_list("center_of_mass", std::span<const double>(g.center_of_mass_mm.data(), 2));
  }
  if (g.tension_limited) {
    const double limits[2] = {g.tension_min_N, g.tension_max_N};
    out.number_list("tension_limits", limits);
  }
  if (g.cable_density_kg_per_m != 0.0) out.number("cable_density", g.cable_density_kg_per_m);
  if (g.spool_buildup_mm_per_m != 0.0) out.number("spool_buildup", g.spool_buildup_mm_per_m);
  if (g.cable_stretch_mm_per_m_per_N != 0.0) {
    out.number("cable_stiffness", 1000.0 / g.cable_stretch_mm_per_m_per_N);
  }
  passthrough_.write(out);
}

std::optional<std::vector<std::string>> CablePlotterKinematics::joint_formulas() const {
  if (!geometry_.ideal()) {
    throw std::invalid_argument(
        "a cable plotter with pulleys, a tilting effector, tension limits or sagging or "
        "stretching cables has no formula: its joints come from a balance of forces");
  }
  // sqrt(((x0 - x)^2) + ((y0 - y)^2)): the cable from each anchor.
  const auto from = [](double anchor, const char* axis) {
    return anchor == 0.0 ? std::string(axis) : "(" + plain_decimal(anchor) + " - " + axis + ")";
  };
  std::vector<std::string> formulas;
  for (int side = 0; side < 2; ++side) {
    const Eigen::Vector2d& anchor = geometry_.anchors_mm[side];
    std::string text =
        "sqrt((" + from(anchor.x(), "x") + "^2) + (" + from(anchor.y(), "y") + "^2))";
    if (geometry_.cable_offsets_mm[side] != 0.0) {
      text += " + " + plain_decimal(geometry_.cable_offsets_mm[side]);
    }
    formulas.push_back(text);
  }
  return formulas;
}

namespace {
Eigen::Vector3d planar(const Eigen::Vector2d& point) {
  return {point.x(), point.y(), 0.0};
}
}  // namespace

void CablePlotterKinematics::fixed_parts(std::span<const JointTravel> /*travel*/,
                                         std::vector<SketchLine>& out) const {
  const CablePlotterGeometry& g = geometry_;
  out.push_back({SketchPart::frame, planar(g.anchors_mm[0]), planar(g.anchors_mm[1])});
  if (g.pulley_radius_mm > 0.0) {
    for (const Eigen::Vector2d& anchor : g.anchors_mm) {
      sketch_circle(out, SketchPart::frame, planar(anchor), g.pulley_radius_mm,
                    Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitY());
    }
  }
}

void CablePlotterKinematics::moving_parts(const geometry::Pose& pose, const JointVector& /*joints*/,
                                          std::vector<SketchLine>& out) const {
  const Eigen::Vector3d pen = pose.position_mm;
  const Eigen::Vector3d pen_xy(pen.x(), pen.y(), 0.0);
  CableStatics balance;
  if (geometry_.effector_mass_kg <= 0.0 || !statics(pose, Eigen::Vector2d::Zero(), balance).ok()) {
    balance.tilt_rad = 0.0;
  }
  const Eigen::Rotation2Dd tilt(balance.tilt_rad);
  std::array<Eigen::Vector3d, 2> tied;
  for (int cable = 0; cable < 2; ++cable) {
    tied[cable] = pen_xy + planar(tilt * geometry_.attach_mm[cable]);
    // The cable leaves its pulley where its line from the tie point touches the circle: drawn
    // from the pulley's centre when the pulley is a point.
    const Eigen::Vector3d anchor = planar(geometry_.anchors_mm[cable]);
    const Eigen::Vector3d away = tied[cable] - anchor;
    const double distance = away.norm();
    const double radius = geometry_.pulley_radius_mm;
    Eigen::Vector3d leave = anchor;
    if (radius > 0.0 && distance > radius) {
      const double angle = std::acos(radius / distance);
      const double side = cable == 0 ? 1.0 : -1.0;  // left cable leaves on the pulley's right
      const Eigen::Rotation2Dd turn(side * angle);
      const Eigen::Vector2d towards = turn * Eigen::Vector2d(away.x(), away.y()).normalized();
      leave = anchor + radius * Eigen::Vector3d(towards.x(), towards.y(), 0.0);
    }
    out.push_back({SketchPart::link, leave, tied[cable]});
  }
  if ((tied[0] - tied[1]).norm() > 0.0) out.push_back({SketchPart::platform, tied[0], tied[1]});
  for (const Eigen::Vector3d& tie : tied) {
    if ((tie - pen_xy).norm() > 0.0) out.push_back({SketchPart::platform, tie, pen_xy});
  }
}

}  // namespace pkm::kinematics
