// Branch and bound over (a, b) with c in closed form (orientation_search.hpp).
#include "pkm/workspace/orientation_search.hpp"

#include <algorithm>

#include "pkm/geometry/pose.hpp"

namespace pkm::workspace {

namespace {

// Ry(b) Rx(a) and its partial derivatives in a and b (rotation_from_abc with c = 0).
void tilt_and_derivatives(const Eigen::Vector2d& ab, Eigen::Matrix3d& tilt,
                          Eigen::Matrix3d& tilt_da, Eigen::Matrix3d& tilt_db) {
  const double sa = std::sin(ab.x()), ca = std::cos(ab.x());
  const double sb = std::sin(ab.y()), cb = std::cos(ab.y());
  tilt << cb, sb * sa, sb * ca,  //
      0.0, ca, -sa,              //
      -sb, cb * sa, cb * ca;
  tilt_da << 0.0, sb * ca, -sb * sa,  //
      0.0, -sa, -ca,                  //
      0.0, cb * ca, -cb * sa;
  tilt_db << -sb, cb * sa, cb * ca,  //
      0.0, 0.0, 0.0,                 //
      -cb, -sb * sa, -sb * ca;
}

// v . Rz(c) q = along cos c + across sin c + vertical.
struct Sinusoid {
  double along = 0.0, across = 0.0, vertical = 0.0;
};

Sinusoid sinusoid_of(const Eigen::Vector3d& v, const Eigen::Vector3d& q) {
  return {v.x() * q.x() + v.y() * q.y(), v.y() * q.x() - v.x() * q.y(), v.z() * q.z()};
}

// The largest of along cos c + across sin c over the arc of c: the amplitude where the peak's
// angle lies on the arc, else the larger end. `attained` asks for a value some c of the arc
// reaches; otherwise the peak is taken wherever rounding could leave its angle in doubt (an
// upper bound).
double largest_on_arc(double along, double across, const TiltTree::Arc& arc, bool attained) {
  const double amplitude = std::sqrt(along * along + across * across);
  const double towards_mid = along * arc.cos_mid + across * arc.sin_mid;
  const double slack = attained ? 0.0 : 1e-12 * amplitude;
  if (towards_mid >= amplitude * arc.cos_half - slack) return amplitude;
  return std::max(along * arc.cos_low + across * arc.sin_low,
                  along * arc.cos_high + across * arc.sin_high);
}

}  // namespace

void TiltTree::reset(const Eigen::Vector3d& centre, const Eigen::Vector3d& half) {
  nodes_.clear();
  root_centre_ = centre;
  root_half_ = half;
  const double low = centre.z() - half.z(), high = centre.z() + half.z();
  arc_ = {std::cos(low),
          std::sin(low),
          std::cos(high),
          std::sin(high),
          std::cos(centre.z()),
          std::sin(centre.z()),
          std::cos(std::min(half.z(), M_PI))};
  add(centre.head<2>(), half.head<2>());
}

int TiltTree::add(const Eigen::Vector2d& centre, const Eigen::Vector2d& half) {
  Node node;
  node.centre = centre;
  node.half = half;
  tilt_and_derivatives(centre, node.tilt, node.tilt_da, node.tilt_db);
  nodes_.push_back(node);
  return static_cast<int>(nodes_.size()) - 1;
}

int TiltTree::child(int node, int which) {
  const auto k = static_cast<std::size_t>(node);
  const auto w = static_cast<std::size_t>(which);
  if (nodes_[k].child[w] >= 0) return nodes_[k].child[w];
  if (full()) return -1;
  Eigen::Vector2d centre = nodes_[k].centre, half = nodes_[k].half;
  const int axis = half.x() >= half.y() ? 0 : 1;
  half[axis] *= 0.5;
  centre[axis] += which == 0 ? -half[axis] : half[axis];
  const int made = add(centre, half);
  nodes_[k].child[w] = made;
  return made;
}

TiltTree& OrientationSearch::tree_for(const Eigen::Vector3d& centre, const Eigen::Vector3d& half) {
  for (TiltTree& tree : trees_) {
    if (tree.has_root(centre, half)) return tree;
  }
  TiltTree& tree = trees_[next_tree_];
  next_tree_ = (next_tree_ + 1) % trees_.size();
  tree.reset(centre, half);
  return tree;
}

namespace {

// The branch and bound both searches share: boxes of D angles, each evaluated (value attained
// at some orientation of the box, upper bound over it) when made, split along the widest angle
// while the goal is still open, the more promising half first.
template <int D>
struct BranchBox {
  Eigen::Matrix<double, D, 1> centre, half;
  int node = -1;  // in a TiltTree, or -1 when evaluated by the caller
  double value = 0.0, upper = 0.0;
};

template <int D, class Evaluate, class ChildNode>
Bracket branch_and_bound(BranchBox<D> root, const SearchGoal& goal, Evaluate&& evaluate,
                         ChildNode&& child_node, long& boxes_total) {
  constexpr int kMaxBoxes = 4096;
  evaluate(root);
  double best = root.value, closed = -INFINITY;
  int boxes = 1;
  std::array<BranchBox<D>, 64> stack;  // depth-first: at most one pending sibling per level
  int size = 0;
  stack[static_cast<std::size_t>(size++)] = root;
  while (size > 0 && !(best > goal.above)) {
    const BranchBox<D> box = stack[static_cast<std::size_t>(--size)];
    const double settles = best > goal.below ? goal.above : goal.below;
    if ((std::isfinite(settles) && box.upper <= settles) || box.upper - best <= goal.tolerance ||
        box.half.maxCoeff() <= 0.0 || boxes >= kMaxBoxes ||
        size + 2 > static_cast<int>(stack.size())) {
      closed = std::max(closed, box.upper);
      continue;
    }
    std::array<BranchBox<D>, 2> halves;
    int axis = 0;
    box.half.maxCoeff(&axis);
    for (int which = 0; which < 2; ++which) {
      BranchBox<D>& part = halves[static_cast<std::size_t>(which)];
      part = box;
      part.half[axis] *= 0.5;
      part.centre[axis] += which == 0 ? -part.half[axis] : part.half[axis];
      part.node = box.node >= 0 ? child_node(box.node, which) : -1;
      evaluate(part);
      best = std::max(best, part.value);
    }
    boxes += 2;
    // The more promising half is searched first: its value raises `best` sooner.
    if (halves[0].upper > halves[1].upper) std::swap(halves[0], halves[1]);
    stack[static_cast<std::size_t>(size++)] = halves[0];
    stack[static_cast<std::size_t>(size++)] = halves[1];
  }
  boxes_total += boxes;
  if (best > goal.above) return {best, INFINITY};
  return {best, std::max(best, closed)};
}

}  // namespace

// For each c, s is within s(centre) + |ds/da| ha + |ds/db| hb + |v| |p| (ha + hb)^2 / 2 over the
// box (every second derivative of Ry(b) Rx(a) p is at most |p| long); |x| = max(x, -x) makes the
// first-order part the largest of four sinusoids in c, each bounded over the arc in closed form.
Bracket OrientationSearch::largest(const Eigen::Vector3d& v, const Eigen::Vector3d& p,
                                   const Eigen::Vector3d& centre_rad,
                                   const Eigen::Vector3d& half_rad, const SearchGoal& goal) {
  TiltTree& tree = tree_for(centre_rad, half_rad);
  const TiltTree::Arc& arc = tree.arc();
  const double curvature = 0.5 * v.norm() * p.norm();
  Eigen::Matrix3d own_tilt, own_da, own_db;
  const auto evaluate = [&](BranchBox<2>& box) {
    if (box.node < 0) tilt_and_derivatives(box.centre, own_tilt, own_da, own_db);
    const TiltTree::Node* node = box.node >= 0 ? &tree[box.node] : nullptr;
    const Sinusoid s = sinusoid_of(v, (node ? node->tilt : own_tilt) * p);
    const Sinusoid s_a = sinusoid_of(v, (node ? node->tilt_da : own_da) * p);
    const Sinusoid s_b = sinusoid_of(v, (node ? node->tilt_db : own_db) * p);
    box.value = s.vertical + largest_on_arc(s.along, s.across, arc, true);
    double first_order = -INFINITY;
    for (const double sign_a : {-box.half.x(), box.half.x()}) {
      for (const double sign_b : {-box.half.y(), box.half.y()}) {
        const double along = s.along + sign_a * s_a.along + sign_b * s_b.along;
        const double across = s.across + sign_a * s_a.across + sign_b * s_b.across;
        const double vertical = s.vertical + sign_a * s_a.vertical + sign_b * s_b.vertical;
        first_order = std::max(first_order, vertical + largest_on_arc(along, across, arc, false));
      }
    }
    const double width = box.half.sum();
    box.upper = first_order + curvature * width * width;
  };
  BranchBox<2> root;
  root.centre = tree[0].centre;
  root.half = tree[0].half;
  root.node = 0;
  return branch_and_bound<2>(
      root, goal, evaluate, [&](int node, int which) { return tree.child(node, which); }, boxes_);
}

// g = -N . U, U = w / |w| the leg's direction (w = v + R p), N the axis (or R axis). Along any
// direction of unit 1-norm in (a, b, c): |w'| <= |p|, |w''| <= |p|, |N'|, |N''| <= 1 (turning),
// |U'| <= |w'| / |w|, |U''| <= 2 |w''| / |w| + 6 |w'|^2 / |w|^2, so
// |g''| <= |N''| + 2 |N'| |U'| + |U''| with |w| at its smallest over the box.
Bracket largest_joint_turn(const LegJointEnd& end, const Eigen::Vector3d& centre_rad,
                           const Eigen::Vector3d& half_rad, const SearchGoal& goal) {
  const double reach = end.p.norm();
  Eigen::Matrix3d rotation;
  std::array<Eigen::Matrix3d, 3> derivatives;
  const auto evaluate = [&](BranchBox<3>& box) {
    geometry::rotation_and_derivatives_abc(box.centre, rotation, derivatives);
    const Eigen::Vector3d w = end.v + rotation * end.p;
    const double length = w.norm();
    const Eigen::Vector3d along = w / length;
    const Eigen::Vector3d axis =
        end.turns_with_platform ? Eigen::Vector3d(rotation * end.axis) : end.axis;
    box.value = -axis.dot(along);
    double first_order = box.value;
    for (int k = 0; k < 3; ++k) {
      const Eigen::Matrix3d& d = derivatives[static_cast<std::size_t>(k)];
      const Eigen::Vector3d dw = d * end.p;
      const Eigen::Vector3d d_along = (dw - along * along.dot(dw)) / length;
      double slope = axis.dot(d_along);
      if (end.turns_with_platform) slope += (d * end.axis).dot(along);
      first_order += std::abs(slope) * box.half[k];
    }
    const double width = box.half.sum();
    const double shortest = length - reach * width;
    if (!(shortest > 0.0)) {
      box.upper = INFINITY;
      return;
    }
    const double ratio = reach / shortest;
    const double curvature =
        (end.turns_with_platform ? 1.0 + 2.0 * ratio : 0.0) + 2.0 * ratio + 6.0 * ratio * ratio;
    box.upper = first_order + 0.5 * curvature * width * width;
  };
  BranchBox<3> root;
  root.centre = centre_rad;
  root.half = half_rad;
  long boxes = 0;
  return branch_and_bound<3>(
      root, goal, evaluate, [](int, int) { return -1; }, boxes);
}

}  // namespace pkm::workspace
