#include "pkm/motion/look_ahead.hpp"

#include <cmath>
#include <numbers>

#include "pkm/motion/time_optimal.hpp"

namespace pkm::motion {

namespace {

// G64 without P still keeps corners this close to the programmed path (mm).
constexpr double kDefaultBlendTolerance = 0.01;
// Directions within this angle (rad) join without a blend or a stop.
constexpr double kTangentAngle = 1e-3;

// Direction of travel at the start (at_end false) or end of a segment.
Eigen::Vector3d tangent(const Segment& segment, bool at_end) {
  return heading(segment, at_end ? 1.0 : 0.0);
}

}  // namespace

// Joins `next` to `previous`: straight on where they are tangent, through a blend arc within
// the G64 tolerance where two lines meet at an angle, with a stop everywhere else.
void LookAhead::join(Piece& previous, Piece& next) {
  const Eigen::Vector3d out = tangent(previous.segment, true);
  const Eigen::Vector3d in = tangent(next.segment, false);
  const bool same_kind = previous.segment.rapid == next.segment.rapid;
  // A blend rounds corners in 3D: a ramp in a Z the machine does not move would tilt it.
  const auto ramps_free_z = [](const Segment& s) { return s.z_free && s.start[2] != s.end[2]; };
  if (builder_.path_mode() != 64 || !same_kind || out.isZero() || in.isZero() ||
      ramps_free_z(previous.segment) || ramps_free_z(next.segment)) {
    previous.stop_after = true;
    return;
  }
  const double angle = std::acos(std::clamp(out.dot(in), -1.0, 1.0));
  if (angle <= kTangentAngle) {
    // Tangent: the speed carries over, as far as the joints' rates allow.
    limits_.limit_junction(previous, next);
    limits_.limit_junction_jerk(previous, next);
    return;
  }
  if (previous.segment.kind != SegmentKind::line || next.segment.kind != SegmentKind::line ||
      angle > std::numbers::pi - 1e-3 || !blend(previous, next, angle, out, in)) {
    previous.stop_after = true;
  }
}

bool LookAhead::blend(Piece& previous, Piece& next, double angle, const Eigen::Vector3d& out,
                      const Eigen::Vector3d& in) {
  // The arc tangent to both lines that strays at most the tolerance from them (its middle is
  // r (1 - cos(angle/2)) from either line) and takes at most half of either.
  const double half = angle / 2.0;
  const double tolerance =
      builder_.blend_tolerance_mm() > 0.0 ? builder_.blend_tolerance_mm() : kDefaultBlendTolerance;
  const double tolerance_radius = tolerance / (1.0 - std::cos(half));
  const double length_radius = 0.5 * std::min(previous.length, next.length) / std::tan(half);
  const double radius = std::min(tolerance_radius, length_radius);
  if (!(radius > 1e-9)) return false;
  const double cut = radius * std::tan(half);
  const Eigen::Vector3d corner = previous.segment.end.head<3>();
  Segment blend;
  blend.kind = SegmentKind::blend;
  blend.line = next.segment.line;
  blend.rapid = next.segment.rapid;
  blend.feed_mm_per_s = next.segment.feed_mm_per_s;
  blend.start = previous.segment.at((previous.length - cut) / previous.length);
  blend.end = next.segment.at(cut / next.length);
  blend.centre = corner + (in - out).normalized() * (radius / std::cos(half));
  blend.radius_mm = radius;
  blend.axis_u = (blend.start.head<3>() - blend.centre).normalized();
  blend.axis_v = out;
  blend.sweep_rad = angle;
  previous.segment.end = blend.start;
  previous.length -= cut;
  previous.grid.ready = false;  // its grid, if planned already, was over the corner
  next.segment.start = blend.end;
  next.length -= cut;
  Piece piece;
  piece.segment = blend;
  piece.length = blend.length();
  // The corner runs at the feed of the move it leads into (the blend's own), as far as the
  // machine allows there (LinuxCNC takes the faster of the two, pkm the one the program set for
  // the path from there on).
  piece.max_speed = limits_.feed_cap(blend);
  piece.acceleration = std::min(previous.acceleration, next.acceleration);
  piece.previous_line = previous.segment.line;
  limits_.limit_by_curvature(piece, radius);
  limits_.limit_by_machine(piece);
  limits_.limit_junction(previous, piece);
  limits_.limit_junction(piece, next);
  limits_.limit_junction_jerk(previous, piece);
  limits_.limit_junction_jerk(piece, next);
  pieces_.push_back(piece);
  return true;
}

void LookAhead::plan_speeds(double entry_speed) {
  if (limits_.time_optimal()) {
    for (Piece& piece : pieces_) {
      if (!piece.grid.ready) limits_.build_grid(piece);
    }
    plan_time_optimal(pieces_, entry_speed, limits_.machine(), limits_.tension());
    return;
  }
  const std::size_t n = pieces_.size();
  // Backward: the fastest each piece may be entered and still brake in time.
  double exit = 0.0;
  for (std::size_t i = n; i-- > 0;) {
    Piece& p = pieces_[i];
    if (p.stop_after) exit = 0.0;
    exit = std::min(exit, p.max_exit_speed);
    p.exit_speed = exit;
    double entry = ramp_for(p).reachable(exit, p.length);
    entry = std::min(entry, p.max_speed);
    if (i > 0) entry = std::min(entry, pieces_[i - 1].max_speed);
    p.entry_speed = entry;
    exit = entry;
  }
  // Forward: the fastest each piece can be reached.
  double speed = entry_speed;
  for (std::size_t i = 0; i < n; ++i) {
    Piece& p = pieces_[i];
    p.entry_speed = std::min(p.entry_speed, speed);
    p.exit_speed = std::min(p.exit_speed, ramp_for(p).reachable(p.entry_speed, p.length));
    speed = p.exit_speed;
  }
}

}  // namespace pkm::motion
