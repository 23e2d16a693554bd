// The planner's look-ahead (internal to motion/): pieces held back in a window, joined where they
// meet (straight on where tangent, a G64 blend arc at a corner between two lines, a stop
// elsewhere), and given the fastest entry and exit speeds from which every later piece can
// still brake in time.
#pragma once

#include <algorithm>
#include <cstddef>
#include <deque>

#include "pkm/motion/feed_limits.hpp"
#include "pkm/motion/plan_piece.hpp"
#include "pkm/motion/segment_builder.hpp"

namespace pkm::motion {

class LookAhead {
 public:
  // `builder` gives the path mode (G61/G64) and G64's tolerance at the time each piece joins.
  LookAhead(FeedLimits& limits, const SegmentBuilder& builder)
      : limits_(limits), builder_(builder) {}

  // Joins `piece` to the last piece held and holds it; true when the window is full.
  bool add(Piece piece) {
    if (!pieces_.empty()) join(pieces_.back(), piece);
    pieces_.push_back(piece);
    return pieces_.size() >= kWindow;
  }

  // Plans the speeds of the pieces held (braking to a stop at the last one, which later pieces
  // can only relax), entering the first at `entry_speed`, and lets `run` make all of them, or
  // all but the last kKeep (kept for the next look-ahead); `entry_speed` becomes the speed the
  // first piece still held is entered at.
  template <class Run>
  void release(bool all, double& entry_speed, const Run& run) {
    const std::size_t n = pieces_.size();
    if (n == 0) return;
    if (all) pieces_.back().stop_after = true;  // a dwell, a pen change or the end follows
    plan_speeds(entry_speed);
    const std::size_t count = all ? n : n - std::min(n, kKeep);
    for (std::size_t i = 0; i < count; ++i) {
      run(pieces_.front());
      entry_speed = pieces_.front().exit_speed;
      pieces_.pop_front();
    }
  }

 private:
  // Pieces held back for look-ahead: enough to brake from any feed over CAM-sized segments.
  static constexpr std::size_t kWindow = 512;
  static constexpr std::size_t kKeep = 256;

  void join(Piece& previous, Piece& next);
  // The arc within G64's tolerance through the corner between two lines meeting at `angle`
  // (rad), held between them; false where no such arc fits (the lines then stop at the corner).
  bool blend(Piece& previous, Piece& next, double angle, const Eigen::Vector3d& out,
             const Eigen::Vector3d& in);
  // The backward and forward passes over the pieces held.
  void plan_speeds(double entry_speed);

  FeedLimits& limits_;
  const SegmentBuilder& builder_;
  std::deque<Piece> pieces_;
};

}  // namespace pkm::motion
