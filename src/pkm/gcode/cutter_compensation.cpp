#include "pkm/gcode/cutter_compensation.hpp"

#include <cmath>
#include <numbers>
#include <string>

namespace pkm::gcode {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kHalfPi = kPi / 2.0;
// A join turning by less than this is straight through; more than this either way of a
// reversal is a corner (LinuxCNC's TOLERANCE_CONCAVE_CORNER), rad.
constexpr double kCornerAngle = 0.05;
// An entry arc whose end is this close to perpendicular to its chord has no centre (rad cosine).
constexpr double kNoCentre = 1e-4;
// How far an arc's end may move off its circle when its end moves into a corner (program units).
constexpr double kOffCircle = 0.01;
// How much longer an arc may become when its end moves into a corner before it gouges, rad.
constexpr double kLongerSweep = 0.001;

int first_axis(Plane plane) {
  return plane == Plane::xz ? 2 : 0;
}
int second_axis(Plane plane) {
  return plane == Plane::xz ? 0 : 1;
}
int normal_axis(Plane plane) {
  return plane == Plane::xz ? 1 : 2;
}

bool is_move(CanonKind kind) {
  return kind == CanonKind::traverse || kind == CanonKind::feed || kind == CanonKind::arc;
}

double direction_of(PlanePoint from, PlanePoint to) {
  return std::atan2(to.second - from.second, to.first - from.first);
}
double distance(PlanePoint a, PlanePoint b) {
  return std::hypot(a.first - b.first, a.second - b.second);
}
PlanePoint step(PlanePoint from, double length, double angle) {
  return {from.first + length * std::cos(angle), from.second + length * std::sin(angle)};
}
PlanePoint centre_of(const Canon& arc) {
  return {arc.center[0], arc.center[1]};
}

// The angle an arc of `turns` sweeps from `start` to `end` about `centre` (+ counterclockwise).
double swept_angle(PlanePoint start, PlanePoint centre, int turns, PlanePoint end) {
  if (turns == 0) return 0.0;
  double from = direction_of(centre, start), to = direction_of(centre, end);
  if (turns > 0) {
    if (to <= from) to += 2.0 * kPi;
    return to - from + (turns - 1) * 2.0 * kPi;
  }
  if (from <= to) from += 2.0 * kPi;
  return to - from + (turns + 1) * 2.0 * kPi;
}

// The length of a straight move from `start` to `end`: through X Y Z, or through the other axes
// when those stay (as LinuxCNC measures an inverse-time move).
double straight_length(const Position& start, const Position& end) {
  double linear = 0.0, other = 0.0;
  for (int axis = 0; axis < kAxes; ++axis) {
    const double step = end[axis] - start[axis];
    (axis < 3 ? linear : other) += step * step;
  }
  return linear > 0.0 ? std::sqrt(linear) : std::sqrt(other);
}

// In inverse time (G93) F says how long the programmed move takes. The compensated path is
// longer or shorter and may gain a corner arc, so, as LinuxCNC does, F becomes the feed rate
// that gives the programmed move that time, and every piece of it runs at that rate.
void to_feed_rate(Canon& move, double programmed_length) {
  if (move.feed_mode != FeedMode::inverse_time) return;
  move.feed_mode = FeedMode::units_per_minute;
  move.value *= programmed_length;
}

// asin/acos argument out of range: the corner has no point where the offset paths meet.
void require_fit(double cosine_or_sine, const char* what) {
  if (cosine_or_sine > 1.0 || cosine_or_sine < -1.0) {
    throw CompensationError(std::string(what) +
                            " makes a corner the compensated tool cannot fit in without gouging");
  }
}

}  // namespace

void CutterCompensation::reset(const Sink& out) {
  out_ = &out;
  side_ = CompensationSide::off;
  radius_ = 0.0;
  entering_ = true;
  start_known_ = false;
  held_.clear();
}

PlanePoint CutterCompensation::in_plane(const Position& position) const {
  return {position[first_axis(plane_)], position[second_axis(plane_)]};
}

void CutterCompensation::set_in_plane(Position& position, PlanePoint point) const {
  position[first_axis(plane_)] = point.first;
  position[second_axis(plane_)] = point.second;
}

bool CutterCompensation::tool_inside(int turns) const {
  return (side_ == CompensationSide::left && turns > 0) ||
         (side_ == CompensationSide::right && turns < 0);
}

const CutterCompensation::Held* CutterCompensation::previous_move() const {
  if (held_.empty() || !is_move(held_.front().canon.kind)) return nullptr;
  return &held_.front();
}

Position CutterCompensation::from_tip(Position position) const {
  if (plane_ != Plane::xz || !lathe_tool()) return position;
  // LinuxCNC's table: orientations 1, 2 and 6 put the tip below the centre in X, 3, 4 and 8
  // above it; 2, 3 and 7 below it in Z, 1, 4 and 5 above it.
  const int o = orientation_;
  if (o == 1 || o == 2 || o == 6) position[0] -= radius_;
  if (o == 3 || o == 4 || o == 8) position[0] += radius_;
  if (o == 2 || o == 3 || o == 7) position[2] -= radius_;
  if (o == 1 || o == 4 || o == 5) position[2] += radius_;
  return position;
}

void CutterCompensation::send(const Canon& canon) const {
  if (!is_move(canon.kind) || !lathe_tool() || plane_ != Plane::xz) return (*out_)(canon);
  Canon moved = canon;
  moved.end = from_tip(canon.end);
  if (canon.kind == CanonKind::arc) {
    // The centre is (Z, X), the plane's order.
    Position centre{};
    centre[2] = canon.center[0];
    centre[0] = canon.center[1];
    centre = from_tip(centre);
    moved.center = {centre[2], centre[0]};
  }
  (*out_)(moved);
}

void CutterCompensation::turn_on(CompensationSide side, double radius, Plane plane,
                                 int orientation) {
  if (radius < 0.0) {
    // A negative diameter in the tool table (a worn tool below nominal) cuts on the other side.
    radius = -radius;
    side = side == CompensationSide::left ? CompensationSide::right : CompensationSide::left;
  }
  side_ = side;
  radius_ = radius;
  plane_ = plane;
  orientation_ = orientation;
  entering_ = true;
}

bool CutterCompensation::turn_off() {
  const bool ended = offsetting() && !entering_;
  if (ended) flush();
  side_ = CompensationSide::off;
  entering_ = true;
  return ended;
}

void CutterCompensation::flush() {
  end_held_at(tool_);
  release();
}

void CutterCompensation::release() {
  for (const Held& held : held_) send(held.canon);
  held_.clear();
  start_known_ = false;
}

void CutterCompensation::end_held_at(PlanePoint end) {
  if (held_.empty()) return;
  // More than one move can be held: a move with no motion in the plane (down into the corner
  // and up again) waits behind the move before it. All of them end at the corner.
  for (Held& held : held_) {
    Canon& move = held.canon;
    if (held.lathe_lead_in) {
      // LinuxCNC moves this feed's end too, to the arc's end: the arc then starts where it
      // ends, a full circle. Refused rather than cut so, or cut otherwise than LinuxCNC does.
      throw CompensationError(
          "the lathe tool's cutter compensation starts with the arc on line " +
          std::to_string(move.line) +
          ", and this move does not continue it tangentially: LinuxCNC would cut that arc as a "
          "full circle. Enter with a straight move (G1) before the arc");
    }
    if (move.kind == CanonKind::arc) {
      const PlanePoint centre = centre_of(move);
      if (std::abs(distance(centre, in_plane(move.end)) - distance(centre, end)) > kOffCircle) {
        throw CompensationError(
            "cutter compensation moved an arc's end off its circle (an internal error)");
      }
      if (held.sweep != 0.0 && start_known_ &&
          std::abs(swept_angle(start_, centre, move.turns, end)) >
              std::abs(held.sweep) + kLongerSweep) {
        throw CompensationError(
            "the arc into this concave corner cannot be cut without gouging: the tool does not "
            "fit");
      }
      set_in_plane(move.end, end);
    } else if (move.kind == CanonKind::traverse || move.kind == CanonKind::feed) {
      // Moving the end back past the start would reverse the move: the tool does not fit.
      const double along = held.direction.first * (end.first - start_.first) +
                           held.direction.second * (end.second - start_.second);
      if (start_known_ && along < 0.0) {
        throw CompensationError(
            std::string("the straight ") +
            (move.kind == CanonKind::traverse ? "traverse" : "feed") +
            " into this concave corner cannot be cut without gouging: the tool does not fit");
      }
      set_in_plane(move.end, end);
    }
  }
  release();
  set_start(end);
}

void CutterCompensation::round_corner(const Canon& move, const Position& start, PlanePoint corner,
                                      PlanePoint to) {
  // The axis normal to the plane stays where it is until the move itself; the other axes reach
  // their end values on the corner already, as LinuxCNC has it.
  Canon around = move;
  set_in_plane(around.end, to);
  around.end[normal_axis(plane_)] = start[normal_axis(plane_)];
  if (move.kind != CanonKind::traverse) {
    around.kind = CanonKind::arc;
    around.center = {corner.first, corner.second};
    around.turns = side_ == CompensationSide::left ? -1 : 1;
  }
  send(around);
  set_start(to);
}

void CutterCompensation::enter_straight(Canon move, const Position& start) {
  // The tool ends one radius off the programmed end, square to the line from where it starts.
  const PlanePoint from = in_plane(start), to = in_plane(move.end);
  if (distance(from, to) <= radius_) {
    throw CompensationError(
        "the cutter compensation entry move is not longer than the tool radius");
  }
  const double sign = side_ == CompensationSide::left ? 1.0 : -1.0;
  const double normal = direction_of(from, to) + sign * kHalfPi;
  const PlanePoint end = step(to, radius_, normal);
  set_in_plane(move.end, end);
  set_start(from);
  hold(move, {std::cos(normal), std::sin(normal)}, 0.0);
  tool_ = end;
  entering_ = false;
}

void CutterCompensation::enter_arc(Canon move, const Position& start) {
  const PlanePoint from = in_plane(start), to = in_plane(move.end), centre = centre_of(move);
  if (distance(from, to) <= radius_) {
    throw CompensationError(
        "the cutter compensation entry arc does not end more than the tool radius from its "
        "start");
  }
  const bool inside = tool_inside(move.turns);
  if (inside && distance(centre, from) <= radius_) {
    throw CompensationError("the tool radius is not less than the arc's radius");
  }
  // The tool ends one radius off the programmed end along its radius; the compensated arc runs
  // from where the tool is to there, its centre on that same radius line.
  const PlanePoint end =
      step(to, radius_, inside ? direction_of(to, centre) : direction_of(centre, to));
  const double towards_centre = direction_of(end, centre);
  const double angle_at_end = direction_of(end, from) - towards_centre;
  if (std::abs(std::cos(angle_at_end)) < kNoCentre) {
    throw CompensationError("the tool radius is not less than the arc's radius");
  }
  const PlanePoint new_centre =
      step(end, distance(from, end) / 2.0 / std::cos(angle_at_end), towards_centre);
  if (std::abs(distance(new_centre, end) - distance(new_centre, from)) >
      arc_radius_tolerance(move.units)) {
    throw CompensationError("cutter compensation cannot make this entry arc (an internal error)");
  }
  if (lathe_tool()) {
    // LinuxCNC first feeds to the start, so that the tip's move is an arc: from the centre's
    // position to the tip's (the other axes already at the arc's end). A next move that is not
    // tangent would move this feed's end as well (refused in end_held_at).
    Canon to_start = move;
    to_start.kind = CanonKind::feed;
    set_in_plane(to_start.end, from);
    to_start.end[normal_axis(plane_)] = start[normal_axis(plane_)];
    hold(to_start, {}, 0.0, true);
    set_start(from);
  }
  set_in_plane(move.end, end);
  move.center = {new_centre.first, new_centre.second};
  hold(move, {}, swept_angle(from, new_centre, move.turns, end));
  tool_ = end;
  entering_ = false;
}

void CutterCompensation::straight(Canon move, const Position& start) {
  if (move.kind == CanonKind::feed) to_feed_rate(move, straight_length(start, move.end));
  if (entering_) {
    enter_straight(move, start);
    return;
  }
  const PlanePoint corner = in_plane(start), to = in_plane(move.end);
  if (to.first == corner.first && to.second == corner.second) {
    // No motion in the plane: the tool stays where it is, and so does the corner.
    set_in_plane(move.end, tool_);
    hold(move, {}, 0.0);
    return;
  }
  const bool left = side_ == CompensationSide::left;
  const double to_side = left ? kHalfPi : -kHalfPi;
  // The direction from the programmed corner to the tool is square to the path arriving there;
  // `turn` is how far the path turns away from the tool's side: 0 straight on, up to pi an
  // outside corner, below 0 (or past pi) an inside one.
  double tool_direction = direction_of(corner, tool_);
  double heading = direction_of(corner, to);
  double turn = 0.0;
  if (left) {
    if (tool_direction < heading) tool_direction += 2.0 * kPi;
    turn = tool_direction - heading - kHalfPi;
  } else {
    if (heading < tool_direction) heading += 2.0 * kPi;
    turn = heading - tool_direction - kHalfPi;
  }
  const PlanePoint end = step(to, radius_, heading + to_side);
  const Held* previous = previous_move();
  const bool after_arc = previous != nullptr && previous->canon.kind == CanonKind::arc;
  bool concave = turn < -kCornerAngle || turn > kPi + kCornerAngle;
  // Nearly reversing off an arc the tool ran outside of (over the top of an "h"): LinuxCNC
  // keeps the tool on the near side rather than looping round.
  if (!concave && turn > kPi - kCornerAngle && after_arc && !tool_inside(previous->canon.turns)) {
    concave = true;
  }
  if (!concave && turn > kCornerAngle) {
    // Outside corner: round it on an arc about the programmed corner. A traverse has no arc;
    // it goes straight to where the arc would end.
    const PlanePoint around_to = step(corner, radius_, heading + to_side);
    end_held_at(tool_);
    round_corner(move, start, corner, around_to);
  } else if (concave && !after_arc) {
    // Inside corner after a line: that line ends where the two offset lines cross.
    const double half_corner = (turn + kPi) / 2.0;
    if (half_corner == 0.0) {
      throw CompensationError("a zero-degree inside corner cannot be cut with compensation");
    }
    end_held_at(step(tool_, radius_ / std::tan(half_corner), tool_direction + to_side));
  } else if (concave) {
    // Inside corner after an arc: the arc ends where it meets the offset line.
    const Canon& arc = previous->canon;
    const PlanePoint arc_centre = centre_of(arc);
    const double arc_radius = distance(arc_centre, in_plane(arc.end));
    const double line_heading = direction_of(corner, to);
    const double square = arc.turns > 0 ? line_heading + kHalfPi : line_heading - kHalfPi;
    const bool inside = tool_inside(arc.turns);
    const double programmed_radius = inside ? arc_radius + radius_ : arc_radius - radius_;
    const double centre_off_line =
        programmed_radius * std::cos(square - direction_of(corner, arc_centre));
    const double cosine = (centre_off_line + (inside ? -radius_ : radius_)) / arc_radius;
    require_fit(cosine, "this arc-to-line move");
    const bool clockwise_from_square = inside == (arc.turns > 0);
    const double at = square + kPi + (clockwise_from_square ? -1.0 : 1.0) * std::acos(cosine);
    end_held_at(step(arc_centre, arc_radius, at));
  } else {
    release();
    set_start(tool_);
  }
  set_in_plane(move.end, end);
  hold(move, {to.first - corner.first, to.second - corner.second}, 0.0);
  tool_ = end;
}

void CutterCompensation::arc(Canon move, const Position& start) {
  {
    const PlanePoint from = in_plane(start), centre = centre_of(move);
    const double around =
        distance(centre, from) * swept_angle(from, centre, move.turns, in_plane(move.end));
    const int normal = normal_axis(plane_);
    to_feed_rate(move, std::hypot(around, move.end[normal] - start[normal]));
  }
  if (entering_) {
    enter_arc(move, start);
    return;
  }
  const PlanePoint corner = in_plane(start), to = in_plane(move.end), centre = centre_of(move);
  const bool left = side_ == CompensationSide::left;
  const int turns = move.turns;
  const double arc_radius = distance(centre, to);
  // Headings: the path arriving at the corner, and the arc leaving it.
  const double arriving = direction_of(corner, tool_) + (left ? -kHalfPi : kHalfPi);
  const double towards_centre = direction_of(corner, centre);
  const double leaving = turns > 0 ? towards_centre - kHalfPi : towards_centre + kHalfPi;
  double turn = left ? arriving - leaving : leaving - arriving;
  if (turn > 1.5 * kPi) {
    turn -= 2.0 * kPi;
  } else if (turn < -kHalfPi) {
    turn += 2.0 * kPi;
  }
  const bool inside = tool_inside(turns);
  if (inside && arc_radius <= radius_) {
    throw CompensationError("the tool radius is not less than the arc's radius");
  }
  const PlanePoint end =
      step(to, radius_, inside ? direction_of(to, centre) : direction_of(centre, to));
  const double tool_side_at_start = inside ? towards_centre : towards_centre + kPi;
  const Held* previous = previous_move();
  const bool after_arc = previous != nullptr && previous->canon.kind == CanonKind::arc;
  const double sweep = swept_angle(corner, centre, turns, to);

  const bool concave = turn < -kCornerAngle || turn > kPi + kCornerAngle ||
                       (std::abs(turn - kPi) < kCornerAngle && !inside);
  if (concave && !after_arc) {
    // Inside corner after a line: the line ends where it meets the offset arc.
    const double tool_circle = inside ? arc_radius - radius_ : arc_radius + radius_;
    const double across = arc_radius * std::sin(turn - kHalfPi) + (inside ? radius_ : -radius_);
    const double sine = across / tool_circle;
    require_fit(sine, "this line-to-arc move");
    const double at = inside ? arriving + (turns > 0 ? 1.0 : -1.0) * std::asin(sine)
                             : arriving + kPi + (turns > 0 ? -1.0 : 1.0) * std::asin(sine);
    end_held_at(step(centre, tool_circle, at));
  } else if (concave) {
    // Inside corner after an arc: the first arc ends where the two offset circles cross.
    const Canon& before = previous->canon;
    const PlanePoint before_centre = centre_of(before);
    const double before_radius = distance(before_centre, in_plane(before.end));
    const double tool_circle = inside ? arc_radius - radius_ : arc_radius + radius_;
    const double between = distance(before_centre, centre);
    if (before_radius == 0.0 || between == 0.0) {
      throw CompensationError("arc to arc motion is invalid: the arcs have the same centre");
    }
    const double cosine =
        (before_radius * before_radius + between * between - tool_circle * tool_circle) /
        (2.0 * before_radius * between);
    require_fit(cosine, "this arc-to-arc move");
    const double pull_back = std::acos(cosine);
    const double sign = tool_inside(before.turns) == (turns > 0) ? 1.0 : -1.0;
    end_held_at(
        step(before_centre, before_radius, direction_of(before_centre, centre) + sign * pull_back));
  } else if (turn > kCornerAngle) {
    // Outside corner: an arc about the programmed corner to where the tool starts the arc.
    const PlanePoint around_to = step(corner, radius_, tool_side_at_start);
    release();
    round_corner(move, start, corner, around_to);
  } else {
    release();
    set_start(tool_);
  }
  set_in_plane(move.end, end);
  hold(move, {}, sweep);
  tool_ = end;
}

void CutterCompensation::rescale(double factor, LengthUnits units) {
  for (Held& held : held_) {
    Canon& canon = held.canon;
    if (!is_move(canon.kind)) continue;
    for (const int axis : {0, 1, 2, 6, 7, 8}) canon.end[axis] *= factor;
    canon.center[0] *= factor;
    canon.center[1] *= factor;
    if (canon.feed_mode == FeedMode::units_per_minute) canon.value *= factor;
    canon.units = units;
  }
  radius_ *= factor;
  tool_ = {tool_.first * factor, tool_.second * factor};
  start_ = {start_.first * factor, start_.second * factor};
}

}  // namespace pkm::gcode
