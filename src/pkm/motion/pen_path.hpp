// A plotter's pen along a job, the one rule plan, post, verify and check follow (docs/post.md,
// "The pen channel"): the pen is up when the job starts, whatever the start pose's Z; from the
// job's first move in Z on, it is down wherever the Z is on the [tool] table's drawing side
// (below `down_below`, or above `down_above`). The job's moves in X and Y are tallied by the Z
// they run at, so that a job whose pen never goes down, or never comes up again, is told which
// Z it uses and which [tool] setting would draw it.
#pragma once

#include <map>
#include <optional>
#include <set>
#include <vector>

#include "pkm/gcode/interpreter.hpp"
#include "pkm/machine/machine.hpp"
#include "pkm/motion/segment.hpp"

namespace pkm::motion {

struct PenChange {
  double u = 0.0;     // fraction of the move where the pen changes (0 before it moves)
  bool down = false;  // the pen from there on
};

// How often the job's moves in X and Y end at one Z, by feed and rapid.
struct ZLevelMoves {
  long feed = 0;
  long rapid = 0;
};

class PenPath {
 public:
  explicit PenPath(const machine::Machine& machine);

  // The job's next move (in the job's order, every one): where along it the pen changes.
  std::vector<PenChange> follow(const Segment& segment);

  bool down() const { return down_; }
  // From which fraction of the move last followed the pen is down exactly where its Z is on the
  // drawing side (before it, up): 0, or where the job's first move in Z leaves the drawing side
  // it started on, or kNever before the job's first move in Z.
  static constexpr double kNever = 2.0;
  double follows_from() const { return follows_from_; }
  long downs() const { return downs_; }
  int first_down_line() const { return first_down_line_; }

  // Once the job has been followed to its end: a warning when the pen never went down while
  // the job moved in X and Y, or never came up again after going down while the job moved in
  // X and Y at more than one Z; none otherwise.
  std::optional<gcode::Warning> warning() const;

 private:
  void tally(const Segment& segment);
  std::string levels_text() const;
  std::string suggestion() const;

  const machine::ToolChannel& tool_;
  double mm_per_unit_;
  std::string unit_;
  bool down_ = false;
  bool follows_z_ = false;
  double follows_from_ = kNever;
  long downs_ = 0, ups_after_down_ = 0;
  int first_down_line_ = 0;
  int first_xy_line_ = 0;
  std::map<double, ZLevelMoves> levels_;  // by Z (mm, machine coordinates, to 0.1 um)
  std::set<double> z_only_levels_;        // where the job's moves in Z alone end
  bool levels_overflow_ = false;
  bool drew_at_two_levels_ = false;  // pen down over moves in X and Y at more than one Z
  std::optional<double> drawn_level_;
};

}  // namespace pkm::motion
