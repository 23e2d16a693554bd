#include "pkm/post/span_bound.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace pkm::post {

double Span::length_mm() const {
  double length = 0.0;
  for (std::size_t k = 0; k < count; ++k) length += pieces[k].segment.length() * (to(k) - from(k));
  return length;
}

double Span::programmed_s(double rapid_mm_per_s) const {
  double seconds = 0.0;
  for (std::size_t k = 0; k < count; ++k) {
    const motion::Segment& segment = pieces[k].segment;
    const double mm_per_s = segment.rapid ? rapid_mm_per_s : segment.feed_mm_per_s;
    seconds += segment.length() * (to(k) - from(k)) / mm_per_s;
  }
  return seconds;
}

namespace {

// The position coordinates among `axes` of a pose (mm); the others zero, so they never count.
Eigen::Vector3d controlled_position(const geometry::Vector6d& pose, const std::vector<int>& axes) {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  for (const int axis : axes) {
    if (axis < 3) position[axis] = pose[axis];
  }
  return position;
}

// A vertex may fall behind the one before along the chord by this much (rounding) and still not
// turn back: verify's "no length" (a move shorter than 1e-9 mm has no path).
constexpr double kNoTurnBackMm = 1e-9;

// The smallest, over the fractions [from, to] of a curved move (an arc, a spiral, a blend), of
// its derivative's component along `direction` (a unit vector in the controlled coordinates), or
// a lower bound on it: S'(u) = r theta (-sin phi e1 + cos phi e2) + dr (cos phi e1 + sin phi e2)
// + dn, phi = phi0 + theta u, r from r0 to r1 linearly. The first term is r theta R cos(phi -
// beta), smallest at an end of the angles or where phi - beta passes pi; the spiral's term is at
// least -|dr| R.
double smallest_advance(const motion::Segment& segment, double from, double to,
                        const Eigen::Vector3d& direction) {
  Eigen::Vector3d e1 = segment.axis_u, e2 = segment.axis_v, normal_step = Eigen::Vector3d::Zero();
  double phi0 = 0.0, r0 = segment.radius_mm, r1 = segment.radius_mm;
  if (segment.kind == motion::SegmentKind::arc) {
    const int a = segment.first_axis, b = segment.second_axis;
    e1 = Eigen::Vector3d::Unit(a);
    e2 = Eigen::Vector3d::Unit(b);
    const Eigen::Vector3d centre = segment.centre;
    phi0 = std::atan2(segment.start[b] - centre[b], segment.start[a] - centre[a]);
    r0 = std::hypot(segment.start[a] - centre[a], segment.start[b] - centre[b]);
    r1 = std::hypot(segment.end[a] - centre[a], segment.end[b] - centre[b]);
    normal_step[segment.normal_axis] =
        segment.end[segment.normal_axis] - segment.start[segment.normal_axis];
  }
  const double theta = segment.sweep_rad;
  // -sin(phi) c1 + cos(phi) c2 = R cos(phi - beta).
  const double c1 = e1.dot(direction), c2 = e2.dot(direction);
  const double radius = std::hypot(c1, c2), beta = std::atan2(-c1, c2);
  const double sign = theta < 0.0 ? -1.0 : 1.0;
  const auto along = [&](double phi) { return sign * radius * std::cos(phi - beta); };
  const double phi_a = phi0 + theta * std::min(from, to), phi_b = phi0 + theta * std::max(from, to);
  const double low = std::min(phi_a, phi_b), high = std::max(phi_a, phi_b);
  double smallest = std::min(along(low), along(high));
  // Where sign * cos(phi - beta) = -1: phi = beta + pi (sign +) or beta (sign -), mod 2 pi.
  const double worst = beta + (sign > 0.0 ? std::numbers::pi : 0.0);
  const double turns = std::ceil((low - worst) / (2.0 * std::numbers::pi));
  if (worst + turns * 2.0 * std::numbers::pi <= high) smallest = -radius;
  const double r_low = std::min(r0, r1), r_high = std::max(r0, r1);
  const double circular = std::abs(theta) * (smallest >= 0.0 ? r_low : r_high) * smallest;
  return circular - std::abs(r1 - r0) * radius + normal_step.dot(direction);
}

}  // namespace

// Let C(l) be the chord from the span's start to its end, and give each vertex V_k (a piece's
// end) the fraction m_k of its projection on the chord. Read the path at fraction l as the piece
// between the vertices whose fractions enclose l, linear in between. On such an interval a line
// piece minus the chord is linear, so its norm is largest at an end: a vertex's distance. An arc
// piece is within its sagitta bound |S''| / 8 of the line between its ends at the same fraction
// (the remainder of linear interpolation, as for a single block), which adds. Where several
// vertices share one fraction, the path between them is taken at that one point of the chord,
// and the same two terms bound its distance from it.
//
// The bound would hold for a path that turns back along the chord too (its fraction held where
// the path goes back), but no span is taken across a turn back: a vertex behind the one before
// or beyond the chord's end, a curved piece whose derivative points back along the chord
// anywhere, a span that ends where it started. Such a path passes the block's end, or points
// within the tolerance of it, more than once, and which pass a block ends at is then no longer
// in the joint program: `pkm verify`, which finds each block's end along the job from the joint
// program alone, could not follow it (docs/post.md, "Spanning moves").
double chord_offset_mm(const Span& span, const std::vector<int>& axes, double angle_scale_mm) {
  const Eigen::Vector3d start = controlled_position(span.start_pose(), axes);
  const Eigen::Vector3d chord = controlled_position(span.end_pose(), axes) - start;
  const double squared = chord.squaredNorm();
  double fraction = 0.0, vertices = 0.0, sagitta = 0.0;
  for (std::size_t k = 0; k < span.count; ++k) {
    const motion::Segment& segment = span.pieces[k].segment;
    if (!(squared > 0.0)) return INFINITY;  // back at its start: it turned back
    if (segment.kind != motion::SegmentKind::line) {
      const bounds::PieceMotion piece =
          bounds::piece_motion(segment, span.from(k), span.to(k), axes, angle_scale_mm);
      sagitta = std::max(sagitta, piece.acceleration / 8.0);
      // It goes back along the chord by at most its smallest advance per unit of fraction (when
      // negative) times its fractions.
      const double advance =
          smallest_advance(segment, span.from(k), span.to(k), chord / std::sqrt(squared));
      if (-advance * (span.to(k) - span.from(k)) > kNoTurnBackMm) return INFINITY;
    }
    if (k + 1 == span.count) break;  // the span's end is the chord's end
    const Eigen::Vector3d vertex = controlled_position(segment.at(span.to(k)), axes) - start;
    const double projected = vertex.dot(chord) / squared;
    const double length = std::sqrt(squared);
    if ((fraction - projected) * length > kNoTurnBackMm ||
        (projected - 1.0) * length > kNoTurnBackMm)
      return INFINITY;
    fraction = std::max(fraction, std::min(projected, 1.0));
    vertices = std::max(vertices, (fraction * chord - vertex).norm());
  }
  return vertices + sagitta;
}

// The block's tool tip is within `bound` of the chord's point at the same fraction (the bound of
// a straight move from the span's start to its end: its ends are the same programmed points, so
// the same joints), and that point within chord_offset_mm of the path's point at its fraction.
double span_deviation_bound(const DeviationBound& bound, const Span& span, const BlockEnds& ends,
                            double give_up_above_mm) {
  if (span.count == 1) return bound(span.first().segment, span.start, span.end, ends);
  const double offset = chord_offset_mm(span, bound.axes(), bound.angle_scale_mm());
  if (!(offset <= give_up_above_mm)) return INFINITY;
  motion::Segment chord;
  chord.kind = motion::SegmentKind::line;
  chord.start = span.start_pose();
  chord.end = span.end_pose();
  chord.z_free = span.first().segment.z_free;
  const double to_chord = bound(chord, 0.0, 1.0, ends);
  if (!std::isfinite(to_chord)) return INFINITY;
  return to_chord + offset;
}

}  // namespace pkm::post
