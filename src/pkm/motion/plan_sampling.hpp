// The planner's time division (internal to motion/): the samples on the multiples of the servo
// period along each planned piece, their joints by inverse kinematics, streamed to the sink and
// counted into the report (only counted when estimating). Nothing here allocates per sample.
#pragma once

#include <algorithm>
#include <string>
#include <vector>

#include "pkm/motion/joint_rates.hpp"
#include "pkm/motion/plan_piece.hpp"
#include "pkm/motion/planner.hpp"
#include "pkm/motion/time_optimal.hpp"

namespace pkm::motion {

[[noreturn]] void not_a_number(const machine::Machine& machine, const std::string& file,
                               const geometry::Vector6d& pose,
                               const kinematics::JointVector& joints, int line,
                               const std::string& where);

// Inverse kinematics that overflowed (a glide far outside its rails) gives NaN joints, which
// pass every limit check (NaN compares false): they stop the plan here instead. `where` says
// where on the line; empty: at time `t` (s).
inline void require_numbers(const machine::Machine& machine, const std::string& file,
                            const geometry::Vector6d& pose, const kinematics::JointVector& joints,
                            int line, const char* where, double t = 0.0) {
  if (pose.allFinite() && joints.allFinite()) return;
  not_a_number(machine, file, pose, joints, line,
               where[0] != '\0' ? std::string(where) : "at t = " + std::to_string(t) + " s");
}

// Widens the report's joint ranges to hold `joints`.
inline void widen_ranges(std::vector<JointStatistics>& ranges,
                         const kinematics::JointVector& joints) {
  for (int i = 0; i < joints.size(); ++i) {
    JointStatistics& stats = ranges[static_cast<std::size_t>(i)];
    stats.min = std::min(stats.min, joints[i]);
    stats.max = std::max(stats.max, joints[i]);
  }
}

class Sampler {
 public:
  Sampler(const machine::Machine& machine, const PlanOptions& options, SampleSink& sink,
          const std::string& file, PlanReport& report)
      : machine_(machine), options_(options), sink_(sink), file_(file), report_(report) {}

  // The sample at `t` (s) of `line`, at `pose`; estimates count it without making it.
  void emit(double t, int line, const geometry::Vector6d& pose);

  // Samples on the multiples of the period up to `end` (time division), then moves on.
  template <class PoseAt>
  void sample_until(double end, int line, const PoseAt& pose_at) {
    const double period = options_.period_s;
    const long stop = stop_before(end, line);
    for (long k = next_sample_; k < stop; ++k) {
      const double t = static_cast<double>(k) * period;
      emit(t, line, pose_at(t));
      next_sample_ = k + 1;
    }
    time_ = end;
  }

  // One planned piece along its speed profile: its grid's (time-optimal) or its ramps' (jerk).
  void run_piece(const Piece& piece);

  void set_pen_down(bool down) { pen_down_ = down; }
  double time_s() const { return time_; }
  double last_sample_time_s() const { return last_sample_time_; }

 private:
  // The sample number sampling up to `end` stops before, after checking the plan's bound on
  // samples; an estimate counts the samples here and leaves none to make.
  long stop_before(double end, int line);
  // The first sample number k with k * period >= t (the samples before it come before t),
  // no further than kSampleCountCap.
  long first_sample_at_or_after(double t) const;
  void run_on_grid(const Piece& piece);
  void widen_peaks(const PathGrid& grid);
  // Tells PlanOptions::on_piece of the piece.
  void report_piece(const Piece& piece, double duration_s) const;

  const machine::Machine& machine_;
  const PlanOptions& options_;
  SampleSink& sink_;
  const std::string& file_;
  PlanReport& report_;
  bool pen_down_ = false;  // the pen channel's state now: up at the start
  double time_ = 0.0;
  long next_sample_ = 1;  // the sample at t = 0 is the start
  double last_sample_time_ = 0.0;
  Sample sample_;
  JointRates rates_;   // of the samples emitted, for the report's peaks
  GridTiming timing_;  // of the piece being sampled, its storage kept
};

}  // namespace pkm::motion
