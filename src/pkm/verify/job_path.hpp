// The Cartesian job as verify follows it: its programmed moves pulled from the interpreter a few
// at a time, measured in the position coordinates the machine controls (a plotter's pen Z is not a
// position), each with the arc length along the job where it starts. Only the moves from the
// cursor to a little ahead of it are held, so memory does not grow with the job.
#pragma once

#include <deque>
#include <filesystem>
#include <string>
#include <vector>

#include "pkm/gcode/interpreter.hpp"
#include "pkm/machine/machine.hpp"
#include "pkm/motion/pen_path.hpp"
#include "pkm/motion/segment_builder.hpp"

namespace pkm::verify {

// 1 for each of x y z the machine positions, 0 for those it does not (its dof).
Eigen::Vector3d position_mask(const machine::Machine& machine);

// One programmed move: its geometry, and its path as the machine controls it.
struct JobPiece {
  motion::Segment segment;
  Eigen::Vector3d mask = Eigen::Vector3d::Ones();  // position_mask of the machine
  double start_mm = 0.0;          // arc length of the job before it, in controlled coordinates
  double length_mm = 0.0;         // its own: 0 for a move of uncontrolled coordinates only (pen Z)
  double curvature_per_mm = 0.0;  // largest curvature of its path: 0 for lines, 1/r for arcs
  // On a pen plotter: the pen is up before this fraction of the move, and down where the Z is
  // on the drawing side from it on (motion::PenPath::follows_from).
  double pen_follows_from = motion::PenPath::kNever;

  int line() const { return segment.line; }
  // The controlled position at fraction u of the move (uncontrolled coordinates are 0).
  Eigen::Vector3d point(double u) const { return segment.at(u).head<3>().cwiseProduct(mask); }
};

// The point of a move nearest to `point` (controlled coordinates) between fractions u0 <= u1.
struct Nearest {
  double distance_mm = 0.0;
  double u = 0.0;
};
Nearest nearest_on(const JobPiece& piece, const Eigen::Vector3d& point, double u0, double u1);

// A pause, tool change, I/O or user M-code of a program (gcode/machine_commands.hpp): its text,
// its line, and the job's arc length (mm) where it comes.
struct PlacedCommand {
  std::string text;
  int line = 0;
  double along_mm = 0.0;
  // In a joint program: how far the job is traced there (at or beyond along_mm, where the job
  // turns back on itself within the tolerance of the block's end: JobCursor::dwell_end).
  double reached_mm = 0.0;
};

// Whether verify holds a joint program to carry the command (not the override switches M48-M53,
// which change no position and which post leaves out where the controller has none).
bool compared_command(const std::string& text);

class JobPath {
 public:
  // The job read as post reads it: from the machine's home, with its origin at `origin` (mm, rad).
  JobPath(const machine::Machine& machine, const std::filesystem::path& job,
          const gcode::InterpreterOptions& options, const geometry::Vector6d& origin);
  JobPath(const JobPath&) = delete;
  JobPath& operator=(const JobPath&) = delete;

  // The move numbered `index` from 0, read from the job when first asked for; nullptr past the
  // job's end. Moves before the last forget_before() are gone.
  const JobPiece* piece(long index);
  // Moves before `index` will not be asked for again.
  void forget_before(long index);
  // The line of the job's end (its M2, or its last line), once piece() has returned nullptr.
  int end_line() const { return end_line_; }
  // On a machine with a pen channel: how often the job puts the pen down (starting from up, as a
  // plotter does) in the moves read so far, the line of the first time, and once the job is
  // read, the warning when it never goes down or never comes up (motion/pen_path.hpp).
  long pen_downs() const { return pen_.downs(); }
  int first_pen_down_line() const { return pen_.first_down_line(); }
  std::optional<gcode::Warning> pen_warning() const {
    return tool_.z == machine::ToolZ::pen ? pen_.warning() : std::nullopt;
  }
  const std::string& file() const { return file_; }
  // The job's machine commands read so far, each with where the job is when it comes.
  const std::vector<PlacedCommand>& commands() const { return commands_; }
  const std::vector<gcode::Warning>& warnings() const { return interpreter_.warnings(); }

 private:
  void take(const gcode::Canon& canon);
  JobPiece make_piece(const motion::Segment& segment) const;

  std::string file_;
  Eigen::Vector3d mask_;
  machine::ToolChannel tool_;
  motion::PenPath pen_;  // where the job puts the pen down
  motion::SegmentBuilder builder_;
  gcode::Interpreter interpreter_;
  gcode::CanonSink sink_;
  std::deque<JobPiece> window_;
  long first_index_ = 0;  // index of window_.front()
  double end_mm_ = 0.0;   // arc length at the end of the last move read
  int end_line_ = 0;
  std::vector<PlacedCommand> commands_;
  bool ended_ = false;
};

}  // namespace pkm::verify
