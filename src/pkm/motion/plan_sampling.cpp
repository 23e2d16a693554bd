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
  if (piece.grid.ready) {
    run_on_grid(piece);
    return;
  }
  const Profile profile = Profile::make(piece.length, piece.entry_speed, piece.exit_speed,
                                        piece.max_speed, ramp_for(piece));
  if (options_.estimate_only) {
    for (int i = 0; i < piece.joint_slope.size(); ++i) {
      double& peak = report_.joints[static_cast<std::size_t>(i)].peak_velocity;
      peak = std::max(peak, piece.joint_slope[i] * profile.peak_speed);
    }
  }
  report_piece(piece, profile.duration_s);
  const double start = time_;
  sample_until(start + profile.duration_s, segment.line,
               [&](double t) { return segment.at(profile.distance(t - start) / piece.length); });
}

void Sampler::run_on_grid(const Piece& piece) {
  const Segment& segment = piece.segment;
  const PathGrid& grid = piece.grid;
  timing_.reset(piece);
  if (options_.estimate_only) widen_peaks(grid);
  report_piece(piece, timing_.duration_s());
  const double start = time_;
  sample_until(start + timing_.duration_s(), segment.line,
               [&](double t) { return segment.at(timing_.distance(t - start) / piece.length); });
}

// Each joint's peak velocity over the grid: |dq/ds| v at the points and where the speed changes
// inside an interval (dq/ds between its ends' there), raised by what the product can do between
// them: with dq/ds linear from q0 to q1 and v^2 linear, q' v passes its ends' by at most about
// ((q1 - q0) / q0)^2 / 8 of itself (a quarter of the square is kept), and the grid's dq/ds, a
// difference of the joints at its points, is good to about 1e-5 of itself (1e-4 is kept).
void Sampler::widen_peaks(const PathGrid& grid) {
  for (int k = 0; k < grid.intervals; ++k) {
    const std::size_t at = static_cast<std::size_t>(k);
    for (int i = 0; i < grid.joint_count; ++i) {
      const double start = std::abs(grid.slope(k, i)), end = std::abs(grid.slope(k + 1, i));
      double peak = std::max(start * std::sqrt(grid.speed_squared[at]),
                             end * std::sqrt(grid.speed_squared[at + 1]));
      for (std::size_t split = 0; split < 2 && grid.split_mm[at][split] > 0.0; ++split) {
        const double slope = start + (end - start) * grid.split_mm[at][split] / grid.step_mm;
        peak = std::max(peak, slope * std::sqrt(grid.split_speed_squared[at][split]));
      }
      const double change = std::abs(end - start) / std::max(std::min(start, end), 1e-300);
      peak *= 1.0 + 1e-4 + 0.25 * std::min(1.0, change * change);
      double& widest = report_.joints[static_cast<std::size_t>(i)].peak_velocity;
      widest = std::max(widest, peak);
    }
  }
}

void Sampler::report_piece(const Piece& piece, double duration_s) const {
  if (!options_.on_piece) return;
  options_.on_piece(PlannedPiece{piece.segment, piece.length, piece.stop_after, piece.entry_speed,
                                 piece.exit_speed, duration_s});
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
