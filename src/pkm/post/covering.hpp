// The covering of the programmed path by joint-linear blocks, greedy from each block's start: the
// furthest end whose block keeps within the tolerance. A run of consecutive moves handed in one
// after the other may be spanned by one block (span_bound.hpp); a run of one move is covered on
// its own. The moves are streamed: only those from the open block's start on are held, at most
// kMaxSpanMoves.
#pragma once

#include <cstddef>
#include <vector>

#include "pkm/post/span_bound.hpp"

namespace pkm::post {

// The joints at one point of the programmed path: as the inverse kinematics gives them, and as
// written (rounded to the dialect's decimals).
struct JointsAt {
  kinematics::JointVector exact, written;
};

// What the covering needs of the post-processor: joints, the deviation of a candidate block, and
// the writing of the blocks it settles.
class CoveringHost {
 public:
  virtual ~CoveringHost() = default;
  // Throws where the point is out of the machine's reach.
  virtual JointsAt joints_at(const motion::Segment& segment, double u) const = 0;
  // The joints of the last block written (where the next block starts).
  virtual const kinematics::JointVector& written_joints() const = 0;
  // An upper bound on the block's deviation from the span (or, for models without one, its
  // sampled deviation); infinity where none.
  virtual double deviation(const Span& span, const BlockEnds& ends) const = 0;
  virtual void write_block(const Span& span, const kinematics::JointVector& joints,
                           double deviation_mm) = 0;
  // No block, however short, keeps within the tolerance at the start of this move: throws.
  [[noreturn]] virtual void cannot_keep_within(const motion::Segment& segment) const = 0;
};

class Covering {
 public:
  // A block spans at most this many moves: a bound on what is held and on the work of one test.
  static constexpr std::size_t kMaxSpanMoves = 1000;

  Covering(CoveringHost& host, double tolerance_mm) : host_(host), tolerance_mm_(tolerance_mm) {}

  // Appends the stretch [from, to] of `segment`, which starts where the run's last move ended,
  // and writes every block that can no longer grow. The last block stays open.
  void add(const motion::Segment& segment, double from, double to);
  // The run ends here: its open block is written.
  void finish();
  bool empty() const { return pieces_.empty(); }

 private:
  Span span_to(std::size_t count, double end) const { return {pieces_.data(), count, start_, end}; }
  // The block from the open block's start to fraction `end` of piece count - 1: true when it
  // keeps within the tolerance, with the joints there and its deviation.
  bool fits(std::size_t count, double end, JointsAt& at, double& deviation_mm) const;
  void write_and_restart(std::size_t count, double end, const JointsAt& at, double deviation_mm);
  void end_in_last_piece();
  void cover_last_piece();

  CoveringHost& host_;
  double tolerance_mm_;
  std::vector<Piece> pieces_;  // from the one the open block starts in
  double start_ = 0.0;         // where the open block starts, a fraction of pieces_[0]'s move
  JointsAt start_joints_;
  // The open block, from the start to the end of the last piece, keeps within the tolerance.
  JointsAt open_end_;
  double open_deviation_mm_ = 0.0;
};

}  // namespace pkm::post
