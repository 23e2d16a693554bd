#include "pkm/motion/planner.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "pkm/motion/segment.hpp"

namespace pkm::motion {

namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;

// Rest-to-rest speed profile with a constant acceleration limit: accelerate, cruise, brake.
struct Profile {
  double length = 0.0, peak_speed = 0.0, acceleration = 0.0;
  double accelerate_s = 0.0, cruise_s = 0.0, duration_s = 0.0;

  static Profile trapezoid(double length, double speed, double acceleration) {
    Profile p;
    p.length = length;
    p.acceleration = acceleration;
    if (length <= 0.0) return p;
    const double ramp_length = speed * speed / acceleration;  // both ramps together
    if (ramp_length >= length) {
      p.peak_speed = std::sqrt(length * acceleration);
      p.accelerate_s = p.peak_speed / acceleration;
    } else {
      p.peak_speed = speed;
      p.accelerate_s = speed / acceleration;
      p.cruise_s = (length - ramp_length) / speed;
    }
    p.duration_s = 2.0 * p.accelerate_s + p.cruise_s;
    return p;
  }

  double distance(double t) const {
    if (t <= 0.0) return 0.0;
    if (t >= duration_s) return length;
    if (t < accelerate_s) return 0.5 * acceleration * t * t;
    const double ramp = 0.5 * acceleration * accelerate_s * accelerate_s;
    if (t < accelerate_s + cruise_s) return ramp + peak_speed * (t - accelerate_s);
    const double remaining = duration_s - t;
    return length - 0.5 * acceleration * remaining * remaining;
  }
};

double to_mm(gcode::LengthUnits units) {
  return units == gcode::LengthUnits::inch ? 25.4 : 1.0;
}

class Planner {
 public:
  Planner(const Machine& machine, const PlanOptions& options, SampleSink& sink, std::string file)
      : machine_(machine), options_(options), sink_(sink), file_(std::move(file)) {
    pose_ = (options.start ? *options.start : machine.home()).as_vector();
    const int joints = static_cast<int>(machine.joints().size());
    report_.joints.resize(static_cast<std::size_t>(joints));
    JointVector start_joints;
    const Status status = machine_.inverse(Pose::from_vector(pose_), start_joints);
    if (!status.ok()) {
      throw PlanError(file_, 0, "the start pose is not usable: " + machine_.describe(status));
    }
    for (int i = 0; i < joints; ++i) {
      report_.joints[static_cast<std::size_t>(i)].min = start_joints[i];
      report_.joints[static_cast<std::size_t>(i)].max = start_joints[i];
    }
    emit(0.0, 0, pose_);  // t = 0: where the machine starts
  }

  void on_canon(const gcode::Canon& canon) {
    using gcode::CanonKind;
    switch (canon.kind) {
      case CanonKind::g5x_offset:
        store_offset(canon, g5x_mm_);
        break;
      case CanonKind::g92_offset:
        store_offset(canon, g92_mm_);
        break;
      case CanonKind::tool_length_offset:
        store_offset(canon, tool_mm_);
        break;
      case CanonKind::traverse:
      case CanonKind::feed:
      case CanonKind::probe: {
        Segment segment;
        segment.kind = SegmentKind::line;
        segment.line = canon.line;
        segment.rapid = canon.kind == CanonKind::traverse;
        segment.start = pose_;
        segment.end = machine_pose(canon, canon.end);
        set_feed(canon, segment);
        run(segment);
        break;
      }
      case CanonKind::arc:
        run(arc_segment(canon));
        break;
      case CanonKind::dwell: {
        Segment segment;
        segment.kind = SegmentKind::dwell;
        segment.line = canon.line;
        segment.start = segment.end = pose_;
        segment.dwell_s = canon.value;
        run(segment);
        break;
      }
      default:
        break;
    }
  }

  PlanReport finish() {
    // The last sample lands exactly on the end of the program.
    if (last_sample_time_ < time_) emit(time_, last_line_, pose_);
    report_.duration_s = time_;
    return report_;
  }

 private:
  void store_offset(const gcode::Canon& canon, Vector6d& offset) {
    for (int axis = 0; axis < 6; ++axis) {
      offset[axis] =
          axis < 3 ? canon.end[axis] * to_mm(canon.units) : degrees_to_radians(canon.end[axis]);
    }
  }

  // Program coordinates (program units, deg) to the machine pose (mm, rad).
  Vector6d machine_pose(const gcode::Canon& canon, const gcode::Position& program) const {
    Vector6d pose;
    for (int axis = 0; axis < 6; ++axis) {
      const double value =
          axis < 3 ? program[axis] * to_mm(canon.units) : degrees_to_radians(program[axis]);
      pose[axis] = value + g5x_mm_[axis] + g92_mm_[axis] + tool_mm_[axis];
    }
    return pose;
  }

  void set_feed(const gcode::Canon& canon, Segment& segment) const {
    if (segment.rapid) return;
    if (canon.feed_mode == gcode::FeedMode::inverse_time) {
      segment.feed_mm_per_s = segment.length() * canon.value / 60.0;  // done in 1/F minutes
    } else {
      const bool angles_only = (segment.end.head<3>() - segment.start.head<3>()).norm() == 0.0;
      segment.feed_mm_per_s = canon.value * (angles_only ? 1.0 : to_mm(canon.units)) / 60.0;
    }
  }

  Segment arc_segment(const gcode::Canon& canon) {
    Segment segment;
    segment.kind = SegmentKind::arc;
    segment.line = canon.line;
    segment.start = pose_;
    segment.end = machine_pose(canon, canon.end);
    switch (canon.plane) {
      case gcode::Plane::xy:
        segment.first_axis = 0, segment.second_axis = 1, segment.normal_axis = 2;
        break;
      case gcode::Plane::xz:
        segment.first_axis = 2, segment.second_axis = 0, segment.normal_axis = 1;
        break;
      case gcode::Plane::yz:
        segment.first_axis = 1, segment.second_axis = 2, segment.normal_axis = 0;
        break;
    }
    const Vector6d offset = g5x_mm_ + g92_mm_ + tool_mm_;
    const double scale = to_mm(canon.units);
    segment.centre[segment.first_axis] = canon.center[0] * scale + offset[segment.first_axis];
    segment.centre[segment.second_axis] = canon.center[1] * scale + offset[segment.second_axis];
    const auto angle_of = [&](const Vector6d& p) {
      return std::atan2(p[segment.second_axis] - segment.centre[segment.second_axis],
                        p[segment.first_axis] - segment.centre[segment.first_axis]);
    };
    double sweep = angle_of(segment.end) - angle_of(segment.start);
    if (canon.turns > 0) {
      while (sweep <= 1e-12) sweep += kTwoPi;
      sweep += kTwoPi * (canon.turns - 1);
    } else {
      while (sweep >= -1e-12) sweep -= kTwoPi;
      sweep -= kTwoPi * (-canon.turns - 1);
    }
    segment.sweep_rad = sweep;
    set_feed(canon, segment);
    return segment;
  }

  // The feed and acceleration that keep every joint within its limits along a move. With q(s)
  // a joint along the path, its acceleration is q' s'' + q'' s'^2: bounding |q'| by S and |q''|
  // by C over the move (sampled every 0.5 mm), speed^2 C <= amax / 2 and accel S <= amax - speed^2
  // C keep it within amax everywhere. A 1 % margin covers the sampling of the derivatives.
  void limit_by_joints(const Segment& segment, double length, double& speed, double& acceleration) {
    constexpr double kMargin = 0.99;
    const int points = std::clamp(static_cast<int>(std::ceil(length / 0.5)), 8, 512);
    const double step = length / points;
    const int joint_count = static_cast<int>(machine_.joints().size());
    JointVector slope_max = JointVector::Zero(joint_count);
    JointVector curvature_max = JointVector::Zero(joint_count);
    JointVector previous, current, next;
    const auto joints_at = [&](int k, JointVector& q) {
      const Pose pose = Pose::from_vector(segment.at(static_cast<double>(k) / points));
      const Status status = machine_.inverse(pose, q);
      if (!status.ok()) {
        throw PlanError(file_, segment.line,
                        "the move leaves the machine's reach: " + machine_.describe(status));
      }
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
    int limiting = -1;
    for (int i = 0; i < joint_count; ++i) {
      const JointSpec& joint = machine_.joints()[static_cast<std::size_t>(i)];
      const double max_velocity = kMargin * joint.max_velocity;
      const double max_acceleration = kMargin * joint.max_acceleration;
      if (slope_max[i] > 0.0 && max_velocity / slope_max[i] < speed) {
        speed = max_velocity / slope_max[i];
        limiting = i;
      }
      if (curvature_max[i] > 0.0 && std::sqrt(0.5 * max_acceleration / curvature_max[i]) < speed) {
        speed = std::sqrt(0.5 * max_acceleration / curvature_max[i]);
        limiting = i;
      }
    }
    for (int i = 0; i < joint_count; ++i) {
      const double max_acceleration =
          kMargin * machine_.joints()[static_cast<std::size_t>(i)].max_acceleration;
      if (slope_max[i] > 0.0) {
        const double left = max_acceleration - curvature_max[i] * speed * speed;
        acceleration = std::min(acceleration, left / slope_max[i]);
      }
    }
    if (limiting >= 0 && speed < programmed * (1.0 - 1e-9)) {
      report_.feed_limits.push_back({segment.line, limiting, programmed, speed});
    }
  }

  void run(const Segment& segment) {
    last_line_ = segment.line;
    double duration = 0.0;
    Profile profile;
    double length = segment.length();
    if (segment.kind == SegmentKind::dwell) {
      duration = segment.dwell_s;
    } else if (length > 0.0) {
      const double max_feed = machine_.cartesian().max_feed_mm_per_min / 60.0;
      double speed = segment.rapid ? max_feed : std::min(segment.feed_mm_per_s, max_feed);
      if (!(speed > 0.0)) throw PlanError(file_, segment.line, "a feed move with no feed rate");
      double acceleration = machine_.cartesian().max_acceleration_mm_per_s2;
      limit_by_joints(segment, length, speed, acceleration);
      profile = Profile::trapezoid(length, speed, acceleration);
      duration = profile.duration_s;
      if ((segment.end.head<3>() - segment.start.head<3>()).norm() > 0.0 ||
          segment.kind == SegmentKind::arc) {
        report_.path_length_mm += length;
      }
    } else {
      pose_ = segment.end;
      return;
    }
    const double period = options_.period_s;
    const double start = time_;
    const double end = start + duration;
    // Samples fall on multiples of the period: time division.
    for (long k = next_sample_; static_cast<double>(k) * period < end; ++k) {
      const double t = static_cast<double>(k) * period;
      const double u =
          segment.kind == SegmentKind::dwell ? 1.0 : profile.distance(t - start) / length;
      emit(t, segment.line, segment.kind == SegmentKind::dwell ? segment.start : segment.at(u));
      next_sample_ = k + 1;
    }
    time_ = end;
    pose_ = segment.end;
  }

  void emit(double t, int line, const Vector6d& pose) {
    Sample& sample = sample_;
    sample.time_s = t;
    sample.line = line;
    sample.pose = pose;
    const Status status = machine_.inverse(Pose::from_vector(pose), sample.joints);
    if (!status.ok()) {
      throw PlanError(file_, line,
                      "at t = " + std::to_string(t) + " s: " + machine_.describe(status));
    }
    const double dt = t - last_sample_time_;
    for (int i = 0; i < sample.joints.size(); ++i) {
      JointStatistics& stats = report_.joints[static_cast<std::size_t>(i)];
      stats.min = std::min(stats.min, sample.joints[i]);
      stats.max = std::max(stats.max, sample.joints[i]);
      if (report_.samples > 0 && dt > 0.0) {
        const double velocity = (sample.joints[i] - last_joints_[i]) / dt;
        stats.peak_velocity = std::max(stats.peak_velocity, std::abs(velocity));
        if (report_.samples > 1) {
          // Velocities are averages over their intervals: their change spans the midpoints.
          const double spacing = 0.5 * (dt + last_dt_);
          stats.peak_acceleration =
              std::max(stats.peak_acceleration, std::abs(velocity - last_velocity_[i]) / spacing);
        }
        last_velocity_[i] = velocity;
      }
    }
    if (report_.samples == 0) last_velocity_ = JointVector::Zero(sample.joints.size());
    last_joints_ = sample.joints;
    if (dt > 0.0) last_dt_ = dt;
    last_sample_time_ = t;
    ++report_.samples;
    sink_.write(sample);
  }

  const Machine& machine_;
  const PlanOptions& options_;
  SampleSink& sink_;
  std::string file_;
  PlanReport report_;
  Vector6d pose_ = Vector6d::Zero();
  Vector6d g5x_mm_ = Vector6d::Zero(), g92_mm_ = Vector6d::Zero(), tool_mm_ = Vector6d::Zero();
  double time_ = 0.0;
  long next_sample_ = 1;  // the sample at t = 0 is the start
  double last_sample_time_ = 0.0;
  double last_dt_ = 0.0;
  int last_line_ = 0;
  Sample sample_;
  JointVector last_joints_, last_velocity_;
};

}  // namespace

PlanReport plan_program(const Machine& machine, const std::filesystem::path& program,
                        const gcode::InterpreterOptions& interpreter_options,
                        const PlanOptions& options, SampleSink& sink) {
  if (!(options.period_s > 0.0)) throw std::invalid_argument("the period must be positive");
  Planner planner(machine, options, sink, program.string());
  // The program starts where the machine is: axes it never names stay at the start pose.
  gcode::InterpreterOptions start_here = interpreter_options;
  const Vector6d start = (options.start ? *options.start : machine.home()).as_vector();
  for (int axis = 0; axis < 6; ++axis) {
    start_here.start_position[axis] = axis < 3 ? start[axis] : radians_to_degrees(start[axis]);
  }
  gcode::Interpreter interpreter(program, start_here);
  interpreter.run([&](const gcode::Canon& canon) { planner.on_canon(canon); });
  PlanReport report = planner.finish();
  report.warnings = interpreter.warnings();
  return report;
}

}  // namespace pkm::motion
