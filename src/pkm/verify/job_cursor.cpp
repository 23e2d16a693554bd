#include "pkm/verify/job_cursor.hpp"

#include <algorithm>
#include <cmath>

namespace pkm::verify {

JobPlace JobCursor::find_end(const Eigen::Vector3d& point, double reach_mm, double slack_mm) {
  candidates_.clear();
  const double limit = along_mm() + reach_mm;
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

void JobCursor::advance(const JobPlace& end) {
  if (end.piece < place_.piece || (end.piece == place_.piece && end.u < place_.u)) return;
  place_ = end;
  path_.forget_before(place_.piece);
}

double JobCursor::along_mm() {
  const JobPiece* piece = path_.piece(place_.piece);
  return piece ? piece->start_mm + place_.u * piece->length_mm : 0.0;
}

int JobCursor::line() {
  const JobPiece* piece = path_.piece(place_.piece);
  return piece ? piece->line() : path_.end_line();
}

JobCursor::Rest JobCursor::rest() {
  Rest rest;
  rest.traced_mm = rest.job_length_mm = along_mm();
  for (long index = place_.piece;; ++index) {
    const JobPiece* piece = path_.piece(index);
    if (!piece) break;
    const double u0 = index == place_.piece ? place_.u : 0.0;
    if (rest.first_line == 0 && u0 < 1.0 && piece->length_mm > 0.0) rest.first_line = piece->line();
    rest.job_length_mm = piece->start_mm + piece->length_mm;
    path_.forget_before(index);
  }
  return rest;
}

}  // namespace pkm::verify
