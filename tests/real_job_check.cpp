#include "real_job_check.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <stdexcept>
#include <string>

#include "pkm/gcode/interpreter.hpp"

namespace pkm::test {

namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;
constexpr double kSearchStepMm = 0.05;  // path step of the search for a block's end
constexpr double kMatchMm = 0.005;      // a block's end on the path, but for the joints' rounding
constexpr double kAcceptMm = 0.1;       // a block's end further than this from the path is lost
constexpr double kSagittaMm = 2e-6;     // chord error of the polyline an arc is measured against

double to_mm(gcode::LengthUnits units) {
  return units == gcode::LengthUnits::inch ? 25.4 : 1.0;
}

Eigen::Vector3d xyz_mm(const gcode::Position& position, gcode::LengthUnits units) {
  return Eigen::Vector3d(position[0], position[1], position[2]) * to_mm(units);
}

// The program's state that places its coordinates on the machine.
struct Placement {
  Eigen::Vector3d origin, g5x = Eigen::Vector3d::Zero(), g92 = Eigen::Vector3d::Zero(),
                          tool = Eigen::Vector3d::Zero();
  Eigen::Vector3d offset() const { return origin + g5x + g92 + tool; }
};

PathMove arc_move(const gcode::Canon& canon, const Eigen::Vector3d& from, const Placement& place) {
  PathMove move;
  move.arc = true;
  move.line = canon.line;
  move.start = from;
  move.end = xyz_mm(canon.end, canon.units) + place.offset();
  if (canon.plane == gcode::Plane::xz) move.first = 2, move.second = 0, move.normal = 1;
  if (canon.plane == gcode::Plane::yz) move.first = 1, move.second = 2, move.normal = 0;
  const Eigen::Vector3d offset = place.offset();
  move.centre[move.first] = canon.center[0] * to_mm(canon.units) + offset[move.first];
  move.centre[move.second] = canon.center[1] * to_mm(canon.units) + offset[move.second];
  const auto angle = [&](const Eigen::Vector3d& p) {
    return std::atan2(p[move.second] - move.centre[move.second],
                      p[move.first] - move.centre[move.first]);
  };
  double sweep = angle(move.end) - angle(move.start);
  if (canon.turns > 0) {
    while (sweep <= 1e-12) sweep += kTwoPi;
    sweep += kTwoPi * (canon.turns - 1);
  } else {
    while (sweep >= -1e-12) sweep -= kTwoPi;
    sweep -= kTwoPi * (-canon.turns - 1);
  }
  move.sweep_rad = sweep;
  return move;
}

// Coordinates the machine does not control are not positions (a plotter's Z is its pen).
Eigen::Vector3d controlled(const Eigen::Vector3d& p, const geometry::Dof& dof) {
  Eigen::Vector3d result = p;
  for (int axis = 0; axis < 3; ++axis) {
    if (!dof.controls(axis)) result[axis] = 0.0;
  }
  return result;
}

// A place on the path: move index and parameter.
struct PathPlace {
  std::size_t move = 0;
  double u = 0.0;
};

class PathWalker {
 public:
  PathWalker(const std::vector<PathMove>& path, const geometry::Dof& dof) : path_(path), dof_(dof) {
    // Each move's length in the controlled coordinates, from 64 chords: the search's step.
    for (std::size_t m = 0; m < path_.size(); ++m) {
      double length = 0.0;
      for (int k = 1; k <= 64; ++k) length += (at({m, k / 64.0}) - at({m, (k - 1) / 64.0})).norm();
      lengths_.push_back(length);
    }
  }

  Eigen::Vector3d at(const PathPlace& place) const {
    return controlled(path_[place.move].at(place.u), dof_);
  }

  // Where a block ending at `target` ends on the path: walking forward from `from` at most
  // `reach_mm` along the path, the first place within kMatchMm of `target` (the distance changes
  // no faster than the path length, so only steps that can come that close are refined); or else,
  // for a block off the path, the first local minimum within kAcceptMm; nothing when neither.
  std::optional<PathPlace> find_end(const PathPlace& from, const Eigen::Vector3d& target,
                                    double reach_mm) const {
    PathPlace before = from, here = from;
    double d_before = INFINITY, d_here = (at(here) - target).norm(), walked = 0.0;
    std::optional<PathPlace> fallback;
    for (;;) {
      const std::optional<PathPlace> next = step(here);
      if (!next) return d_here < kMatchMm ? here : fallback;
      const double d_next = (at(*next) - target).norm();
      const double h = 1.01 * length_between(here, *next);  // lengths come from chords
      if (0.5 * (d_here + d_next - h) < kMatchMm) {
        const PathPlace found = refine(here, *next, target);
        if ((at(found) - target).norm() < kMatchMm) return settle(found, target);
      }
      if (!fallback && d_here <= d_before && d_here < d_next && d_here < kAcceptMm) {
        fallback = refine(before, *next, target);
      }
      walked += h;
      if (walked > reach_mm) return fallback;
      before = here, d_before = d_here;
      here = *next, d_here = d_next;
    }
  }

  // The nearest place to `target` at or after `from`, where the distance stops falling: a block
  // ends where the path comes nearest its end, not where it first comes within kMatchMm.
  PathPlace settle(const PathPlace& from, const Eigen::Vector3d& target) const {
    PathPlace before = from, here = from;
    double d_here = (at(here) - target).norm();
    for (;;) {
      const std::optional<PathPlace> next = step(here);
      if (!next) return refine(before, here, target);
      const double d_next = (at(*next) - target).norm();
      if (d_next > d_here) return refine(before, *next, target);
      before = here, here = *next, d_here = d_next;
    }
  }

  // The path from `a` to `b` as a polyline fine enough to measure against.
  std::vector<Eigen::Vector3d> polyline(const PathPlace& a, const PathPlace& b) const {
    std::vector<Eigen::Vector3d> points{at(a)};
    for (std::size_t m = a.move; m <= b.move && m < path_.size(); ++m) {
      const double u0 = m == a.move ? a.u : 0.0, u1 = m == b.move ? b.u : 1.0;
      const PathMove& move = path_[m];
      int pieces = 1;
      if (move.arc) {
        const double radius = std::max(
            1e-9, (move.start - move.centre)
                      .cwiseProduct(Eigen::Vector3d::Ones() - Eigen::Vector3d::Unit(move.normal))
                      .norm());
        const double step_rad = std::sqrt(8.0 * kSagittaMm / radius);
        pieces =
            std::clamp(static_cast<int>(std::ceil(std::abs(move.sweep_rad) * (u1 - u0) / step_rad)),
                       1, 200000);
      }
      for (int k = 1; k <= pieces; ++k) points.push_back(at({m, u0 + (u1 - u0) * k / pieces}));
    }
    return points;
  }

  double remaining_mm(const PathPlace& from) const {
    return length_between(from, {path_.size() - 1, 1.0});
  }

 private:
  // The next sample after `place`, about kSearchStepMm further along the path.
  // Moves of no length in the controlled coordinates (a plotter's pen lifts) have no samples:
  // the next move starts where this one ends, so its first sample is one step into it.
  std::optional<PathPlace> step(const PathPlace& place) const {
    PathPlace next = place;
    for (;;) {
      const double length = lengths_[next.move];
      if (next.u < 1.0 && length > 0.0) {
        next.u = std::min(1.0, next.u + kSearchStepMm / length);
        return next;
      }
      if (next.move + 1 >= path_.size()) return std::nullopt;
      next = {next.move + 1, 0.0};
    }
  }

  // Path length between two places, `a` before `b` (mm, controlled coordinates).
  double length_between(const PathPlace& a, const PathPlace& b) const {
    if (a.move == b.move) return (b.u - a.u) * lengths_[a.move];
    double length = (1.0 - a.u) * lengths_[a.move] + b.u * lengths_[b.move];
    for (std::size_t m = a.move + 1; m < b.move; ++m) length += lengths_[m];
    return length;
  }

  // The minimum of the distance to `target` between two samples, by golden section on each move
  // the bracket touches (it may straddle a junction).
  PathPlace refine(const PathPlace& from, const PathPlace& to,
                   const Eigen::Vector3d& target) const {
    PathPlace best = from;
    double d_best = (at(from) - target).norm();
    for (std::size_t m = from.move; m <= to.move; ++m) {
      if (lengths_[m] <= 0.0) continue;
      double a = m == from.move ? from.u : 0.0, b = m == to.move ? to.u : 1.0;
      const double golden = 0.5 * (std::sqrt(5.0) - 1.0);
      for (int i = 0; i < 60 && b - a > 1e-13; ++i) {
        const double c = b - golden * (b - a), d = a + golden * (b - a);
        if ((at({m, c}) - target).norm() <= (at({m, d}) - target).norm()) {
          b = d;
        } else {
          a = c;
        }
      }
      for (const PathPlace candidate :
           {PathPlace{m, 0.5 * (a + b)}, PathPlace{m, m == to.move ? to.u : 1.0}}) {
        const double d = (at(candidate) - target).norm();
        if (d < d_best) best = candidate, d_best = d;
      }
    }
    return best;
  }

  const std::vector<PathMove>& path_;
  geometry::Dof dof_;
  std::vector<double> lengths_;  // mm
};

// Distance from each point to a polyline, walking both forward together: the nearest segment is
// searched on both sides of the previous one until the segments are `margin` further away than the
// nearest so far.
class NearestSweep {
 public:
  explicit NearestSweep(const std::vector<Eigen::Vector3d>& polyline) : polyline_(polyline) {}

  double distance(const Eigen::Vector3d& p) {
    if (polyline_.size() == 1) return (p - polyline_[0]).norm();
    const std::size_t segments = polyline_.size() - 1;
    double best = segment_distance(p, current_);
    const double margin = 0.05;
    for (std::size_t j = current_ + 1; j < segments; ++j) {
      const double d = segment_distance(p, j);
      if (d < best) best = d, current_ = j;
      if (d > best + margin) break;
    }
    for (std::size_t j = current_; j-- > 0;) {
      const double d = segment_distance(p, j);
      if (d < best) best = d, current_ = j;
      if (d > best + margin) break;
    }
    return best;
  }

 private:
  double segment_distance(const Eigen::Vector3d& p, std::size_t j) const {
    const Eigen::Vector3d& a = polyline_[j];
    const Eigen::Vector3d ab = polyline_[j + 1] - a;
    const double squared = ab.squaredNorm();
    const double t = squared > 0.0 ? std::clamp((p - a).dot(ab) / squared, 0.0, 1.0) : 0.0;
    return (a + t * ab - p).norm();
  }

  const std::vector<Eigen::Vector3d>& polyline_;
  std::size_t current_ = 0;
};

}  // namespace

Eigen::Vector3d PathMove::at(double u) const {
  Eigen::Vector3d p = start + u * (end - start);
  if (!arc) return p;
  const double a0 = std::atan2(start[second] - centre[second], start[first] - centre[first]);
  const double r0 = std::hypot(start[first] - centre[first], start[second] - centre[second]);
  const double r1 = std::hypot(end[first] - centre[first], end[second] - centre[second]);
  const double radius = r0 + u * (r1 - r0), angle = a0 + u * sweep_rad;
  p[first] = centre[first] + radius * std::cos(angle);
  p[second] = centre[second] + radius * std::sin(angle);
  return p;
}

std::vector<PathMove> programmed_path(const std::filesystem::path& job,
                                      const Eigen::Vector3d& origin, const Eigen::Vector3d& start) {
  gcode::InterpreterOptions options;
  for (int axis = 0; axis < 3; ++axis) options.start_position[axis] = start[axis] - origin[axis];
  Placement place{origin};
  Eigen::Vector3d at = start;
  std::vector<PathMove> path;
  gcode::Interpreter interpreter(job, options);
  interpreter.run([&](const gcode::Canon& canon) {
    using gcode::CanonKind;
    switch (canon.kind) {
      case CanonKind::g5x_offset:
        place.g5x = xyz_mm(canon.end, canon.units);
        return;
      case CanonKind::g92_offset:
        place.g92 = xyz_mm(canon.end, canon.units);
        return;
      case CanonKind::tool_length_offset:
        place.tool = xyz_mm(canon.end, canon.units);
        return;
      case CanonKind::traverse:
      case CanonKind::feed:
      case CanonKind::probe: {
        PathMove move;
        move.line = canon.line;
        move.start = at;
        move.end = xyz_mm(canon.end, canon.units) + place.offset();
        path.push_back(move);
        break;
      }
      case CanonKind::arc:
        path.push_back(arc_move(canon, at, place));
        break;
      case CanonKind::xy_rotation:
        // This independent reading composes translations only: a turned job needs it taught.
        if (canon.value != 0.0) {
          throw std::runtime_error(job.string() + ":" + std::to_string(canon.line) +
                                   ": the independent check does not turn coordinate systems");
        }
        return;
      default:
        return;
    }
    at = path.back().end;
  });
  return path;
}

std::vector<JointBlock> joint_blocks(const machine::Machine& machine,
                                     const std::filesystem::path& program) {
  const std::string letters = "XYZABCUVW";
  kinematics::JointVector home;
  if (!machine.inverse(machine.home(), home).ok()) return {};
  gcode::InterpreterOptions options;
  for (std::size_t i = 0; i < machine.joints().size(); ++i) {
    const machine::JointSpec& joint = machine.joints()[i];
    options.start_position[letters.find(joint.axis_letter)] =
        joint.to_interface(home[static_cast<int>(i)]);
  }
  // A pen command is not a block, even where it is G-code (a servo on Z: "G0 Z90").
  if (machine.tool().z == machine::ToolZ::pen) {
    options.event_lines = {machine.tool().down_command, machine.tool().up_command};
  }
  std::vector<JointBlock> blocks;
  gcode::Position last = options.start_position;
  gcode::Interpreter interpreter(program, options);
  interpreter.run([&](const gcode::Canon& canon) {
    if (canon.kind != gcode::CanonKind::traverse && canon.kind != gcode::CanonKind::feed) return;
    JointBlock block{canon.line, home};
    bool joints_move = false, others_move = false;
    for (std::size_t slot = 0; slot < letters.size(); ++slot) {
      const bool joint_axis =
          std::any_of(machine.joints().begin(), machine.joints().end(),
                      [&](const machine::JointSpec& j) { return j.axis_letter == letters[slot]; });
      (joint_axis ? joints_move : others_move) |= canon.end[slot] != last[slot];
    }
    last = canon.end;
    // A move of axes that are no joint's only (a pen servo on Z: `G0 Z90`) is a tool command.
    if (others_move && !joints_move) return;
    for (std::size_t i = 0; i < machine.joints().size(); ++i) {
      const machine::JointSpec& joint = machine.joints()[i];
      const std::size_t slot = letters.find(joint.axis_letter);
      const double value = joint.kind == kinematics::JointKind::linear
                               ? canon.end[slot] * to_mm(canon.units)
                               : canon.end[slot];
      block.joints[static_cast<int>(i)] = joint.from_interface(value);
    }
    blocks.push_back(block);
  });
  return blocks;
}

IndependentReport check_independently(const machine::Machine& machine,
                                      const std::vector<PathMove>& path,
                                      const std::vector<JointBlock>& blocks, int points_per_block,
                                      double tolerance_mm) {
  IndependentReport report;
  const geometry::Dof dof = machine.kinematics().dof();
  const PathWalker walker(path, dof);
  PathPlace cursor;
  geometry::Pose pose = machine.home();
  kinematics::JointVector q0;
  if (path.empty() || !machine.inverse(pose, q0).ok()) return report;
  std::vector<Eigen::Vector3d> points(static_cast<std::size_t>(points_per_block) + 1);
  for (const JointBlock& block : blocks) {
    ++report.blocks;
    for (int k = 0; k <= points_per_block; ++k) {
      const double lambda = static_cast<double>(k) / points_per_block;
      const kinematics::JointVector q = q0 + lambda * (block.joints - q0);
      const bool solved = machine.kinematics().forward(q, pose).ok();
      points[static_cast<std::size_t>(k)] =
          solved ? controlled(pose.position_mm, dof) : Eigen::Vector3d::Constant(INFINITY);
    }
    q0 = block.joints;
    double traced_mm = 0.0;
    for (std::size_t k = 1; k < points.size(); ++k) traced_mm += (points[k] - points[k - 1]).norm();
    const std::optional<PathPlace> end =
        walker.find_end(cursor, points.back(), 1.5 * traced_mm + 1.0);
    if (!end) {
      report.lost_at_line = block.line;
      report.max_deviation_mm = INFINITY;
      report.max_deviation_line = block.line;
      return report;
    }
    const std::vector<Eigen::Vector3d> window = walker.polyline(cursor, *end);
    NearestSweep nearest(window);
    for (const Eigen::Vector3d& p : points) {
      const double d = nearest.distance(p);
      ++report.points;
      if (d > tolerance_mm) ++report.points_over_tolerance;
      if (d > report.max_deviation_mm + 1e-9) {  // a tie stays with the first block
        report.max_deviation_mm = d;
        report.max_deviation_line = block.line;
      }
    }
    // Every point of the path the block stands for is traced: nothing skipped (a full circle).
    NearestSweep traced(points);
    for (const Eigen::Vector3d& p : window) {
      const double d = traced.distance(p);
      if (d > report.max_untraced_mm) {
        report.max_untraced_mm = d;
        report.max_untraced_line = block.line;
      }
    }
    cursor = *end;
  }
  report.reached_end = walker.remaining_mm(cursor) < 1e-3;
  return report;
}

}  // namespace pkm::test
