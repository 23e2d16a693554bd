// The largest value of s = v . R p over a box of orientations R = Rz(c) Ry(b) Rx(a) (the
// rotation convention of pose.hpp), bracketed by branch and bound: what a hexapod leg's longest
// and shortest length over an orientation range come down to (|v + R p|^2 = |v|^2 + |p|^2 + 2 s).
// The angle c is solved in closed form (s is a sinusoid in c), so the search splits boxes of
// (a, b) only; docs/workspace.md ("Hexapod legs") gives the bound.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cmath>
#include <vector>

namespace pkm::workspace {

// Bounds on a value: lo is attained (by some orientation of the box), hi is never passed.
struct Bracket {
  double lo = -INFINITY;
  double hi = INFINITY;
};

// What the search must decide, in units of s: whether the largest value passes `above` (then it
// stops with lo > above), or stays at most `below` (then hi <= below). Once lo passes `below`,
// only `above` can still be decided, and boxes whose bound is at most `above` are not split.
// Boxes whose bound is within `tolerance` of the best value found are not split either: with
// both thresholds infinite the search brackets the largest value to `tolerance`.
struct SearchGoal {
  double above = INFINITY;
  double below = -INFINITY;
  double tolerance = 0.0;
};

// The boxes of (a, b) the searches visit, as a tree below one root box: each box's Ry(b) Rx(a)
// and its two partial derivatives at the box's middle, computed once and reused by every leg,
// both directions and every position cell searched over the same range (a fixed split rule makes
// a box a function of its path from the root). Per-thread scratch, not shared.
class TiltTree {
 public:
  // The range of c, as what the closed form over it needs.
  struct Arc {
    double cos_low, sin_low, cos_high, sin_high;  // its ends
    double cos_mid, sin_mid, cos_half;            // its middle and half-width
  };
  struct Node {
    Eigen::Vector2d centre, half;  // a, b (rad)
    Eigen::Matrix3d tilt;          // Ry(b) Rx(a) at the centre
    Eigen::Matrix3d tilt_da, tilt_db;
    std::array<int, 2> child{-1, -1};
  };
  // Starts again from the root box of an orientation range (a b c, rad).
  void reset(const Eigen::Vector3d& centre, const Eigen::Vector3d& half);
  bool has_root(const Eigen::Vector3d& centre, const Eigen::Vector3d& half) const {
    return !nodes_.empty() && root_centre_ == centre && root_half_ == half;
  }
  const Arc& arc() const { return arc_; }
  // Child `which` (0: the lower half) of `node`, split along its wider half-width; -1 when the
  // tree is full (the caller then evaluates the box itself).
  int child(int node, int which);
  const Node& operator[](int node) const { return nodes_[static_cast<std::size_t>(node)]; }
  bool full() const { return nodes_.size() >= kMaxNodes; }

  static constexpr std::size_t kMaxNodes = 1u << 16;  // ~16 MB at most

 private:
  int add(const Eigen::Vector2d& centre, const Eigen::Vector2d& half);
  std::vector<Node> nodes_;
  Eigen::Vector3d root_centre_ = Eigen::Vector3d::Zero(), root_half_ = Eigen::Vector3d::Zero();
  Arc arc_{};
};

class OrientationSearch {
 public:
  // The largest s = v . R p over a b c within centre +- half (rad), bracketed for `goal`.
  Bracket largest(const Eigen::Vector3d& v, const Eigen::Vector3d& p,
                  const Eigen::Vector3d& centre_rad, const Eigen::Vector3d& half_rad,
                  const SearchGoal& goal);
  long boxes_searched() const { return boxes_; }

 private:
  TiltTree& tree_for(const Eigen::Vector3d& centre, const Eigen::Vector3d& half);
  std::array<TiltTree, 4> trees_;
  std::size_t next_tree_ = 0;
  long boxes_ = 0;
};

// One end of a hexapod leg: the base joint at the origin of v, the platform joint at v + R p
// (mm); its neutral axis (unit) fixed in the world (a base joint) or turning with the platform
// (R axis, a platform joint).
struct LegJointEnd {
  Eigen::Vector3d v = Eigen::Vector3d::Zero(), p = Eigen::Vector3d::Zero();
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();
  bool turns_with_platform = false;
};

// The largest of -cos(angle between the leg and the end's axis) over a b c within centre +- half
// (rad), bracketed for `goal`: a branch and bound over boxes of (a, b, c), each bounded by its
// value and gradient at the middle and a bound on the second derivative (docs/workspace.md,
// "Joint angles"). Not cached: only cells near an angle limit search more than one box.
Bracket largest_joint_turn(const LegJointEnd& end, const Eigen::Vector3d& centre_rad,
                           const Eigen::Vector3d& half_rad, const SearchGoal& goal);

}  // namespace pkm::workspace
