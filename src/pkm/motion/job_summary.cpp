#include "pkm/motion/job_summary.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "pkm/motion/segment_builder.hpp"

namespace pkm::motion {

namespace {

// The points of a move that bound it: its end and, on an arc, every point where it passes a
// quarter turn (where its in-plane coordinates peak).
template <class Add>
void extreme_points(const Segment& segment, const Add& add) {
  add(Eigen::Vector3d(segment.end.head<3>()));
  if (segment.kind != SegmentKind::arc || segment.sweep_rad == 0.0) return;
  const double quarter = std::numbers::pi / 2.0;
  const double from =
      std::atan2(segment.start[segment.second_axis] - segment.centre[segment.second_axis],
                 segment.start[segment.first_axis] - segment.centre[segment.first_axis]);
  const double to = from + segment.sweep_rad;
  const double low = std::min(from, to), high = std::max(from, to);
  for (double k = std::ceil(low / quarter); k * quarter <= high; k += 1.0) {
    add(Eigen::Vector3d(segment.at((k * quarter - from) / segment.sweep_rad).head<3>()));
  }
}

class Summariser {
 public:
  Summariser(JobSummary& summary, const std::string& file)
      : summary_(summary), builder_(geometry::Vector6d::Zero(), geometry::Vector6d::Zero(), false) {
    builder_.set_file(file);
  }

  void on_canon(const gcode::Canon& canon) {
    using gcode::CanonKind;
    if (canon.kind == CanonKind::select_tool || canon.kind == CanonKind::change_tool) {
      summary_.tools.insert(canon.integer);
    }
    for (const Segment& segment : builder_.take(canon)) add(canon, segment);
  }

 private:
  void add(const gcode::Canon& canon, const Segment& segment) {
    if (segment.kind == SegmentKind::dwell) {
      summary_.dwell_s += segment.dwell_s;
      return;
    }
    ++summary_.moves;
    summary_.units.insert(canon.units);
    const bool turns_only = segment.kind == SegmentKind::line &&
                            (segment.end.head<3>() - segment.start.head<3>()).norm() == 0.0;
    const double length = segment.length();
    if (turns_only) {
      summary_.angles_deg += length;
    } else if (segment.rapid) {
      summary_.rapid_mm += length;
    } else {
      (segment.kind == SegmentKind::arc ? summary_.arc_mm : summary_.feed_mm) += length;
    }
    extreme_points(segment, [&](const Eigen::Vector3d& point) {
      summary_.box.extend(point);
      if (!segment.rapid) summary_.feed_box.extend(point);
    });
    if (!segment.rapid) note_feed(canon);
  }

  void note_feed(const gcode::Canon& canon) {
    if (canon.feed_mode == gcode::FeedMode::inverse_time) {
      summary_.inverse_time = true;
      return;
    }
    // Fed per revolution (G95, G33, G76): F or the pitch times the spindle's speed, per minute.
    const double per_minute = canon.feed_mode == gcode::FeedMode::units_per_revolution
                                  ? canon.value * canon.spindle_rpm
                                  : canon.value;
    const double feed = per_minute * (canon.units == gcode::LengthUnits::inch ? 25.4 : 1.0);
    summary_.min_feed_mm_per_min = any_feed_ ? std::min(summary_.min_feed_mm_per_min, feed) : feed;
    summary_.max_feed_mm_per_min = any_feed_ ? std::max(summary_.max_feed_mm_per_min, feed) : feed;
    any_feed_ = true;
  }

  JobSummary& summary_;
  SegmentBuilder builder_;
  bool any_feed_ = false;
};

}  // namespace

JobSummary summarize_job(const std::filesystem::path& program,
                         const gcode::InterpreterOptions& options) {
  JobSummary summary;
  Summariser summariser(summary, program.string());
  gcode::Interpreter interpreter(
      program, starting_at(options, geometry::Vector6d::Zero(), geometry::Vector6d::Zero()));
  interpreter.run([&](const gcode::Canon& canon) { summariser.on_canon(canon); });
  summary.warnings = interpreter.warnings();
  return summary;
}

}  // namespace pkm::motion
