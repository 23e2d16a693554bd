// What a page needs from a plan's million samples or a joint program's blocks, gathered as they
// stream past in bounded memory (decimation.hpp): the thinned tool path with its colour (speed,
// deviation), min/max buckets of each joint's position, velocity and acceleration (blocks:
// position and deviation), the moments the machine is drawn at, and where each G-code line starts.
#pragma once

#include <map>
#include <optional>

#include "pkm/motion/joint_rates.hpp"
#include "pkm/motion/planner.hpp"
#include "pkm/verify/joint_path.hpp"
#include "pkm/verify/joint_trace.hpp"
#include "pkm/view/decimation.hpp"

namespace pkm::view {

// Where a G-code line's first sample (block) lies: to mark the moves a joint slowed.
struct LineStart {
  double t = 0.0;  // s (plan) or mm along the path (blocks)
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
};

// Chart buckets: 1000 to 2000, more than a screen's pixel columns; path: at most 60 000 points.
inline constexpr std::size_t kChartBuckets = 1000;
inline constexpr std::size_t kMaxPathPoints = 60000;
inline constexpr std::size_t kDrawnMoments = 200;

// The spacing a path starts thinned at: a 4000th of the machine's drawing (fixed parts and
// home), so that a path on screen is exact to a fraction of a pixel.
double initial_spacing_mm(const machine::Machine& machine);

// A sink of the planner that records the samples for the page and passes each on to `next`
// (the samples' file), if any.
class PlanRecorder final : public motion::SampleSink {
 public:
  explicit PlanRecorder(const machine::Machine& machine, motion::SampleSink* next = nullptr);
  void write(const motion::Sample& sample) override;
  void finish();  // after the last sample

  const machine::Machine& machine() const { return machine_; }
  // Channels: joint i's position (i), velocity (J + i), acceleration (2J + i), in the machine's
  // internal units, per s and per s^2 as the planner's report computes them.
  const MinMaxBuckets& joint_buckets() const { return buckets_; }
  // colour: tool speed over the controlled coordinates, mm/s; pen_down: the pen channel's state
  const PathThinner& path() const { return path_; }
  const MomentSampler& moments() const { return moments_; }
  const std::map<int, LineStart>& line_starts() const { return line_starts_; }
  bool has_pen() const { return has_pen_; }
  bool pen_ever_down() const { return pen_ever_down_; }  // on a machine with a pen

 private:
  double controlled_distance_mm(const Eigen::Vector3d& step) const;
  const machine::Machine& machine_;
  motion::SampleSink* next_;
  bool has_pen_ = false;
  bool pen_ever_down_ = false;
  bool controlled_[3] = {true, true, true};  // x y z: moved by the machine's joints
  MinMaxBuckets buckets_;
  PathThinner path_;
  MomentSampler moments_;
  std::map<int, LineStart> line_starts_;
  std::vector<double> values_;
  motion::JointRates rates_;
  Eigen::Vector3d last_position_ = Eigen::Vector3d::Zero();
  double last_t_ = 0.0;
  long samples_ = 0;
};

// A block among the worst deviations, where the page marks it.
struct WorstBlock {
  double deviation_mm = 0.0;
  int line = 0, job_line = 0;
  LineStart at;
};

// Records the blocks of post's or verify's joint program. The slider's parameter and the charts'
// abscissa is the length of the polyline through home (where the program starts) and the blocks'
// ends (mm). Channels: joint i's position (i), the block's deviation (J).
class BlockRecorder {
 public:
  static constexpr std::size_t kWorstKept = 100;
  explicit BlockRecorder(const machine::Machine& machine);
  void add(const verify::VerifiedBlock& block);
  void finish();
  // The kWorstKept largest deviations, largest first.
  std::vector<WorstBlock> worst_blocks() const;

  const machine::Machine& machine() const { return machine_; }
  const MinMaxBuckets& buckets() const { return buckets_; }
  const PathThinner& path() const { return path_; }  // colour: deviation, mm
  const MomentSampler& moments() const { return moments_; }
  const std::map<int, LineStart>& line_starts() const { return line_starts_; }
  long blocks() const { return blocks_; }

 private:
  const machine::Machine& machine_;
  MinMaxBuckets buckets_;
  PathThinner path_;
  MomentSampler moments_;
  std::map<int, LineStart> line_starts_;
  std::vector<double> values_;
  std::vector<WorstBlock> worst_;  // a min-heap on deviation_mm, at most kWorstKept
  Eigen::Vector3d last_position_;
  double length_mm_ = 0.0;
  long blocks_ = 0;
};

// Records what pkm view traces of a joint program alone: the path with its pen (drawn or not),
// coloured by how much of a joint's travel the tool uses there (100 % at an end of it, more
// beyond), and each joint's position at the block ends. The abscissa is the tool path's length
// from home (mm). Channels: joint i's position (i).
class TraceRecorder {
 public:
  explicit TraceRecorder(const machine::Machine& machine);
  void add(const verify::TracePoint& point);
  void finish();

  const machine::Machine& machine() const { return machine_; }
  const MinMaxBuckets& buckets() const { return buckets_; }
  const PathThinner& path() const { return path_; }  // colour: % of a joint's half travel
  const MomentSampler& moments() const { return moments_; }
  const std::map<int, LineStart>& line_starts() const { return line_starts_; }

 private:
  double travel_used_percent(const kinematics::JointVector& joints) const;
  const machine::Machine& machine_;
  MinMaxBuckets buckets_;
  PathThinner path_;
  MomentSampler moments_;
  std::map<int, LineStart> line_starts_;
  std::vector<double> values_;
};

// The job a joint program must trace, as verify reads it (JobPath: from home, at `origin`, mm and
// rad; uncontrolled coordinates 0), sampled every few mm of each move and thinned like a plan's
// path: drawn grey under the blocks so that a reader sees where they should have gone.
std::vector<PathPoint> job_outline(const machine::Machine& machine,
                                   const std::filesystem::path& job,
                                   const gcode::InterpreterOptions& options,
                                   const geometry::Vector6d& origin);

}  // namespace pkm::view
