#include "pkm/motion/plan_sampling.hpp"

#include <algorithm>
#include <cmath>

namespace pkm::motion {

void not_a_number(const machine::Machine& machine, const std::string& file,
                  const geometry::Vector6d& pose, const kinematics::JointVector& joints, int line,
                  const std::string& where) {
  if (!pose.allFinite()) {
    throw PlanError(file, line, where + ": the pose is not a number (check --origin and --start)");
  }
  int i = 0;
  while (i + 1 < joints.size() && std::isfinite(joints[i])) ++i;
  throw PlanError(file, line,
                  where + ": the inverse kinematics gives no number for joint '" +
                      machine.joints()[static_cast<std::size_t>(i)].name + "' at x " +
                      std::to_string(pose[0]) + " y " + std::to_string(pose[1]) + " z " +
                      std::to_string(pose[2]) + " mm");
}

void Sampler::emit(double t, int line, const geometry::Vector6d& pose) {
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
  const kinematics::Status status =
      machine_.inverse(geometry::Pose::from_vector(pose), sample.joints);
  if (!status.ok()) {
    throw PlanError(file_, line,
                    "at t = " + std::to_string(t) +
                        " s: " + machine_.explain(geometry::Pose::from_vector(pose), status));
  }
  require_numbers(machine_, file_, pose, sample.joints, line, "", t);
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

void Sampler::run_piece(const Piece& piece) {
  const Segment& segment = piece.segment;
  if (segment.kind != SegmentKind::line ||
      (segment.end.head<3>() - segment.start.head<3>()).norm() > 0.0) {
    report_.path_length_mm += piece.length;  // moves of the angles alone are no path
  }
  const Profile profile = Profile::make(piece.length, piece.entry_speed, piece.exit_speed,
                                        piece.max_speed, ramp_for(piece, options_.jerk_mm_per_s3));
  if (options_.estimate_only) {
    for (int i = 0; i < piece.joint_slope.size(); ++i) {
      double& peak = report_.joints[static_cast<std::size_t>(i)].peak_velocity;
      peak = std::max(peak, piece.joint_slope[i] * profile.peak_speed);
    }
  }
  if (options_.on_piece) {
    options_.on_piece(PlannedPiece{segment, piece.length, piece.stop_after, piece.entry_speed,
                                   piece.exit_speed, profile.duration_s});
  }
  const double start = time_;
  sample_until(start + profile.duration_s, segment.line,
               [&](double t) { return segment.at(profile.distance(t - start) / piece.length); });
}

long Sampler::stop_before(double end, int line) {
  const double period = options_.period_s;
  const long stop = first_sample_at_or_after(end);
  if (options_.max_samples > 0 && !options_.estimate_only &&
      report_.samples + (stop - next_sample_) > options_.max_samples) {
    throw PlanError(file_, line,
                    "the plan would pass " + std::to_string(options_.max_samples) +
                        " samples here (t = " + std::to_string(end) +
                        " s): estimate the job first, or raise the bound");
  }
  if (options_.estimate_only && stop > next_sample_) {
    report_.samples = std::min(kSampleCountCap, report_.samples + (stop - next_sample_));
    last_sample_time_ = static_cast<double>(stop - 1) * period;
    next_sample_ = stop;
  }
  return options_.estimate_only ? next_sample_ : stop;
}

long Sampler::first_sample_at_or_after(double t) const {
  const double period = options_.period_s;
  const double k = std::ceil(t / period);
  if (!(k < static_cast<double>(kSampleCountCap))) return kSampleCountCap;
  long n = std::max(next_sample_, static_cast<long>(k));
  while (n > next_sample_ && static_cast<double>(n - 1) * period >= t) --n;
  while (static_cast<double>(n) * period < t) ++n;
  return n;
}

}  // namespace pkm::motion
