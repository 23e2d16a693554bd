#include "pkm/post/covering.hpp"

#include <algorithm>

namespace pkm::post {

namespace {

constexpr int kMaxDepth = 40;    // halvings of one move before giving up
constexpr int kBisections = 10;  // between the last end that fits and the first that does not

}  // namespace

bool Covering::fits(std::size_t count, double end, JointsAt& at, double& deviation_mm) const {
  at = host_.joints_at(pieces_[count - 1].segment, end);
  deviation_mm = host_.deviation(
      span_to(count, end), {start_joints_.written, start_joints_.exact, at.written, at.exact});
  return deviation_mm <= tolerance_mm_;
}

// Writes the block from the open block's start to fraction `end` of piece count - 1, which then
// starts the open block (or the piece after it, where the block took that piece whole).
void Covering::write_and_restart(std::size_t count, double end, const JointsAt& at,
                                 double deviation_mm) {
  host_.write_block(span_to(count, end), at.written, deviation_mm);
  std::size_t done = count - 1;
  if (end >= pieces_[count - 1].to && count < pieces_.size()) done = count;
  pieces_.erase(pieces_.begin(), pieces_.begin() + static_cast<std::ptrdiff_t>(done));
  start_ = done == count ? pieces_.front().from : end;
  start_joints_ = at;
}

void Covering::add(const motion::Segment& segment, double from, double to) {
  if (!(from < to)) return;  // nothing to trace
  if (pieces_.empty()) {
    start_ = from;
    start_joints_ = {host_.joints_at(segment, from).exact, host_.written_joints()};
    pieces_.push_back({segment, from, to});
    cover_last_piece();
    return;
  }
  pieces_.push_back({segment, from, to});
  if (pieces_.size() > kMaxSpanMoves) {
    write_and_restart(pieces_.size() - 1, pieces_[pieces_.size() - 2].to, open_end_,
                      open_deviation_mm_);
    cover_last_piece();
    return;
  }
  JointsAt at;
  double deviation_mm = 0.0;
  if (fits(pieces_.size(), to, at, deviation_mm)) {
    open_end_ = at;
    open_deviation_mm_ = deviation_mm;
    return;
  }
  end_in_last_piece();
  cover_last_piece();
}

void Covering::finish() {
  if (pieces_.empty()) return;
  host_.write_block(span_to(pieces_.size(), pieces_.back().to), open_end_.written,
                    open_deviation_mm_);
  pieces_.clear();
}

// The open block fits up to the start of the last piece and not to its end: it ends in between,
// as far as bisection finds, or at the piece's start. Where it cannot go even a bisection's step
// into the piece (a corner, or a block whose budget the moves before have spent), one test says
// so.
void Covering::end_in_last_piece() {
  const std::size_t count = pieces_.size();
  double good = pieces_.back().from, bad = pieces_.back().to;
  JointsAt good_at = open_end_, at;
  double good_deviation = open_deviation_mm_, deviation_mm = 0.0;
  const double step = good + (bad - good) / (1 << kBisections);
  if (!fits(count, step, at, deviation_mm)) {
    write_and_restart(count - 1, pieces_[count - 2].to, good_at, good_deviation);
    return;
  }
  good = step;
  good_at = at;
  good_deviation = deviation_mm;
  for (int i = 0; i < kBisections; ++i) {
    const double middle = 0.5 * (good + bad);
    if (fits(count, middle, at, deviation_mm)) {
      good = middle;
      good_at = at;
      good_deviation = deviation_mm;
    } else {
      bad = middle;
    }
  }
  if (good > pieces_.back().from) {
    write_and_restart(count, good, good_at, good_deviation);
  } else {
    write_and_restart(count - 1, pieces_[count - 2].to, good_at, good_deviation);
  }
}

// The open block starts in the only piece held: blocks as long as the tolerance allows, from
// each block's start the furthest end found by halving, then bisection, until the one to the
// piece's end fits, which stays open. Block lengths follow how sharply the kinematics bends the
// path.
void Covering::cover_last_piece() {
  const double to = pieces_.back().to;
  JointsAt candidate, good_at;
  double deviation_mm = 0.0;
  while (!fits(1, to, candidate, deviation_mm)) {
    double good = -1.0, good_deviation = 0.0;
    double step = 0.5 * (to - start_);
    for (int halvings = 0; halvings < kMaxDepth && good < 0.0; ++halvings, step *= 0.5) {
      if (fits(1, start_ + step, candidate, deviation_mm)) {
        good = start_ + step;
        good_deviation = deviation_mm;
        good_at = candidate;
      }
    }
    if (good < 0.0) host_.cannot_keep_within(pieces_.back().segment);
    // Between `good` (within) and twice the step (not, or the end): bisect for the furthest.
    double bad = std::min(to, start_ + 4.0 * step);
    for (int i = 0; i < kBisections; ++i) {
      const double middle = 0.5 * (good + bad);
      if (fits(1, middle, candidate, deviation_mm)) {
        good = middle;
        good_deviation = deviation_mm;
        good_at = candidate;
      } else {
        bad = middle;
      }
    }
    write_and_restart(1, good, good_at, good_deviation);
  }
  open_end_ = candidate;
  open_deviation_mm_ = deviation_mm;
}

}  // namespace pkm::post
