#include "pkm/verify/job_cursor.hpp"

#include <algorithm>
#include <cmath>

namespace pkm::verify {

namespace {

// Moves a dwell walks at most: stopping short only leaves less of the job traced.
constexpr long kMaxDwellPieces = 100000;
constexpr int kArcSteps = 64;  // samples of an arc piece in a dwell

// The largest fraction u in [u0, 1] of a move such that the move from u0 to u lies within
// `radius_mm` of `point`, where its point at u0 does; u0 where it does not.
double last_within(const JobPiece& piece, double u0, const Eigen::Vector3d& point,
                   double radius_mm) {
  const Eigen::Vector3d a = piece.point(u0);
  if ((a - point).norm() > radius_mm) return u0;
  if (piece.segment.kind != motion::SegmentKind::arc) {
    // A line: the ball holds one interval of it, from u0 to the larger root of |a + t d - p| = r.
    const Eigen::Vector3d d = piece.point(1.0) - a, w = a - point;
    const double dd = d.squaredNorm();
    if (dd <= 0.0) return 1.0;
    const double dw = d.dot(w);
    const double root =
        (-dw + std::sqrt(std::max(0.0, dw * dw - dd * (w.squaredNorm() - radius_mm * radius_mm)))) /
        dd;
    return root >= 1.0 ? 1.0 : u0 + std::max(0.0, root) * (1.0 - u0);
  }
  // An arc: samples within the ball shrunk by the arc's sagitta over one step (the controlled
  // path is a projection, which sags no more); the last sample before one outside.
  const double step = (1.0 - u0) / kArcSteps;
  const double step_mm = step * std::max(piece.segment.length(), piece.length_mm);
  const double sag_mm = piece.curvature_per_mm * step_mm * step_mm / 8.0;
  double good = u0;
  for (int k = 1; k <= kArcSteps; ++k) {
    const double u = k == kArcSteps ? 1.0 : u0 + k * step;
    if ((piece.point(u) - point).norm() > radius_mm - sag_mm) return good;
    good = u;
  }
  return good;
}

}  // namespace

JobPlace JobCursor::dwell_end(const JobPlace& end, const Eigen::Vector3d& point, double radius_mm) {
  JobPlace reached = end;
  for (long index = end.piece; index < end.piece + kMaxDwellPieces; ++index) {
    const JobPiece* piece = path_.piece(index);
    if (!piece) break;
    const double u0 = index == end.piece ? end.u : 0.0;
    if (piece->length_mm <= 0.0) continue;  // no controlled path: stays where it is
    const double u = last_within(*piece, u0, point, radius_mm);
    if (u > u0) reached = {index, u};
    if (u < 1.0) break;
  }
  return reached;
}

double JobCursor::inside_box_until_mm(const Eigen::AlignedBox3d& box) {
  double until = reached_along_mm();
  for (long index = reached_.piece; index < reached_.piece + kMaxDwellPieces; ++index) {
    const JobPiece* piece = path_.piece(index);
    if (!piece) break;
    if (piece->length_mm <= 0.0) continue;
    const double u0 = index == reached_.piece ? reached_.u : 0.0;
    const Eigen::Vector3d a = piece->point(u0), b = piece->point(1.0);
    if (!box.contains(a)) break;
    if (piece->segment.kind != motion::SegmentKind::arc && !box.contains(b)) {
      // A line leaves the box where it first crosses one of its sides.
      double t = 1.0;
      for (int axis = 0; axis < 3; ++axis) {
        const double d = b[axis] - a[axis];
        if (d > 0.0) t = std::min(t, (box.max()[axis] - a[axis]) / d);
        if (d < 0.0) t = std::min(t, (box.min()[axis] - a[axis]) / d);
      }
      until = piece->start_mm + (u0 + std::max(0.0, t) * (1.0 - u0)) * piece->length_mm;
      break;
    }
    if (!box.contains(b)) break;
    if (piece->segment.kind == motion::SegmentKind::arc) {
      // Samples within the box shrunk by the arc's sagitta over one step.
      const double step_mm =
          (1.0 - u0) / kArcSteps * std::max(piece->segment.length(), piece->length_mm);
      const double sag_mm = piece->curvature_per_mm * step_mm * step_mm / 8.0;
      const Eigen::Vector3d shrink = Eigen::Vector3d::Constant(sag_mm);
      const Eigen::AlignedBox3d inner(box.min() + shrink, box.max() - shrink);
      bool inside = true;
      for (int k = 1; k < kArcSteps && inside; ++k) {
        inside = inner.contains(piece->point(u0 + k * (1.0 - u0) / kArcSteps));
      }
      if (!inside) break;
    }
    until = piece->start_mm + piece->length_mm;
  }
  return until;
}

JobPlace JobCursor::find_end(const Eigen::Vector3d& point, double reach_mm, double slack_mm,
                             double inside_until_mm) {
  candidates_.clear();
  const double limit = std::max(reached_along_mm() + reach_mm, inside_until_mm);
  for (long index = place_.piece;; ++index) {
    const JobPiece* piece = path_.piece(index);
    if (!piece || piece->start_mm > limit) break;
    if (piece->length_mm <= 0.0) continue;
    const double u0 = index == place_.piece ? place_.u : 0.0;
    const double u1 = std::max(u0, std::min(1.0, (limit - piece->start_mm) / piece->length_mm));
    const Nearest nearest = nearest_on(*piece, point, u0, u1);
    candidates_.push_back({nearest, index, nearest.u <= u0, nearest.u >= 1.0});
  }
  if (candidates_.empty()) return place_;
  double smallest = INFINITY;
  for (const Candidate& c : candidates_) smallest = std::min(smallest, c.nearest.distance_mm);
  for (std::size_t k = 0; k < candidates_.size(); ++k) {
    const Candidate& c = candidates_[k];
    if (c.nearest.distance_mm > smallest + slack_mm) continue;
    // The end of a move is no minimum when the next move goes on nearer.
    const bool next_nearer = k + 1 < candidates_.size() && c.at_end &&
                             candidates_[k + 1].at_start &&
                             candidates_[k + 1].nearest.distance_mm < c.nearest.distance_mm;
    if (!next_nearer) return {c.piece, c.nearest.u};
  }
  const Candidate& last = candidates_.back();
  return {last.piece, last.nearest.u};
}

void JobCursor::stretch_to(const JobPlace& end, std::vector<PieceRange>& ranges) {
  ranges.clear();
  for (long index = place_.piece; index <= end.piece; ++index) {
    const JobPiece* piece = path_.piece(index);
    if (!piece) break;
    const double u0 = index == place_.piece ? place_.u : 0.0;
    const double u1 = index == end.piece ? end.u : 1.0;
    if (piece->length_mm > 0.0 && u1 > u0) ranges.push_back({piece, u0, u1});
  }
  if (ranges.empty()) {
    const JobPiece* piece = path_.piece(place_.piece);
    if (piece) ranges.push_back({piece, place_.u, place_.u});
  }
}

void JobCursor::point_reached(std::vector<PieceRange>& ranges) {
  ranges.clear();
  const JobPiece* piece = path_.piece(reached_.piece);
  if (piece) ranges.push_back({piece, reached_.u, reached_.u});
}

void JobCursor::advance(const JobPlace& end, const JobPlace& reached) {
  if (end.before(place_)) return;
  place_ = end;
  reached_ = reached;
  path_.forget_before(place_.piece);
}

double JobCursor::along_mm(const JobPlace& place) {
  const JobPiece* piece = path_.piece(place.piece);
  return piece ? piece->start_mm + place.u * piece->length_mm : 0.0;
}

double JobCursor::along_mm() {
  return along_mm(place_);
}

double JobCursor::reached_along_mm() {
  return along_mm(reached_);
}

int JobCursor::line() {
  const JobPiece* piece = path_.piece(place_.piece);
  return piece ? piece->line() : path_.end_line();
}

JobCursor::Rest JobCursor::rest() {
  Rest rest;
  rest.traced_mm = rest.job_length_mm = reached_along_mm();
  for (long index = reached_.piece;; ++index) {
    const JobPiece* piece = path_.piece(index);
    if (!piece) break;
    const double u0 = index == reached_.piece ? reached_.u : 0.0;
    if (rest.first_line == 0 && u0 < 1.0 && piece->length_mm > 0.0) rest.first_line = piece->line();
    rest.job_length_mm = piece->start_mm + piece->length_mm;
    path_.forget_before(index);
  }
  return rest;
}

}  // namespace pkm::verify
