#include "pkm/motion/planner.hpp"

#include <algorithm>
#include <cmath>
#include <deque>
#include <numbers>

#include "pkm/motion/joint_rates.hpp"
#include "pkm/motion/pen_path.hpp"
#include "pkm/motion/segment.hpp"
#include "pkm/motion/segment_builder.hpp"
#include "pkm/motion/tension_limit.hpp"

namespace pkm::motion {

namespace {

// A change of speed at an acceleration limit and, optionally, a jerk limit (0: none). With a jerk
// limit the acceleration rises and falls linearly (an S-curve); its velocity is symmetric about
// the ramp's middle, so a ramp covers the mean of its two speeds times its duration.
struct Ramp {
  double acceleration = 0.0;
  double jerk = 0.0;

  // The acceleration reached and the time at constant acceleration, for a change of `change`.
  void shape(double change, double& peak_acceleration, double& jerk_s, double& constant_s) const {
    peak_acceleration =
        jerk > 0.0 ? std::min(acceleration, std::sqrt(change * jerk)) : acceleration;
    jerk_s = jerk > 0.0 ? peak_acceleration / jerk : 0.0;
    constant_s = peak_acceleration > 0.0 ? std::max(0.0, change / peak_acceleration - jerk_s) : 0.0;
  }
  double time(double from, double to) const {
    double peak = 0.0, jerk_s = 0.0, constant_s = 0.0;
    shape(std::abs(to - from), peak, jerk_s, constant_s);
    return 2.0 * jerk_s + constant_s;
  }
  double distance(double from, double to) const { return 0.5 * (from + to) * time(from, to); }
  // The highest speed reachable from `from` within `length` (or the highest speed from which
  // `from` can be reached: the same by symmetry).
  double reachable(double from, double length) const {
    if (jerk <= 0.0) return std::sqrt(from * from + 2.0 * acceleration * length);
    double low = from, high = from + std::sqrt(2.0 * acceleration * length) + 1.0;
    for (int i = 0; i < 60; ++i) {
      const double middle = 0.5 * (low + high);
      (distance(from, middle) <= length ? low : high) = middle;
    }
    return low;
  }
  // Distance covered `t` seconds into the ramp from `from` to `to`.
  double position(double from, double to, double t) const {
    const double sign = to >= from ? 1.0 : -1.0;
    double peak = 0.0, jerk_s = 0.0, constant_s = 0.0;
    shape(std::abs(to - from), peak, jerk_s, constant_s);
    if (jerk_s == 0.0) return from * t + 0.5 * sign * peak * t * t;
    const double j = sign * jerk;
    if (t <= jerk_s) return from * t + j * t * t * t / 6.0;
    const double v1 = from + 0.5 * j * jerk_s * jerk_s;
    const double x1 = from * jerk_s + j * jerk_s * jerk_s * jerk_s / 6.0;
    if (t <= jerk_s + constant_s) {
      const double u = t - jerk_s;
      return x1 + v1 * u + 0.5 * sign * peak * u * u;
    }
    const double v2 = v1 + sign * peak * constant_s;
    const double x2 = x1 + v1 * constant_s + 0.5 * sign * peak * constant_s * constant_s;
    const double u = std::min(t - jerk_s - constant_s, jerk_s);
    return x2 + v2 * u + 0.5 * sign * peak * u * u - j * u * u * u / 6.0;
  }
};

// Speed profile along one piece: from the entry speed up to the peak, cruise, and down to the
// exit speed. The planner's passes guarantee that the exit speed can be reached from the entry
// speed within the piece.
struct Profile {
  double length = 0.0, entry_speed = 0.0, peak_speed = 0.0, exit_speed = 0.0;
  Ramp ramp;
  double accelerate_s = 0.0, cruise_s = 0.0, brake_s = 0.0, duration_s = 0.0;
  double accelerate_mm = 0.0, cruise_mm = 0.0;

  static Profile make(double length, double entry, double exit, double max_speed,
                      const Ramp& ramp) {
    Profile p;
    p.length = length;
    p.entry_speed = entry;
    p.exit_speed = exit;
    p.ramp = ramp;
    if (length <= 0.0) return p;
    const auto fits = [&](double peak) {
      return ramp.distance(entry, peak) + ramp.distance(peak, exit) <= length;
    };
    double low = std::max(entry, exit), high = std::max(low, max_speed);
    if (fits(high)) {
      low = high;
    } else {
      for (int i = 0; i < 60; ++i) {
        const double middle = 0.5 * (low + high);
        (fits(middle) ? low : high) = middle;
      }
    }
    p.peak_speed = low;
    p.accelerate_s = ramp.time(entry, p.peak_speed);
    p.brake_s = ramp.time(p.peak_speed, exit);
    p.accelerate_mm = ramp.distance(entry, p.peak_speed);
    p.cruise_mm = std::max(0.0, length - p.accelerate_mm - ramp.distance(p.peak_speed, exit));
    p.cruise_s = p.peak_speed > 0.0 ? p.cruise_mm / p.peak_speed : 0.0;
    p.duration_s = p.accelerate_s + p.cruise_s + p.brake_s;
    return p;
  }

  double distance(double t) const {
    if (t <= 0.0) return 0.0;
    if (t >= duration_s) return length;
    if (t < accelerate_s) return ramp.position(entry_speed, peak_speed, t);
    if (t < accelerate_s + cruise_s) return accelerate_mm + peak_speed * (t - accelerate_s);
    const double braking = t - accelerate_s - cruise_s;
    return std::min(length,
                    accelerate_mm + cruise_mm + ramp.position(peak_speed, exit_speed, braking));
  }
};

// A move ready for speed planning: its limits, and the speeds it is entered and left at.
struct Piece {
  Segment segment;
  double length = 0.0;
  double max_speed = 0.0;
  double acceleration = 0.0;
  bool stop_after = false;
  double max_exit_speed = 1e300;  // where the joints' rates jump at the junction to the next
  double entry_speed = 0.0, exit_speed = 0.0;
  JointVector joint_slope;  // largest |dq/ds| of each joint along the piece (per mm)
  // On an arc or a corner blend: its radius, and the speed and acceleration v^2/r may take
  // (limit_by_curvature); the line before a blend's corner.
  double curve_radius_mm = 0.0;
  double curve_speed_mm_per_s = 0.0;
  double curve_acceleration_mm_per_s2 = 0.0;
  int previous_line = 0;
};

// Direction of travel from fraction a to b of a segment's position path (in XY where the
// machine does not move Z).
Eigen::Vector3d direction(const Segment& segment, double a, double b) {
  Eigen::Vector3d d = segment.at(b).head<3>() - segment.at(a).head<3>();
  if (segment.z_free) d.z() = 0.0;
  const double n = d.norm();
  return n > 0.0 ? Eigen::Vector3d(d / n) : Eigen::Vector3d::Zero();
}

// Direction of travel at the start (at_end false) or end of a segment.
Eigen::Vector3d tangent(const Segment& segment, bool at_end) {
  return at_end ? direction(segment, 1.0 - 1e-6, 1.0) : direction(segment, 0.0, 1e-6);
}

// G64 without P still keeps corners this close to the programmed path (mm).
constexpr double kDefaultBlendTolerance = 0.01;
// Directions within this angle (rad) join without a blend or a stop.
constexpr double kTangentAngle = 1e-3;
// Pieces held back for look-ahead: enough to brake from any feed over CAM-sized segments.
constexpr std::size_t kWindow = 512;
constexpr std::size_t kKeep = 256;
// Share of a joint's acceleration limit the moves may use; the rest absorbs the change of its
// rate at junctions passed without stopping, which happens within one servo period.
constexpr double kMoveAccelerationShare = 0.8;

class Planner {
 public:
  Planner(const Machine& machine, const PlanOptions& options, SampleSink& sink, std::string file)
      : machine_(machine),
        options_(options),
        sink_(sink),
        file_(std::move(file)),
        builder_((options.start ? *options.start : machine.home()).as_vector(), options.origin,
                 options.great_circle_attitude),
        pen_(machine.tool().z == ToolZ::pen),
        pen_path_(machine),
        tension_(TensionLimit::of(machine.kinematics())) {
    builder_.set_z_free(!machine.kinematics().dof().controls(static_cast<int>(Axis::z)));
    builder_.set_file(file_);
    pose_ = builder_.pose();
    const int joints = static_cast<int>(machine.joints().size());
    report_.joints.resize(static_cast<std::size_t>(joints));
    JointVector start_joints;
    const Status status = machine_.inverse(Pose::from_vector(pose_), start_joints);
    if (!status.ok()) {
      throw PlanError(
          file_, 0,
          "the start pose is not usable: " + machine_.explain(Pose::from_vector(pose_), status));
    }
    require_numbers(pose_, start_joints, 0, "at the start pose");
    for (int i = 0; i < joints; ++i) {
      report_.joints[static_cast<std::size_t>(i)].min = start_joints[i];
      report_.joints[static_cast<std::size_t>(i)].max = start_joints[i];
    }
    emit(0.0, 0, pose_);  // t = 0: where the machine starts
  }

  void on_canon(const gcode::Canon& canon) {
    for (const Segment& segment : builder_.take(canon)) {
      if (segment.kind == SegmentKind::dwell) {
        flush(true);
        entry_speed_ = 0.0;
        run_dwell(segment);
      } else if (pen_) {
        add_with_pen(segment);
      } else {
        add(segment);
      }
    }
  }

  PlanReport finish() {
    flush(true);
    if (!std::isfinite(time_)) {
      throw PlanError(file_, last_line_,
                      "the job would take forever: check the machine's feeds and accelerations");
    }
    // The last sample lands exactly on the end of the program.
    if (last_sample_time_ < time_) emit(time_, last_line_, pose_);
    report_.duration_s = time_;
    if (const auto warning = pen_path_.warning(); pen_ && warning) {
      report_.warnings.push_back(*warning);
    }
    return report_;
  }

 private:
  // Where a move leaves the reach, and on a cable machine how far its tensions go beyond their
  // limits along it.
  [[noreturn]] void leaves_reach(const Segment& segment) const {
    const auto pose_at = [&](double u) { return segment.at(u); };
    std::string message = "the move leaves the machine's reach " + machine_.explain_path(pose_at);
    if (tension_) message += tension_->beyond_limits_at_rest(pose_at);
    throw PlanError(file_, segment.line, message);
  }

  static int sample_points(double length_mm) {
    return std::clamp(static_cast<int>(std::ceil(length_mm / 0.5)), 8, 512);
  }

  // The feed and acceleration that keep every joint within its limits along a move. With q(s)
  // a joint along the path, its acceleration is q' s'' + q'' s'^2: bounding |q'| by S and |q''|
  // by C over the move (sampled every 0.5 mm), speed^2 C <= amax / 2 and accel S <= amax - speed^2
  // C keep it within amax everywhere. A 1 % margin covers the sampling of the derivatives.
  void limit_by_joints(Piece& piece) {
    const Segment& segment = piece.segment;
    const double length = piece.length;
    double& speed = piece.max_speed;
    double& acceleration = piece.acceleration;
    constexpr double kMargin = 0.99;
    // Joint accelerations along the moves use this share of each limit; the rest is left for the
    // change of rate at junctions where the moves join without stopping (limit_junction).
    const int points = sample_points(length);
    const double step = length / points;
    const int joint_count = static_cast<int>(machine_.joints().size());
    JointVector slope_max = JointVector::Zero(joint_count);
    JointVector curvature_max = JointVector::Zero(joint_count);
    JointVector previous, current, next;
    const auto joints_at = [&](int k, JointVector& q) {
      const Pose pose = Pose::from_vector(segment.at(static_cast<double>(k) / points));
      const Status status = machine_.inverse(pose, q);
      if (!status.ok()) leaves_reach(segment);
      require_numbers(pose.as_vector(), q, segment.line, "along the move");
      if (options_.estimate_only) widen_ranges(q);
    };
    joints_at(0, previous);
    joints_at(1, current);
    for (int k = 1; k <= points; ++k) {
      if (k < points) joints_at(k + 1, next);
      for (int i = 0; i < joint_count; ++i) {
        slope_max[i] = std::max(slope_max[i], std::abs(current[i] - previous[i]) / step);
        if (k < points) {
          curvature_max[i] = std::max(
              curvature_max[i], std::abs(next[i] - 2.0 * current[i] + previous[i]) / (step * step));
        }
      }
      previous = current;
      current = next;
    }
    const double programmed = speed;
    piece.joint_slope = slope_max;
    int limiting = -1;
    JointBound bound = JointBound::velocity;
    for (int i = 0; i < joint_count; ++i) {
      const JointSpec& joint = machine_.joints()[static_cast<std::size_t>(i)];
      const double max_velocity = kMargin * joint.max_velocity;
      const double max_acceleration = kMoveAccelerationShare * joint.max_acceleration;
      if (slope_max[i] > 0.0 && max_velocity / slope_max[i] < speed) {
        speed = max_velocity / slope_max[i];
        limiting = i;
        bound = JointBound::velocity;
      }
      if (curvature_max[i] > 0.0 && std::sqrt(0.5 * max_acceleration / curvature_max[i]) < speed) {
        speed = std::sqrt(0.5 * max_acceleration / curvature_max[i]);
        limiting = i;
        bound = JointBound::acceleration;
      }
    }
    for (int i = 0; i < joint_count; ++i) {
      const double max_acceleration =
          kMoveAccelerationShare * machine_.joints()[static_cast<std::size_t>(i)].max_acceleration;
      if (slope_max[i] > 0.0) {
        const double left = max_acceleration - curvature_max[i] * speed * speed;
        acceleration = std::min(acceleration, left / slope_max[i]);
      }
    }
    if (limiting >= 0 && speed < programmed * (1.0 - 1e-9)) {
      FeedLimit limit = feed_limit(piece, limiting, speed, LimitCause::joint);
      const JointSpec& joint = machine_.joints()[static_cast<std::size_t>(limiting)];
      const double feed = std::min(programmed_feed(segment), max_feed());
      limit.bound = bound;
      if (bound == JointBound::velocity) {
        limit.needed_at_programmed = slope_max[limiting] * feed;
        limit.usable = kMargin * joint.max_velocity;
      } else {
        limit.needed_at_programmed = curvature_max[limiting] * feed * feed;
        limit.usable = 0.5 * kMoveAccelerationShare * joint.max_acceleration;
      }
      report_.feed_limits.push_back(limit);
    }
  }

  double programmed_feed(const Segment& segment) const {
    return segment.rapid ? max_feed() : segment.feed_mm_per_s;
  }
  double max_feed() const { return machine_.cartesian().max_feed_mm_per_min / 60.0; }

  // The report's entry for a move whose feed `joint` (or cable) lowered to `speed`, with the
  // curve it is, if any.
  FeedLimit feed_limit(const Piece& piece, int joint, double speed, LimitCause cause) const {
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
  // their tensions within their limits (tension_limit.hpp), every 0.5 mm as limit_by_joints.
  void limit_by_tensions(Piece& piece) {
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
                            describe_excess(tension_->kinematics(), bound.excess));
      }
      report_.tension_limits.push_back({segment.line, bound.excess.cable, bound.excess.slack,
                                        piece.acceleration, bound.acceleration_mm_per_s2});
      piece.acceleration = bound.acceleration_mm_per_s2;
    }
  }

  // Everything that bounds a move's feed and acceleration along it.
  void limit_by_machine(Piece& piece) {
    limit_by_joints(piece);
    limit_by_tensions(piece);
  }

  void add(const Segment& segment) {
    last_line_ = segment.line;
    Piece piece;
    piece.segment = segment;
    piece.length = segment.length();
    if (piece.length <= 0.0) {
      pose_ = segment.end;  // a move to where the tool is: nothing to plan
      return;
    }
    piece.max_speed = segment.rapid ? max_feed() : std::min(segment.feed_mm_per_s, max_feed());
    if (!(piece.max_speed > 0.0)) {
      throw PlanError(file_, segment.line, "a feed move with no feed rate");
    }
    piece.acceleration = machine_.cartesian().max_acceleration_mm_per_s2;
    if (segment.kind == SegmentKind::arc) limit_by_curvature(piece, arc_radius(segment));
    limit_by_machine(piece);
    if (!pieces_.empty()) join(pieces_.back(), piece);
    pieces_.push_back(piece);
    pose_ = segment.end;
    if (pieces_.size() >= kWindow) flush(false);
  }

  static double arc_radius(const Segment& s) {
    return std::hypot(s.start[s.first_axis] - s.centre[s.first_axis],
                      s.start[s.second_axis] - s.centre[s.second_axis]);
  }

  // On a curve of radius r the tool's acceleration is the tangential one plus v^2/r across:
  // v^2/r <= a/2 and a tangential of 0.866 a keep the sum within a.
  static void limit_by_curvature(Piece& piece, double radius) {
    if (radius <= 0.0) return;
    piece.curve_radius_mm = radius;
    piece.curve_acceleration_mm_per_s2 = 0.5 * piece.acceleration;
    piece.curve_speed_mm_per_s = std::sqrt(0.5 * piece.acceleration * radius);
    piece.max_speed = std::min(piece.max_speed, piece.curve_speed_mm_per_s);
    piece.acceleration *= std::sqrt(0.75);
  }

  // Joins `next` to `previous`: straight on where they are tangent, through a blend arc within
  // the G64 tolerance where two lines meet at an angle, with a stop everywhere else.
  void join(Piece& previous, Piece& next) {
    const Eigen::Vector3d out = tangent(previous.segment, true);
    const Eigen::Vector3d in = tangent(next.segment, false);
    const bool same_kind = previous.segment.rapid == next.segment.rapid;
    // A blend rounds corners in 3D: a ramp in a Z the machine does not move would tilt it.
    const auto ramps_free_z = [](const Segment& s) { return s.z_free && s.start[2] != s.end[2]; };
    if (builder_.path_mode() != 64 || !same_kind || out.isZero() || in.isZero() ||
        ramps_free_z(previous.segment) || ramps_free_z(next.segment)) {
      previous.stop_after = true;
      return;
    }
    const double angle = std::acos(std::clamp(out.dot(in), -1.0, 1.0));
    if (angle <= kTangentAngle) {
      // Tangent: the speed carries over, as far as the joints' rates allow.
      limit_junction(previous, next.segment, next.length);
      return;
    }
    if (previous.segment.kind != SegmentKind::line || next.segment.kind != SegmentKind::line ||
        angle > std::numbers::pi - 1e-3) {
      previous.stop_after = true;
      return;
    }
    // The arc tangent to both lines that strays at most the tolerance from them (its middle is
    // r (1 - cos(angle/2)) from either line) and takes at most half of either.
    const double half = angle / 2.0;
    const double tolerance = builder_.blend_tolerance_mm() > 0.0 ? builder_.blend_tolerance_mm()
                                                                 : kDefaultBlendTolerance;
    const double tolerance_radius = tolerance / (1.0 - std::cos(half));
    const double length_radius = 0.5 * std::min(previous.length, next.length) / std::tan(half);
    const double radius = std::min(tolerance_radius, length_radius);
    if (!(radius > 1e-9)) {
      previous.stop_after = true;
      return;
    }
    const double cut = radius * std::tan(half);
    const Eigen::Vector3d corner = previous.segment.end.head<3>();
    Segment blend;
    blend.kind = SegmentKind::blend;
    blend.line = next.segment.line;
    blend.rapid = next.segment.rapid;
    blend.feed_mm_per_s = next.segment.feed_mm_per_s;
    blend.start = previous.segment.at((previous.length - cut) / previous.length);
    blend.end = next.segment.at(cut / next.length);
    blend.centre = corner + (in - out).normalized() * (radius / std::cos(half));
    blend.radius_mm = radius;
    blend.axis_u = (blend.start.head<3>() - blend.centre).normalized();
    blend.axis_v = out;
    blend.sweep_rad = angle;
    previous.segment.end = blend.start;
    previous.length -= cut;
    next.segment.start = blend.end;
    next.length -= cut;
    Piece piece;
    piece.segment = blend;
    piece.length = blend.length();
    piece.max_speed = std::min(previous.max_speed, next.max_speed);
    piece.acceleration = std::min(previous.acceleration, next.acceleration);
    piece.previous_line = previous.segment.line;
    limit_by_curvature(piece, radius);
    limit_by_machine(piece);
    limit_junction(previous, blend, piece.length);
    limit_junction(piece, next.segment, next.length);
    pieces_.push_back(piece);
  }

  // A joint whose rate along the path (dq/ds) differs across a junction would change its
  // velocity in one servo period: the junction speed keeps that change within what its
  // acceleration allows in a period. So does the effector's velocity, which a hanging effector's
  // cables feel (TensionLimit::junction_speed).
  void limit_junction(Piece& before, const Segment& after, double after_length) {
    // Over a thousandth of a mm: a blend's end is its next line's start, not its own formula's
    // end to the last bit.
    const auto ends = [](double length, bool at_end, double& from, double& to) {
      const double ds = std::min(1e-3, 0.01 * length);
      from = at_end ? 1.0 - ds / length : 0.0;
      to = at_end ? 1.0 : ds / length;
      return ds;
    };
    const auto rate = [&](const Segment& segment, double length, bool at_end) {
      double from = 0.0, to = 0.0;
      const double ds = ends(length, at_end, from, to);
      JointVector q0, q1;
      const Status a = machine_.inverse(Pose::from_vector(segment.at(from)), q0);
      const Status b = machine_.inverse(Pose::from_vector(segment.at(to)), q1);
      if (!a.ok() || !b.ok()) leaves_reach(segment);
      return JointVector((q1 - q0) / ds);
    };
    const JointVector out = rate(before.segment, before.length, true);
    const JointVector in = rate(after, after_length, false);
    for (int i = 0; i < out.size(); ++i) {
      const double jump = std::abs(in[i] - out[i]);
      if (jump <= 0.0) continue;
      const double allowed = (1.0 - kMoveAccelerationShare) *
                             machine_.joints()[static_cast<std::size_t>(i)].max_acceleration *
                             options_.period_s / jump;
      before.max_exit_speed = std::min(before.max_exit_speed, allowed);
    }
    if (tension_) {
      double out_from = 0.0, out_to = 0.0, in_from = 0.0, in_to = 0.0;
      ends(before.length, true, out_from, out_to);
      ends(after_length, false, in_from, in_to);
      before.max_exit_speed = tension_->junction_speed(
          before.segment.end, direction(before.segment, out_from, out_to),
          direction(after, in_from, in_to), std::min(before.length, after_length),
          options_.period_s, std::min(before.max_exit_speed, before.max_speed));
    }
  }

  // Plans the speeds of the buffered pieces (braking to a stop at the end of the buffer, which
  // later pieces can only relax) and emits them; keeps the last kKeep for the next look-ahead
  // unless `all`.
  void flush(bool all) {
    const std::size_t n = pieces_.size();
    if (n == 0) return;
    // Backward: the fastest each piece may be entered and still brake in time.
    double exit = 0.0;
    for (std::size_t i = n; i-- > 0;) {
      Piece& p = pieces_[i];
      if (p.stop_after) exit = 0.0;
      exit = std::min(exit, p.max_exit_speed);
      p.exit_speed = exit;
      double entry = ramp_for(p).reachable(exit, p.length);
      entry = std::min(entry, p.max_speed);
      if (i > 0) entry = std::min(entry, pieces_[i - 1].max_speed);
      p.entry_speed = entry;
      exit = entry;
    }
    // Forward: the fastest each piece can be reached.
    double speed = entry_speed_;
    for (std::size_t i = 0; i < n; ++i) {
      Piece& p = pieces_[i];
      p.entry_speed = std::min(p.entry_speed, speed);
      p.exit_speed = std::min(p.exit_speed, ramp_for(p).reachable(p.entry_speed, p.length));
      speed = p.exit_speed;
    }
    const std::size_t emit_count = all ? n : n - std::min(n, kKeep);
    for (std::size_t i = 0; i < emit_count; ++i) {
      run_piece(pieces_.front());
      entry_speed_ = pieces_.front().exit_speed;
      pieces_.pop_front();
    }
  }

  Ramp ramp_for(const Piece& piece) const {
    return Ramp{piece.acceleration, options_.jerk_mm_per_s3};
  }

  void run_piece(const Piece& piece) {
    const Segment& segment = piece.segment;
    if (segment.kind != SegmentKind::line ||
        (segment.end.head<3>() - segment.start.head<3>()).norm() > 0.0) {
      report_.path_length_mm += piece.length;  // moves of the angles alone are no path
    }
    const Profile profile = Profile::make(piece.length, piece.entry_speed, piece.exit_speed,
                                          piece.max_speed, ramp_for(piece));
    if (options_.estimate_only) {
      for (int i = 0; i < piece.joint_slope.size(); ++i) {
        double& peak = report_.joints[static_cast<std::size_t>(i)].peak_velocity;
        peak = std::max(peak, piece.joint_slope[i] * profile.peak_speed);
      }
    }
    sample_until(time_ + profile.duration_s, segment.line,
                 [&](double t) { return segment.at(profile.distance(t - time_) / piece.length); });
  }

  void run_dwell(const Segment& segment) {
    last_line_ = segment.line;
    sample_until(time_ + segment.dwell_s, segment.line, [&](double) { return segment.start; });
  }

  // A move on a machine with a pen channel: wherever the pen changes along it (pen_path.hpp)
  // the machine stops, the pen goes down or up (samples carry the new state from then on) and
  // the pen's delay passes; the move runs on from there.
  void add_with_pen(const Segment& segment) {
    double from = 0.0;
    for (const PenChange& change : pen_path_.follow(segment)) {
      if (change.u > from) add(segment.part(from, change.u));
      flush(true);
      entry_speed_ = 0.0;
      pen_down_ = change.down;
      ++report_.pen_changes;
      last_line_ = segment.line;
      const Vector6d here = pose_;
      sample_until(time_ + machine_.tool().delay_s, segment.line, [&](double) { return here; });
      from = change.u;
    }
    add(from > 0.0 ? segment.part(from, 1.0) : segment);
  }

  // Samples on the multiples of the period up to `end` (time division), then moves on.
  template <class PoseAt>
  void sample_until(double end, int line, const PoseAt& pose_at) {
    const double period = options_.period_s;
    const long stop = first_sample_at_or_after(end);
    if (options_.max_samples > 0 && !options_.estimate_only &&
        report_.samples + (stop - next_sample_) > options_.max_samples) {
      throw PlanError(file_, line,
                      "the plan would pass " + std::to_string(options_.max_samples) +
                          " samples here (t = " + std::to_string(end) +
                          " s): estimate the job first, or raise the bound");
    }
    if (options_.estimate_only) {
      if (stop > next_sample_) {
        report_.samples = std::min(kSampleCountCap, report_.samples + (stop - next_sample_));
        last_sample_time_ = static_cast<double>(stop - 1) * period;
        next_sample_ = stop;
      }
      time_ = end;
      return;
    }
    for (long k = next_sample_; k < stop; ++k) {
      const double t = static_cast<double>(k) * period;
      emit(t, line, pose_at(t));
      next_sample_ = k + 1;
    }
    time_ = end;
  }

  // The first sample number k with k * period >= t (the samples before it come before t),
  // no further than kSampleCountCap.
  long first_sample_at_or_after(double t) const {
    const double period = options_.period_s;
    const double k = std::ceil(t / period);
    if (!(k < static_cast<double>(kSampleCountCap))) return kSampleCountCap;
    long n = std::max(next_sample_, static_cast<long>(k));
    while (n > next_sample_ && static_cast<double>(n - 1) * period >= t) --n;
    while (static_cast<double>(n) * period < t) ++n;
    return n;
  }

  // Inverse kinematics that overflowed (a glide far outside its rails) gives NaN joints, which
  // pass every limit check (NaN compares false): they stop the plan here instead.
  void require_numbers(const Vector6d& pose, const JointVector& joints, int line, const char* where,
                       double t = 0.0) const {
    if (pose.allFinite() && joints.allFinite()) return;
    not_a_number(pose, joints, line,
                 where[0] != '\0' ? std::string(where) : "at t = " + std::to_string(t) + " s");
  }
  [[noreturn]] void not_a_number(const Vector6d& pose, const JointVector& joints, int line,
                                 const std::string& where) const {
    if (!pose.allFinite()) {
      throw PlanError(file_, line,
                      where + ": the pose is not a number (check --origin and --start)");
    }
    int i = 0;
    while (i + 1 < joints.size() && std::isfinite(joints[i])) ++i;
    throw PlanError(file_, line,
                    where + ": the inverse kinematics gives no number for joint '" +
                        machine_.joints()[static_cast<std::size_t>(i)].name + "' at x " +
                        std::to_string(pose[0]) + " y " + std::to_string(pose[1]) + " z " +
                        std::to_string(pose[2]) + " mm");
  }

  void widen_ranges(const JointVector& joints) {
    for (int i = 0; i < joints.size(); ++i) {
      JointStatistics& stats = report_.joints[static_cast<std::size_t>(i)];
      stats.min = std::min(stats.min, joints[i]);
      stats.max = std::max(stats.max, joints[i]);
    }
  }

  void emit(double t, int line, const Vector6d& pose) {
    if (options_.estimate_only) {  // the start and the end: counted, not made
      report_.samples = std::min(kSampleCountCap, report_.samples + 1);
      last_sample_time_ = t;
      return;
    }
    Sample& sample = sample_;
    sample.time_s = t;
    sample.line = line;
    sample.pose = pose;
    sample.pen_down = pen_down_;
    const Status status = machine_.inverse(Pose::from_vector(pose), sample.joints);
    if (!status.ok()) {
      throw PlanError(file_, line,
                      "at t = " + std::to_string(t) +
                          " s: " + machine_.explain(Pose::from_vector(pose), status));
    }
    require_numbers(pose, sample.joints, line, "", t);
    rates_.add(t, sample.joints);
    for (int i = 0; i < sample.joints.size(); ++i) {
      JointStatistics& stats = report_.joints[static_cast<std::size_t>(i)];
      stats.min = std::min(stats.min, sample.joints[i]);
      stats.max = std::max(stats.max, sample.joints[i]);
      if (rates_.has_velocity()) {
        stats.peak_velocity = std::max(stats.peak_velocity, std::abs(rates_.velocity()[i]));
      }
      if (rates_.has_acceleration()) {
        stats.peak_acceleration =
            std::max(stats.peak_acceleration, std::abs(rates_.acceleration()[i]));
      }
    }
    last_sample_time_ = t;
    ++report_.samples;
    sink_.write(sample);
  }

  const Machine& machine_;
  const PlanOptions& options_;
  SampleSink& sink_;
  std::string file_;
  SegmentBuilder builder_;  // before pose_: the constructor takes the start from it
  bool pen_ = false;        // the machine has a pen channel
  PenPath pen_path_;        // where the pen changes
  bool pen_down_ = false;   // its state now: up at the start
  // A cable machine whose effector has a mass: its cables' tensions bound the moves.
  std::optional<TensionLimit> tension_;
  PlanReport report_;
  Vector6d pose_ = Vector6d::Zero();
  double time_ = 0.0;
  long next_sample_ = 1;  // the sample at t = 0 is the start
  std::deque<Piece> pieces_;
  double entry_speed_ = 0.0;  // the speed the first buffered piece is entered at
  double last_sample_time_ = 0.0;
  int last_line_ = 0;
  Sample sample_;
  JointRates rates_;  // of the samples emitted, for the report's peaks
};

}  // namespace

PlanReport plan_program(const Machine& machine, const std::filesystem::path& program,
                        const gcode::InterpreterOptions& interpreter_options,
                        const PlanOptions& options, SampleSink& sink) {
  if (!(options.period_s > 0.0)) throw std::invalid_argument("the period must be positive");
  Planner planner(machine, options, sink, program.string());
  // The program starts where the machine is: axes it never names stay at the start pose.
  gcode::Interpreter interpreter(
      program,
      starting_at(interpreter_options,
                  (options.start ? *options.start : machine.home()).as_vector(), options.origin));
  gcode::LineProgress progress(options.on_line);
  interpreter.run([&](const gcode::Canon& canon) {
    progress.see(canon.line);
    planner.on_canon(canon);
  });
  PlanReport report = planner.finish();
  // The interpreter's warnings first, in the job's order; the planner's own (the pen) after.
  report.warnings.insert(report.warnings.begin(), interpreter.warnings().begin(),
                         interpreter.warnings().end());
  return report;
}

}  // namespace pkm::motion
