// What a joint program draws without the job it came from (pkm view, docs/html-views.md): its
// blocks replayed from home as a controller without kinematics runs them, each joint moving
// linearly from block end to block end, and the tool's path found by forward kinematics along
// each block; the pen as the machine's [tool] commands switch it; each joint's range against its
// travel. Streamed: memory does not grow with the program.
#pragma once

#include <Eigen/Core>
#include <filesystem>
#include <functional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "pkm/gcode/interpreter.hpp"
#include "pkm/machine/machine.hpp"
#include "pkm/verify/joint_path.hpp"

namespace pkm::verify {

// The words a controller takes (post's dialects, post/joint_program.hpp): a word it does not
// have is refused at its column before anything is drawn.
struct JointDialect {
  std::string name = "linuxcnc";
  std::string_view axes = "XYZABCUVW";  // axis letters it accepts
  std::size_t max_line = 0;             // longest line it reads (0: any)
  bool programming = true;  // O-words and #parameters (LinuxCNC, Mach3); grbl has neither
};

// One point of the tool's path: a block's start (home first), its samples, its end.
struct TracePoint {
  int line = 0;           // the block's line (0: home)
  double along_mm = 0.0;  // the length of the tool's path so far, in the controlled coordinates
  geometry::Pose pose;
  kinematics::JointVector joints;
  bool drawn = false;      // on the way to this point: the pen down (no pen channel: a G1 block)
  bool block_end = false;  // the end of a block (or home)
};

// The range a joint used: internal units (mm, rad), and the lines where it peaks.
struct JointRange {
  double low = 0.0, high = 0.0;
  int low_line = 0, high_line = 0;
};

struct TraceOptions {
  JointDialect dialect;
  gcode::InterpreterOptions bounds;                       // loop bounds only
  std::function<void(int line)> on_line;                  // progress, once per change of line
  std::function<void(const TracePoint& point)> on_point;  // the path, for a page
};

struct TraceReport {
  long blocks = 0;
  bool has_pen = false;
  long pen_downs = 0;
  // The tool path's length (controlled coordinates): drawn (pen down; without a pen channel,
  // the G1 blocks), the rest (pen up; without a pen channel, the G0 blocks), and the G0 blocks.
  double drawn_mm = 0.0, travel_mm = 0.0, rapid_mm = 0.0;
  // The extent of what is drawn, x and y (mm); NaN when nothing is.
  Eigen::Vector2d drawn_min = Eigen::Vector2d::Constant(NAN);
  Eigen::Vector2d drawn_max = Eigen::Vector2d::Constant(NAN);
  std::vector<JointRange> joints;  // from home on
  ViolationSummary position;       // block ends beyond a joint's travel (joint program lines)
};

// Raised where the program cannot be drawn: file:line[:column]: why.
class TraceError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Throws TraceError for a word the dialect or the machine does not have, an arc or probe in joint
// space, or a block whose joints have no tool pose; gcode::GcodeError for what the interpreter
// refuses.
TraceReport trace_joint_program(const machine::Machine& machine,
                                const std::filesystem::path& joints, const TraceOptions& options);

}  // namespace pkm::verify
