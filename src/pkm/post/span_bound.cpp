#include "pkm/post/span_bound.hpp"

#include <algorithm>
#include <cmath>

namespace pkm::post {

double Span::programmed_s() const {
  double seconds = 0.0;
  for (std::size_t k = 0; k < count; ++k) {
    const motion::Segment& segment = pieces[k].segment;
    seconds += segment.length() * (to(k) - from(k)) / segment.feed_mm_per_s;
  }
  return seconds;
}

namespace {

// The position coordinates among `axes` of a pose (mm); the others zero, so they never count.
Eigen::Vector3d controlled_position(const Vector6d& pose, const std::vector<int>& axes) {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  for (const int axis : axes) {
    if (axis < 3) position[axis] = pose[axis];
  }
  return position;
}

}  // namespace

// Let C(l) be the chord from the span's start to its end, and give each vertex V_k (a piece's
// end) the fraction m_k of its projection on the chord, clamped to [0, 1] and never below the
// vertex before. Read the path at fraction l as the piece between the vertices whose fractions
// enclose l, linear in between (a reparametrisation that never goes back). On such an interval a
// line piece minus the chord is linear, so its norm is largest at an end: a vertex's distance.
// An arc piece is within its sagitta bound |S''| / 8 of the line between its ends at the same
// fraction (the remainder of linear interpolation, as for a single block), which adds. Where
// several vertices share one fraction, the path between them is taken at that one point of the
// chord, and the same two terms bound its distance from it.
double chord_offset_mm(const Span& span, const std::vector<int>& axes, double angle_scale_mm) {
  const Eigen::Vector3d start = controlled_position(span.start_pose(), axes);
  const Eigen::Vector3d chord = controlled_position(span.end_pose(), axes) - start;
  const double squared = chord.squaredNorm();
  double fraction = 0.0, vertices = 0.0, sagitta = 0.0;
  for (std::size_t k = 0; k < span.count; ++k) {
    const motion::Segment& segment = span.pieces[k].segment;
    if (segment.kind != motion::SegmentKind::line) {
      const PieceMotion piece =
          piece_motion(segment, span.from(k), span.to(k), axes, angle_scale_mm);
      sagitta = std::max(sagitta, piece.acceleration / 8.0);
    }
    if (k + 1 == span.count) break;  // the span's end is the chord's end
    const Eigen::Vector3d vertex = controlled_position(segment.at(span.to(k)), axes) - start;
    if (squared > 0.0)
      fraction = std::max(fraction, std::clamp(vertex.dot(chord) / squared, 0.0, 1.0));
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
