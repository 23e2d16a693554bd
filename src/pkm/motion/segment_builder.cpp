#include "pkm/motion/segment_builder.hpp"

#include <cmath>
#include <numbers>
#include <stdexcept>

#include "pkm/gcode/gcode_error.hpp"

namespace pkm::motion {

namespace {
constexpr double kTwoPi = 2.0 * std::numbers::pi;
double to_mm(gcode::LengthUnits units) {
  return units == gcode::LengthUnits::inch ? 25.4 : 1.0;
}
}  // namespace

gcode::InterpreterOptions starting_at(gcode::InterpreterOptions options,
                                      const geometry::Vector6d& start,
                                      const geometry::Vector6d& origin) {
  const geometry::Vector6d from_origin = start - origin;
  for (int axis = 0; axis < 6; ++axis) {
    options.start_position[axis] =
        axis < 3 ? from_origin[axis] : geometry::radians_to_degrees(from_origin[axis]);
  }
  return options;
}

SegmentBuilder::SegmentBuilder(const geometry::Vector6d& start, const geometry::Vector6d& origin,
                               bool great_circle_attitude)
    : pose_(start), origin_(origin), great_circle_attitude_(great_circle_attitude) {}

Moves SegmentBuilder::take(const gcode::Canon& canon) {
  using gcode::CanonKind;
  switch (canon.kind) {
    case CanonKind::path_control:
      path_mode_ = canon.integer;
      blend_tolerance_mm_ = canon.value > 0.0 ? canon.value * to_mm(canon.units) : 0.0;
      return {};
    case CanonKind::g5x_offset:
      store_offset(canon, g5x_mm_);
      return {};
    case CanonKind::g92_offset:
      store_offset(canon, g92_mm_);
      return {};
    case CanonKind::tool_length_offset:
      store_offset(canon, tool_mm_);
      return {};
    case CanonKind::xy_rotation:
      xy_rotation_rad_ = geometry::degrees_to_radians(canon.value);
      return {};
    case CanonKind::traverse:
    case CanonKind::feed:
    case CanonKind::probe:
      moves_[0] = line_segment(canon, machine_pose(canon));
      pose_ = moves_[0].end;
      return {moves_.data(), 1};
    case CanonKind::rigid_tap:
      return rigid_tap(canon);
    case CanonKind::arc:
      moves_[0] = arc_segment(canon);
      pose_ = moves_[0].end;
      return {moves_.data(), 1};
    case CanonKind::dwell: {
      Segment& segment = moves_[0];
      segment = Segment();
      segment.kind = SegmentKind::dwell;
      segment.line = canon.line;
      segment.start = segment.end = pose_;
      segment.dwell_s = canon.value;
      return {moves_.data(), 1};
    }
    default:
      return {};
  }
}

Segment SegmentBuilder::line_segment(const gcode::Canon& canon,
                                     const geometry::Vector6d& end) const {
  Segment segment;
  segment.kind = SegmentKind::line;
  segment.line = canon.line;
  segment.rapid = canon.kind == gcode::CanonKind::traverse;
  segment.start = pose_;
  segment.end = end;
  segment.great_circle_attitude = great_circle_attitude_;
  segment.z_free = z_free_;
  set_feed(canon, segment);
  return segment;
}

// In to the tap's end along X Y Z and back out to where it started, both at the pitch times the
// spindle's speed (the spindle reverses at the bottom): the tool ends where it was.
Moves SegmentBuilder::rigid_tap(const gcode::Canon& canon) {
  geometry::Vector6d bottom = machine_pose(canon);
  bottom.tail<3>() = pose_.tail<3>();  // the tap moves X Y Z only
  moves_[0] = line_segment(canon, bottom);
  moves_[1] = moves_[0];
  moves_[1].start = moves_[0].end;
  moves_[1].end = moves_[0].start;
  return {moves_.data(), 2};
}

void SegmentBuilder::store_offset(const gcode::Canon& canon, geometry::Vector6d& offset) const {
  for (int axis = 0; axis < 6; ++axis) {
    offset[axis] = axis < 3 ? canon.end[axis] * to_mm(canon.units)
                            : geometry::degrees_to_radians(canon.end[axis]);
  }
}

// Program coordinates (program units, deg) to the machine pose (mm, rad).
geometry::Vector6d SegmentBuilder::machine_pose(const gcode::Canon& canon) const {
  geometry::Vector6d pose;
  for (int axis = 0; axis < 6; ++axis) {
    const double value = axis < 3 ? canon.end[axis] * to_mm(canon.units)
                                  : geometry::degrees_to_radians(canon.end[axis]);
    pose[axis] = value + origin_[axis] + g5x_mm_[axis] + g92_mm_[axis] + tool_mm_[axis];
  }
  if (xy_rotation_rad_ != 0.0) {
    double x = canon.end[0] * to_mm(canon.units) + g92_mm_[0];
    double y = canon.end[1] * to_mm(canon.units) + g92_mm_[1];
    turn_xy(x, y);
    pose[0] = x + origin_[0] + g5x_mm_[0] + tool_mm_[0];
    pose[1] = y + origin_[1] + g5x_mm_[1] + tool_mm_[1];
  }
  return pose;
}

void SegmentBuilder::turn_xy(double& x, double& y) const {
  const double cos = std::cos(xy_rotation_rad_), sin = std::sin(xy_rotation_rad_);
  const double turned_x = x * cos - y * sin;
  y = x * sin + y * cos;
  x = turned_x;
}

void SegmentBuilder::set_feed(const gcode::Canon& canon, Segment& segment) const {
  if (segment.rapid) return;
  if (canon.feed_mode == gcode::FeedMode::inverse_time) {
    segment.feed_mm_per_s = segment.length() * canon.value / 60.0;  // done in 1/F minutes
    return;
  }
  const bool angles_only = (segment.end.head<3>() - segment.start.head<3>()).norm() == 0.0;
  const double per_minute = canon.feed_mode == gcode::FeedMode::units_per_revolution
                                ? per_revolution_feed(canon, segment)
                                : canon.value;
  segment.feed_mm_per_s = per_minute * (angles_only ? 1.0 : to_mm(canon.units)) / 60.0;
}

// Units per minute of a move fed per revolution: F (or the pitch) times the spindle's rpm. A
// move that cannot run (the spindle stopped, S0, no pitch) is refused at its line rather than
// planned at no speed.
double SegmentBuilder::per_revolution_feed(const gcode::Canon& canon,
                                           const Segment& segment) const {
  const double feed = canon.value * canon.spindle_rpm;
  if (feed > 0.0 && std::isfinite(feed)) return feed;
  if (segment.length() == 0.0) return 1.0;  // no motion: it takes no time at any feed
  std::string why;
  if (!(canon.spindle_rpm > 0.0)) {
    why = "the spindle is stopped or at S0";
  } else if (!(canon.value > 0.0)) {
    why = "its pitch (K, P) or F per revolution is 0";
  } else {
    why = "its speed overflows (" + gcode::written_number(canon.value) + " per revolution at " +
          gcode::written_number(canon.spindle_rpm) + " rpm)";
  }
  throw gcode::GcodeError(file_, canon.line, 0,
                          "a move fed per revolution of the spindle (G33, G33.1, G76, G95) "
                          "cannot run: " +
                              why);
}

Segment SegmentBuilder::arc_segment(const gcode::Canon& canon) const {
  Segment segment;
  segment.kind = SegmentKind::arc;
  segment.line = canon.line;
  segment.start = pose_;
  segment.end = machine_pose(canon);
  segment.great_circle_attitude = great_circle_attitude_;
  segment.z_free = z_free_;
  switch (canon.plane) {
    case gcode::Plane::xy:
      segment.first_axis = 0, segment.second_axis = 1, segment.normal_axis = 2;
      break;
    case gcode::Plane::xz:
      segment.first_axis = 2, segment.second_axis = 0, segment.normal_axis = 1;
      break;
    case gcode::Plane::yz:
      segment.first_axis = 1, segment.second_axis = 2, segment.normal_axis = 0;
      break;
  }
  const geometry::Vector6d offset = origin_ + g5x_mm_ + g92_mm_ + tool_mm_;
  const double scale = to_mm(canon.units);
  if (xy_rotation_rad_ != 0.0) {
    // A turned XY plane stays a principal plane; a turned XZ or YZ plane does not (segments'
    // arcs lie in principal planes): the interpreter refuses those arcs.
    if (canon.plane != gcode::Plane::xy) {
      throw std::logic_error("an XZ or YZ arc in a turned coordinate system reached the planner");
    }
    double x = canon.center[0] * scale + g92_mm_[0], y = canon.center[1] * scale + g92_mm_[1];
    turn_xy(x, y);
    segment.centre[0] = x + origin_[0] + g5x_mm_[0] + tool_mm_[0];
    segment.centre[1] = y + origin_[1] + g5x_mm_[1] + tool_mm_[1];
  } else {
    segment.centre[segment.first_axis] = canon.center[0] * scale + offset[segment.first_axis];
    segment.centre[segment.second_axis] = canon.center[1] * scale + offset[segment.second_axis];
  }
  const auto angle_of = [&](const geometry::Vector6d& p) {
    return std::atan2(p[segment.second_axis] - segment.centre[segment.second_axis],
                      p[segment.first_axis] - segment.centre[segment.first_axis]);
  };
  double sweep = angle_of(segment.end) - angle_of(segment.start);
  if (canon.turns > 0) {
    while (sweep <= 1e-12) sweep += kTwoPi;
    sweep += kTwoPi * (canon.turns - 1);
  } else {
    while (sweep >= -1e-12) sweep -= kTwoPi;
    sweep -= kTwoPi * (-canon.turns - 1);
  }
  segment.sweep_rad = sweep;
  set_feed(canon, segment);
  return segment;
}

}  // namespace pkm::motion
