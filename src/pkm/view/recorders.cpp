#include "pkm/view/recorders.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "pkm/verify/job_path.hpp"
#include "pkm/view/machine_drawing.hpp"

namespace pkm::view {

double initial_spacing_mm(const machine::Machine& machine) {
  Eigen::Vector3d low = machine.home().position_mm, high = low;
  for (const Segment& segment : fixed_parts(machine)) {
    for (const Eigen::Vector3d& point : {segment.from, segment.to}) {
      low = low.cwiseMin(point);
      high = high.cwiseMax(point);
    }
  }
  const double size = (high - low).norm();
  return size > 0.0 ? size / 4000.0 : 0.01;
}

// The tool's speed counts only the coordinates the machine moves: a plotter's Z is its pen
// channel (or dropped), and a pen lifted 5 mm in one period is no 5000 mm/s of tool speed.
double PlanRecorder::controlled_distance_mm(const Eigen::Vector3d& step) const {
  double squared = 0.0;
  for (int k = 0; k < 3; ++k) {
    if (controlled_[k]) squared += step[k] * step[k];
  }
  return std::sqrt(squared);
}

PlanRecorder::PlanRecorder(const machine::Machine& machine, motion::SampleSink* next)
    : machine_(machine),
      next_(next),
      has_pen_(machine.tool().z == machine::ToolZ::pen),
      buckets_(3 * static_cast<int>(machine.joints().size()), kChartBuckets),
      path_(initial_spacing_mm(machine), kMaxPathPoints),
      moments_(kDrawnMoments),
      values_(3 * machine.joints().size()) {
  const geometry::Dof dof = machine.kinematics().dof();
  for (int k = 0; k < 3; ++k) {
    controlled_[k] = dof.controls(k) && !(k == 2 && machine.tool().z != machine::ToolZ::none);
  }
}

void PlanRecorder::write(const motion::Sample& sample) {
  if (next_ != nullptr) next_->write(sample);
  const Eigen::Vector3d position = sample.pose.head<3>();
  const double t = sample.time_s;
  const double dt = t - last_t_;
  const int count = static_cast<int>(sample.joints.size());
  const double nan = std::numeric_limits<double>::quiet_NaN();
  double speed = 0.0;
  // The planner's own measure, so that the charts' peaks are the report's.
  rates_.add(t, sample.joints);
  for (int i = 0; i < count; ++i) {
    values_[static_cast<std::size_t>(i)] = sample.joints[i];
    values_[static_cast<std::size_t>(count + i)] =
        rates_.has_velocity() ? rates_.velocity()[i] : nan;
    values_[static_cast<std::size_t>(2 * count + i)] =
        rates_.has_acceleration() ? rates_.acceleration()[i] : nan;
  }
  if (samples_ > 0 && dt > 0.0) speed = controlled_distance_mm(position - last_position_) / dt;
  buckets_.add(t, values_);
  path_.add(t, position, speed, sample.line, sample.pen_down || !has_pen_);
  pen_ever_down_ = pen_ever_down_ || sample.pen_down;
  moments_.add(t, geometry::Pose::from_vector(sample.pose), sample.joints);
  line_starts_.try_emplace(sample.line, LineStart{t, position});
  last_position_ = position;
  last_t_ = t;
  ++samples_;
}

void PlanRecorder::finish() {
  path_.finish();
  moments_.finish();
}

// The program starts at home: the path and the charts start there too, so that a program of a
// single block still draws its move.
BlockRecorder::BlockRecorder(const machine::Machine& machine)
    : machine_(machine),
      buckets_(static_cast<int>(machine.joints().size()) + 1, kChartBuckets),
      path_(initial_spacing_mm(machine), kMaxPathPoints),
      moments_(kDrawnMoments),
      values_(machine.joints().size() + 1),
      last_position_(machine.home().position_mm) {
  kinematics::JointVector home;
  if (!machine.inverse(machine.home(), home).ok()) return;
  const std::size_t count = machine_.joints().size();
  for (std::size_t i = 0; i < count; ++i) values_[i] = home[static_cast<int>(i)];
  values_[count] = 0.0;
  buckets_.add(0.0, values_);
  path_.add(0.0, last_position_, 0.0, 0);
  moments_.add(0.0, machine.home(), home);
}

static bool deviation_greater(const WorstBlock& a, const WorstBlock& b) {
  return a.deviation_mm > b.deviation_mm;
}

void BlockRecorder::add(const verify::VerifiedBlock& block) {
  const Eigen::Vector3d position = block.end_pose.position_mm;
  length_mm_ += (position - last_position_).norm();
  last_position_ = position;
  const std::size_t count = machine_.joints().size();
  for (std::size_t i = 0; i < count; ++i) values_[i] = block.joints[static_cast<int>(i)];
  values_[count] = block.deviation_mm;
  buckets_.add(length_mm_, values_);
  // Every block end is kept on the path (its own line), so the page can mark the ends.
  path_.add(length_mm_, position, block.deviation_mm, block.line);
  moments_.add(length_mm_, block.end_pose, block.joints);
  line_starts_.try_emplace(block.line, LineStart{length_mm_, position});
  if (worst_.size() < kWorstKept || block.deviation_mm > worst_.front().deviation_mm) {
    worst_.push_back({block.deviation_mm, block.line, block.job_line, {length_mm_, position}});
    std::push_heap(worst_.begin(), worst_.end(), deviation_greater);
    if (worst_.size() > kWorstKept) {
      std::pop_heap(worst_.begin(), worst_.end(), deviation_greater);
      worst_.pop_back();
    }
  }
  ++blocks_;
}

std::vector<WorstBlock> BlockRecorder::worst_blocks() const {
  std::vector<WorstBlock> sorted = worst_;
  std::sort(sorted.begin(), sorted.end(), deviation_greater);
  return sorted;
}

void BlockRecorder::finish() {
  path_.finish();
  moments_.finish();
}

TraceRecorder::TraceRecorder(const machine::Machine& machine)
    : machine_(machine),
      buckets_(static_cast<int>(machine.joints().size()), kChartBuckets),
      path_(initial_spacing_mm(machine), kMaxPathPoints),
      moments_(kDrawnMoments),
      values_(machine.joints().size()) {}

// The largest distance of a joint from the middle of its travel, as a share of half the travel.
double TraceRecorder::travel_used_percent(const kinematics::JointVector& joints) const {
  double used = 0.0;
  for (std::size_t i = 0; i < machine_.joints().size(); ++i) {
    const machine::JointSpec& joint = machine_.joints()[i];
    const double half = 0.5 * (joint.max - joint.min);
    if (!(half > 0.0) || !std::isfinite(half)) continue;
    const double q = joints[static_cast<int>(i)];
    used = std::max(used, 100.0 * std::abs(q - 0.5 * (joint.max + joint.min)) / half);
  }
  return used;
}

void TraceRecorder::add(const verify::TracePoint& point) {
  const Eigen::Vector3d& position = point.pose.position_mm;
  path_.add(point.along_mm, position, travel_used_percent(point.joints), point.line, point.drawn);
  moments_.add(point.along_mm, point.pose, point.joints);
  if (!point.block_end) return;
  for (std::size_t i = 0; i < values_.size(); ++i) values_[i] = point.joints[static_cast<int>(i)];
  buckets_.add(point.along_mm, values_);
  line_starts_.try_emplace(point.line, LineStart{point.along_mm, position});
}

void TraceRecorder::finish() {
  path_.finish();
  moments_.finish();
}

std::vector<PathPoint> job_outline(const machine::Machine& machine,
                                   const std::filesystem::path& job,
                                   const gcode::InterpreterOptions& options,
                                   const geometry::Vector6d& origin) {
  const double spacing = initial_spacing_mm(machine);
  PathThinner outline(spacing, kMaxPathPoints);
  verify::JobPath path(machine, job, options, origin);
  for (long index = 0;; ++index) {
    const verify::JobPiece* piece = path.piece(index);
    if (piece == nullptr) break;
    const int steps = std::clamp(static_cast<int>(piece->length_mm / spacing), 1, 64);
    for (int k = 0; k <= steps; ++k) {
      const double u = static_cast<double>(k) / steps;
      outline.add(piece->start_mm + u * piece->length_mm, piece->point(u), 0.0, piece->line());
    }
    path.forget_before(index + 1);
  }
  outline.finish();
  return outline.points();
}

}  // namespace pkm::view
