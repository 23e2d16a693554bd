// The time-optimal reference (issue 29): the fastest timing of the path the planner sampled, under
// the same limits at 100 %, by the classic reachability passes over a fine grid. Independent of
// src/pkm/motion's speed planning: it takes the planner's pieces (PlanOptions::on_piece) and
// nothing else from it. Slow and simple on purpose; docs/motion.md, "The time-optimal reference",
// states the problem it solves.
#pragma once

#include <filesystem>
#include <vector>

#include "pkm/machine/machine.hpp"
#include "pkm/motion/planner.hpp"

namespace pkm::test {

// One step of the reference's speed profile as the passes found it: `step_mm` of piece `piece`
// from `s_mm` along it, the speed going from v0 to v1 (mm/s) at one acceleration.
struct ProfileStep {
  std::size_t piece = 0;
  double s_mm = 0.0, step_mm = 0.0;
  double v0_mm_per_s = 0.0, v1_mm_per_s = 0.0;
};

struct ReferenceResult {
  double duration_s = 0.0;                // the motion's time: no dwells, no pen delays
  std::vector<double> piece_durations_s;  // one per piece, in order
  long grid_points = 0;
  std::vector<ProfileStep> profile;  // every step, in order (only when asked for)
};

// The time-optimal timing of `pieces` (in the order the planner ran them) on `machine`: start and
// end at rest, at rest after every piece that stops, each joint's velocity and acceleration, the
// tool tip's acceleration (tangential and normal as one budget), the feed, and on a cable machine
// whose effector has a mass its cables' tensions, all at 100 %; at a junction passed without
// stopping, each joint's change of rate within one servo period `period_s`. The grid is
// `grid_step_mm` (mm of path; degrees for a move of the angles alone), at least 20 intervals a
// piece. With `keep_profile`, the profile's steps too (tests check that it keeps the limits).
// Throws std::runtime_error where the path leaves the kinematics' reach or no timing
// keeps the limits at rest.
ReferenceResult solve_reference(const machine::Machine& machine,
                                const std::vector<motion::PlannedPiece>& pieces, double period_s,
                                double grid_step_mm, bool keep_profile = false);

// A job planned as an estimate with every piece collected: the planner's report, its pieces, its
// motion time (the pieces' durations summed) and the CPU time the plan took (s).
struct PlannedJob {
  motion::PlanReport report;
  std::vector<motion::PlannedPiece> pieces;
  double motion_time_s = 0.0;
  double cpu_s = 0.0;
};
PlannedJob plan_pieces(const machine::Machine& machine, const std::filesystem::path& program,
                       motion::PlanOptions options = {});

}  // namespace pkm::test
