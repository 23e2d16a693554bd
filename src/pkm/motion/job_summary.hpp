// What a G-code job does before any machine runs it (`pkm gcode JOB`): its units, the box its
// moves span, the length of its path by kind of motion, its feeds, tools and dwells, and the
// interpreter's warnings. Program coordinates with the program's own offsets, in mm.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <filesystem>
#include <set>
#include <vector>

#include "pkm/gcode/interpreter.hpp"

namespace pkm::motion {

struct JobSummary {
  int moves = 0;                       // lines, arcs and probes
  std::set<gcode::LengthUnits> units;  // the units its moves were written in
  // The extents (mm), empty (isEmpty()) where no point was added.
  Eigen::AlignedBox3d box;       // every point the moves reach (not the start at X0 Y0 Z0)
  Eigen::AlignedBox3d feed_box;  // the points of feed moves and arcs: what is cut or drawn
  double rapid_mm = 0.0, feed_mm = 0.0, arc_mm = 0.0;  // path length by kind of motion
  double angles_deg = 0.0;                             // travel of moves that turn A B C alone
  double min_feed_mm_per_min = 0.0, max_feed_mm_per_min = 0.0;  // programmed F of feed moves
  bool inverse_time = false;                                    // some moves are in G93
  std::set<int> tools;  // tool numbers selected or changed to
  double dwell_s = 0.0;
  std::vector<gcode::Warning> warnings;
};

// Runs the job through the interpreter from X0 Y0 Z0 (as rs274 does). Throws gcode::GcodeError
// (file:line:column) at the first error.
JobSummary summarize_job(const std::filesystem::path& program,
                         const gcode::InterpreterOptions& options);

}  // namespace pkm::motion
