#include "pkm/motion/feed_limits.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "pkm/motion/feed_rule.hpp"
#include "pkm/motion/plan_sampling.hpp"
#include "pkm/motion/time_optimal.hpp"

namespace pkm::motion {

namespace {

// The part of a joint's max_jerk a piece may use, and the part a junction passed at speed may:
// the rest covers the sampling of its third derivative along the path, every kJointSampleStepMm.
constexpr double kJointJerkShare = 0.85;
constexpr double kJunctionJerkShare = 0.1;

int sample_points(double length_mm) {
  return std::clamp(static_cast<int>(std::ceil(length_mm / kJointSampleStepMm)), 8, 512);
}

double arc_radius(const Segment& s) {
  return std::hypot(s.start[s.first_axis] - s.centre[s.first_axis],
                    s.start[s.second_axis] - s.centre[s.second_axis]);
}

}  // namespace

JointFeedLimit joint_feed_limit(const std::vector<machine::JointSpec>& joints,
                                const kinematics::JointVector& slope,
                                const kinematics::JointVector& curvature, double speed,
                                double velocity_share, double bend_share) {
  JointFeedLimit limit;
  limit.speed_mm_per_s = speed;
  for (int i = 0; i < slope.size(); ++i) {
    const machine::JointSpec& joint = joints[static_cast<std::size_t>(i)];
    const double max_velocity = velocity_share * joint.max_velocity;
    const double bend_acceleration = bend_share * joint.max_acceleration;
    double& allowed = limit.speed_mm_per_s;
    if (slope[i] > 0.0 && max_velocity / slope[i] < allowed) {
      allowed = max_velocity / slope[i];
      limit.joint = i;
      limit.bound = JointBound::velocity;
      limit.derivative = slope[i];
    }
    if (curvature[i] > 0.0 && std::sqrt(bend_acceleration / curvature[i]) < allowed) {
      allowed = std::sqrt(bend_acceleration / curvature[i]);
      limit.joint = i;
      limit.bound = JointBound::acceleration;
      limit.derivative = curvature[i];
    }
  }
  return limit;
}

double FeedLimits::feed_cap(const Segment& segment) const {
  const double max_feed = machine_.cartesian().max_feed_mm_per_s();
  return segment.rapid ? max_feed : std::min(segment.feed_mm_per_s, max_feed);
}

Piece FeedLimits::piece(const Segment& segment, double length) {
  Piece piece;
  piece.segment = segment;
  piece.length = length;
  piece.max_speed = feed_cap(segment);
  if (!(piece.max_speed > 0.0)) {
    throw PlanError(file_, segment.line, "a feed move with no feed rate");
  }
  piece.acceleration = machine_.cartesian().max_acceleration_mm_per_s2;
  if (segment.kind == SegmentKind::arc) limit_by_curvature(piece, arc_radius(segment));
  limit_by_machine(piece);
  return piece;
}

void FeedLimits::limit_by_machine(Piece& piece) {
  if (time_optimal()) return;  // the grid holds the limits, built once the piece is final
  limit_by_joints(piece);
  limit_by_tensions(piece);
}

void FeedLimits::limit_by_curvature(Piece& piece, double radius) const {
  if (radius <= 0.0) return;
  piece.curve_radius_mm = radius;
  if (time_optimal()) {  // the report's numbers: v^2/r may take the whole acceleration
    piece.curve_acceleration_mm_per_s2 = piece.acceleration;
    piece.curve_speed_mm_per_s = std::sqrt(piece.curve_acceleration_mm_per_s2 * radius);
    return;
  }
  piece.curve_acceleration_mm_per_s2 = 0.5 * piece.acceleration;
  piece.curve_speed_mm_per_s = std::sqrt(0.5 * piece.acceleration * radius);
  piece.max_speed = std::min(piece.max_speed, piece.curve_speed_mm_per_s);
  piece.acceleration *= std::sqrt(0.75);
}

void FeedLimits::joint_derivatives(const Piece& piece, kinematics::JointVector& slope,
                                   kinematics::JointVector& curvature,
                                   kinematics::JointVector& third) {
  const Segment& segment = piece.segment;
  const int points = sample_points(piece.length);
  const double step = piece.length / points;
  const int joint_count = static_cast<int>(machine_.joints().size());
  slope = kinematics::JointVector::Zero(joint_count);
  curvature = kinematics::JointVector::Zero(joint_count);
  third = kinematics::JointVector::Zero(joint_count);
  // The joints at the last four points: q[k % 4] at point k.
  std::array<kinematics::JointVector, 4> q;
  for (int k = 0; k <= points; ++k) {
    kinematics::JointVector& here = q[static_cast<std::size_t>(k % 4)];
    joints_along(segment, static_cast<double>(k) / points, here);
    const auto back = [&](int n) -> const kinematics::JointVector& {
      return q[static_cast<std::size_t>((k - n) % 4)];
    };
    for (int i = 0; k >= 1 && i < joint_count; ++i) {
      slope[i] = std::max(slope[i], std::abs(here[i] - back(1)[i]) / step);
      if (k < 2) continue;
      const double second = here[i] - 2.0 * back(1)[i] + back(2)[i];
      curvature[i] = std::max(curvature[i], std::abs(second) / (step * step));
      if (k < 3) continue;
      const double difference = here[i] - 3.0 * back(1)[i] + 3.0 * back(2)[i] - back(3)[i];
      third[i] = std::max(third[i], std::abs(difference) / (step * step * step));
    }
  }
}

void FeedLimits::joints_along(const Segment& segment, double u, kinematics::JointVector& q) {
  const geometry::Vector6d pose = segment.at(u);
  const kinematics::Status status = machine_.inverse(geometry::Pose::from_vector(pose), q);
  if (!status.ok()) leaves_reach(segment);
  require_numbers(machine_, file_, pose, q, segment.line, "along the move");
  if (options_.estimate_only) widen_ranges(report_.joints, q);
}

bool FeedLimits::joints_either_side(const geometry::Vector6d& pose,
                                    const geometry::Vector6d& direction, double step_mm,
                                    kinematics::JointVector& ahead,
                                    kinematics::JointVector& behind) const {
  return machine_.inverse(geometry::Pose::from_vector(pose + step_mm * direction), ahead).ok() &&
         machine_.inverse(geometry::Pose::from_vector(pose - step_mm * direction), behind).ok();
}

// With q(s) a joint along the path, its acceleration is q' s'' + q'' s'^2: bounding |q'| by S
// and |q''| by C over the move, speed^2 C <= kJerkBendShare amax (the feed rule) and accel S <=
// amax - speed^2 C keep it within amax everywhere. A junction passed at speed where the joint's
// rate jumps takes up to 1 - kMoveAccelerationShare of amax within the two periods about it
// (limit_junction), where the ramps' acceleration is zero at the junction and rises at most
// 2 T J: where S 2 T J stays within kMoveAccelerationShare - kJerkBendShare of amax for every
// joint, the move uses all of amax, else kMoveAccelerationShare of it.
void FeedLimits::limit_by_joints(Piece& piece) {
  kinematics::JointVector slope, curvature, third;
  joint_derivatives(piece, slope, curvature, third);
  const double programmed = piece.max_speed;
  piece.joint_slope = slope;
  const JointFeedLimit rule = joint_feed_limit(machine_.joints(), slope, curvature, programmed);
  const double speed = rule.speed_mm_per_s;
  piece.max_speed = speed;
  double shared = piece.acceleration;
  for (int i = 0; i < slope.size(); ++i) {
    const double max_acceleration = machine_.joints()[static_cast<std::size_t>(i)].max_acceleration;
    if (slope[i] > 0.0) {
      const double bend = curvature[i] * speed * speed;
      piece.acceleration = std::min(piece.acceleration, (max_acceleration - bend) / slope[i]);
      shared = std::min(shared, (kMoveAccelerationShare * max_acceleration - bend) / slope[i]);
    }
  }
  limit_jerk_by_joints(piece, slope, curvature, third);
  const double ramp_end = 2.0 * options_.period_s * piece.jerk;  // tool acceleration, mm/s^2
  for (int i = 0; i < slope.size(); ++i) {
    const double max_acceleration = machine_.joints()[static_cast<std::size_t>(i)].max_acceleration;
    if (!(piece.jerk > 0.0) ||
        slope[i] * ramp_end > (kMoveAccelerationShare - kJerkBendShare) * max_acceleration) {
      piece.acceleration = std::min(piece.acceleration, shared);
      break;
    }
  }
  if (rule.joint < 0 || !(speed < programmed * (1.0 - 1e-9))) return;
  report_joint_limit(piece, rule, kJointVelocityMargin, kJerkBendShare);
}

bool FeedLimits::has_joint_jerk(const machine::Machine& machine) {
  return std::any_of(machine.joints().begin(), machine.joints().end(),
                     [](const machine::JointSpec& joint) { return joint.max_jerk > 0.0; });
}

// A joint's jerk along the path is q' s''' + 3 q'' s' s'' + q''' s'^3. With |q'|, |q''|, |q'''|
// bounded by S, C, T over the piece and the piece's |s'| <= v, |s''| <= a and the ramp's
// |s'''| <= J, S J + 3 C v a + T v^3 within kJointJerkShare of max_jerk keeps it within. The
// terms of the speed and the acceleration come first but take at most a quarter of that each
// (the speed, then the acceleration, is lowered until they do): at least half is left to J.
void FeedLimits::limit_jerk_by_joints(Piece& piece, const kinematics::JointVector& slope,
                                      const kinematics::JointVector& curvature,
                                      const kinematics::JointVector& third) const {
  double jerk = options_.jerk_mm_per_s3 > 0.0 ? options_.jerk_mm_per_s3 : 0.0;
  for (int i = 0; i < slope.size(); ++i) {
    const double max_jerk = machine_.joints()[static_cast<std::size_t>(i)].max_jerk;
    if (!(max_jerk > 0.0) || !(slope[i] > 0.0)) continue;
    const double budget = kJointJerkShare * max_jerk;
    double& v = piece.max_speed;
    double& a = piece.acceleration;
    if (third[i] * v * v * v > 0.25 * budget) v = std::cbrt(0.25 * budget / third[i]);
    if (3.0 * curvature[i] * v * a > 0.25 * budget) a = 0.25 * budget / (3.0 * curvature[i] * v);
    const double allowed = (budget - third[i] * v * v * v - 3.0 * curvature[i] * v * a) / slope[i];
    jerk = jerk > 0.0 ? std::min(jerk, allowed) : allowed;
  }
  piece.jerk = jerk;
}

// A joint's rate q' and bend q'' at the start or end (`at_end`) of a piece: one-sided
// differences of second order over three points `step` mm apart.
void FeedLimits::rates_at_end(const Piece& piece, bool at_end, kinematics::JointVector& rate,
                              kinematics::JointVector& bend) const {
  const double step = std::min(1e-3, piece.length / 8.0);
  std::array<kinematics::JointVector, 3> q;
  for (std::size_t k = 0; k < q.size(); ++k) {
    const double distance = static_cast<double>(k) * step;
    const double u = at_end ? 1.0 - distance / piece.length : distance / piece.length;
    const kinematics::Status status =
        machine_.inverse(geometry::Pose::from_vector(piece.segment.at(u)), q[k]);
    if (!status.ok()) leaves_reach(piece.segment);
  }
  const double sign = at_end ? -1.0 : 1.0;  // along the travel
  rate = sign * (-3.0 * q[0] + 4.0 * q[1] - q[2]) / (2.0 * step);
  bend = (q[0] - 2.0 * q[1] + q[2]) / (step * step);
}

// Passing the junction at v, the ramps' tangential acceleration is zero there and a joint's
// velocity jumps by dq' v and its acceleration by dq'' v^2 between two samples T apart: a third
// difference over T^3 of up to dq' v / T^2 + 0.75 dq'' v^2 / T (the largest third differences of
// a kink and of a jump of the second derivative). That within kJunctionJerkShare of max_jerk
// bounds v; the pieces keep the rest.
void FeedLimits::limit_junction_jerk(Piece& before, const Piece& after) const {
  if (!has_joint_jerk(machine_)) return;
  kinematics::JointVector out_rate, out_bend, in_rate, in_bend;
  rates_at_end(before, true, out_rate, out_bend);
  rates_at_end(after, false, in_rate, in_bend);
  const double period = options_.period_s;
  for (int i = 0; i < out_rate.size(); ++i) {
    const double max_jerk = machine_.joints()[static_cast<std::size_t>(i)].max_jerk;
    if (!(max_jerk > 0.0)) continue;
    const double budget = kJunctionJerkShare * max_jerk;
    const double linear = std::abs(in_rate[i] - out_rate[i]) / (period * period);
    const double square = 0.75 * std::abs(in_bend[i] - out_bend[i]) / period;
    // The positive root of square v^2 + linear v = budget.
    const double root = std::sqrt(linear * linear + 4.0 * square * budget);
    if (linear + root > 0.0) {
      before.max_exit_speed = std::min(before.max_exit_speed, 2.0 * budget / (linear + root));
    }
  }
}

void FeedLimits::report_joint_limit(const Piece& piece, const JointFeedLimit& rule,
                                    double velocity_share, double bend_share) {
  FeedLimit limit = feed_limit(piece, rule.joint, rule.speed_mm_per_s, LimitCause::joint);
  const machine::JointSpec& joint = machine_.joints()[static_cast<std::size_t>(rule.joint)];
  const double feed =
      std::min(programmed_feed(piece.segment), machine_.cartesian().max_feed_mm_per_s());
  limit.bound = rule.bound;
  if (rule.bound == JointBound::velocity) {
    limit.needed_at_programmed = rule.derivative * feed;
    limit.usable = velocity_share * joint.max_velocity;
  } else {
    limit.needed_at_programmed = rule.derivative * feed * feed;
    limit.usable = bend_share * joint.max_acceleration;
  }
  report_.feed_limits.push_back(limit);
}

FeedLimit FeedLimits::feed_limit(const Piece& piece, int joint, double speed,
                                 LimitCause cause) const {
  FeedLimit limit;
  limit.line = piece.segment.line;
  limit.joint = joint;
  limit.programmed_mm_per_s = programmed_feed(piece.segment);
  limit.allowed_mm_per_s = speed;
  limit.cause = cause;
  if (piece.curve_radius_mm > 0.0) {
    limit.curve = piece.segment.kind == SegmentKind::blend ? CurveKind::blend : CurveKind::arc;
    limit.previous_line = piece.previous_line;
    limit.radius_mm = piece.curve_radius_mm;
    limit.turn_rad = piece.segment.kind == SegmentKind::blend ? piece.segment.sweep_rad : 0.0;
    limit.curve_allowed_mm_per_s = piece.curve_speed_mm_per_s;
    limit.curve_acceleration_mm_per_s2 = piece.curve_acceleration_mm_per_s2;
  }
  return limit;
}

// A hanging effector's cables: the feed on curves and the acceleration along the move that keep
// their tensions within their limits (tension_limit.hpp), sampled as the joints are.
void FeedLimits::limit_by_tensions(Piece& piece) {
  if (!tension_) return;
  const Segment& segment = piece.segment;
  // Tensions change with the position alone on a line: its ends do for a short one.
  const int points = segment.kind == SegmentKind::line
                         ? std::clamp(static_cast<int>(std::ceil(piece.length / 0.5)), 2, 512)
                         : sample_points(piece.length);
  const TensionBound bound =
      tension_->along(segment, piece.length, points, piece.max_speed, piece.acceleration);
  if (bound.speed_limited) {
    FeedLimit limit =
        feed_limit(piece, bound.excess.cable, bound.speed_mm_per_s, LimitCause::tension);
    limit.slack = bound.excess.slack;
    report_.feed_limits.push_back(limit);
    piece.max_speed = bound.speed_mm_per_s;
  }
  if (bound.acceleration_limited) {
    if (!(bound.acceleration_mm_per_s2 > 0.0)) {
      throw PlanError(file_, segment.line,
                      "no acceleration along the move keeps the cables within their tension "
                      "limits: " +
                          tension_->describe(bound.excess));
    }
    report_.tension_limits.push_back({segment.line, bound.excess.cable, bound.excess.slack,
                                      piece.acceleration, bound.acceleration_mm_per_s2});
    piece.acceleration = bound.acceleration_mm_per_s2;
  }
}

namespace {

// What a junction's change of velocity v * jump (jump per mm of path: a joint's dq/ds, the tool's
// direction) asks of a limit (per s^2): it happens within one period, or, where the moves are
// shorter than v * period (a curve in short chords), once per chord: v jump max(1 / period,
// v / chord). The share of the limit kept for it (20 %, or time-optimally no more than passing
// at `passing` needs) and the highest speed at which it fits in that share.
struct JunctionShare {
  double share = 0.0;
  double speed = 1e300;
};
JunctionShare junction_share(double jump, double limit, double passing, double period, double chord,
                             bool time_optimal) {
  JunctionShare result;
  if (!(jump > 0.0) || !(limit > 0.0)) return result;
  const double most = 1.0 - kMoveAccelerationShare;
  if (!time_optimal) {  // the jerk-limited planner's rule: within a period, 20 %
    result.share = most;
    result.speed = most * limit * period / jump;
    return result;
  }
  const double kick = passing * jump * std::max(1.0 / period, passing / chord);
  result.share = std::min(most, kick / limit);
  result.speed = std::min(result.share * limit * period / jump,
                          std::sqrt(result.share * limit * chord / jump));
  return result;
}

}  // namespace

void FeedLimits::limit_junction(Piece& before, Piece& after) {
  // Each side's rate at the junction along its own tangent (from the segments' numbers, not
  // from poses a hair apart, which rounding swamps on a micrometre's move): central differences
  // of the joints 1e-3 mm either side of the junction's pose along that tangent.
  const geometry::Vector6d at = before.segment.end;
  const geometry::Vector6d out_tangent = before.segment.velocity_at(1.0) / before.length;
  const geometry::Vector6d in_tangent = after.segment.velocity_at(0.0) / after.length;
  const auto rate = [&](const geometry::Vector6d& tangent, const Segment& segment) {
    constexpr double kStepMm = 1e-3;
    kinematics::JointVector ahead, behind;
    if (!joints_either_side(at, tangent, kStepMm, ahead, behind)) leaves_reach(segment);
    return kinematics::JointVector((ahead - behind) / (2.0 * kStepMm));
  };
  const kinematics::JointVector out = rate(out_tangent, before.segment);
  const kinematics::JointVector in = rate(in_tangent, after.segment);
  const Eigen::Vector3d out_direction = heading(before.segment, 1.0);
  const Eigen::Vector3d in_direction = heading(after.segment, 0.0);
  const double passing = passing_speed(before, after);
  const double chord = std::min(before.length, after.length);
  kinematics::JointVector reserve = kinematics::JointVector::Zero(out.size());
  for (int i = 0; i < out.size(); ++i) {
    const JunctionShare joint = junction_share(
        std::abs(in[i] - out[i]), machine_.joints()[static_cast<std::size_t>(i)].max_acceleration,
        passing, options_.period_s, chord, time_optimal());
    reserve[i] = joint.share;
    before.max_exit_speed = std::min(before.max_exit_speed, joint.speed);
  }
  bool turns = false;
  if (tension_) {
    // What the cables feel: the plotter's x y, n cables' x y z.
    turns = tension_->robot() != nullptr ? (in_direction - out_direction).norm() > 0.0
                                         : (in_direction - out_direction).head<2>().norm() > 0.0;
    before.max_exit_speed = tension_->junction_speed(
        before.segment.end, out_direction, in_direction, chord, options_.period_s,
        std::min(before.max_exit_speed, before.max_speed));
  }
  if (!time_optimal()) return;
  // The tool's own change of direction, as a joint's change of rate.
  const JunctionShare tool = junction_share((in_direction - out_direction).norm(),
                                            machine_.cartesian().max_acceleration_mm_per_s2,
                                            passing, options_.period_s, chord, true);
  before.max_exit_speed = std::min(before.max_exit_speed, tool.speed);
  // A sample's second difference sees the change within two periods of the junction.
  before.exit_reserve = after.entry_reserve = reserve;
  before.exit_tool_reserve = after.entry_tool_reserve = tool.share;
  before.exit_reserve_mm = after.entry_reserve_mm = 2.0 * options_.period_s * passing;
  before.exit_tension_reserve = after.entry_tension_reserve = turns;
}

// The fastest a junction can be passed anyway: the moves' feeds, and on a curve (an arc or a
// G64 blend) what the tool's own acceleration allows across it.
double FeedLimits::passing_speed(const Piece& before, const Piece& after) const {
  double passing = std::min(before.max_speed, after.max_speed);
  const double tool = machine_.cartesian().max_acceleration_mm_per_s2;
  for (const Piece* piece : {&before, &after}) {
    if (piece->curve_radius_mm > 0.0) {
      passing = std::min(passing, std::sqrt(tool * piece->curve_radius_mm));
    }
  }
  return passing;
}

void FeedLimits::leaves_reach(const Segment& segment) const {
  const auto pose_at = [&](double u) { return segment.at(u); };
  std::string message = "the move leaves the machine's reach " + machine_.explain_path(pose_at);
  if (tension_) message += tension_->beyond_limits_at_rest(pose_at);
  throw PlanError(file_, segment.line, message);
}

}  // namespace pkm::motion
