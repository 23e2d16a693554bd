// An independent check of a joint-space program against its Cartesian job, written for the tests
// apart from pkm verify (no code of src/pkm/verify or of the planner's segments): the job's path
// rebuilt from the interpreter's canonical commands, the joint program read back with the same
// interpreter, forward kinematics at many points of every joint block, and each point's distance
// to the stretch of the programmed path the block traces, found by walking the path forward.
#pragma once

#include <Eigen/Core>
#include <filesystem>
#include <vector>

#include "pkm/machine/machine.hpp"

namespace pkm::test {

// One programmed move in machine coordinates (mm): a straight line, or a circular arc (a helix
// along the plane's normal; a spiral where its two radii differ, as LinuxCNC moves it).
struct PathMove {
  int line = 0;  // line of the job
  bool arc = false;
  Eigen::Vector3d start = Eigen::Vector3d::Zero(), end = Eigen::Vector3d::Zero();
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();  // arcs: the centre's in-plane coordinates
  int first = 0, second = 1, normal = 2;             // arcs: the plane's axes
  double sweep_rad = 0.0;                            // arcs: + counterclockwise

  Eigen::Vector3d at(double u) const;  // u in [0, 1]
};

// The job's moves, in machine coordinates: program units, work offsets and tool length offsets
// applied, the job placed at `origin` (mm), starting from `start` (machine coordinates, mm).
std::vector<PathMove> programmed_path(const std::filesystem::path& job,
                                      const Eigen::Vector3d& origin, const Eigen::Vector3d& start);

// One motion block of a joint program: its line and the joints at its end (mm, rad).
struct JointBlock {
  int line = 0;
  kinematics::JointVector joints;
};

// The motion blocks of a joint-space program, joints in the machine's internal units.
std::vector<JointBlock> joint_blocks(const machine::Machine& machine,
                                     const std::filesystem::path& program);

struct IndependentReport {
  long blocks = 0;
  long points = 0;                // forward-kinematics points measured
  double max_deviation_mm = 0.0;  // largest distance of a point to the path it should trace
  int max_deviation_line = 0;     // line of the joint program where it is
  long points_over_tolerance = 0;
  double max_untraced_mm = 0.0;  // largest distance of a point of the path to the traced path
  int max_untraced_line = 0;     // line of the joint program where it is
  bool reached_end = false;      // the last block ends at the job's last move's end
  int lost_at_line = 0;          // a block whose end is nowhere ahead on the path (0: none)
};

// Forward kinematics at `points_per_block` + 1 points of every block, seeded along the way; each
// point's distance to the programmed path between where the block starts and where it ends, the
// end found as the first local minimum of the distance to the block's end point, walking the path
// forward from the previous block's end; and each point of that stretch of path's distance to the
// traced one (coverage: a move left out shows there). Only the coordinates the machine controls
// count (a plotter's Z is its pen, not a position).
IndependentReport check_independently(const machine::Machine& machine,
                                      const std::vector<PathMove>& path,
                                      const std::vector<JointBlock>& blocks, int points_per_block,
                                      double tolerance_mm);

}  // namespace pkm::test
