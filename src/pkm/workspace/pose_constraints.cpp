// The constraints of Machine::inverse, bounded over a cell of poses (pose_constraints.hpp).
#include "pkm/workspace/pose_constraints.hpp"

#include <algorithm>
#include <cmath>

#include "pkm/bounds/assembly_mode.hpp"
#include "pkm/bounds/cable_bound.hpp"
#include "pkm/bounds/inverse_hessian.hpp"
#include "pkm/bounds/mechanism_rate.hpp"
#include "pkm/kinematics/assembly_mode_bounds.hpp"
#include "pkm/kinematics/cable_tensions.hpp"
#include "pkm/kinematics/derivative_bounds.hpp"
#include "pkm/kinematics/hanging_cables.hpp"
#include "pkm/kinematics/hexapod.hpp"
#include "pkm/workspace/orientation_search.hpp"

namespace pkm::workspace {

namespace {

// The cell's half-diagonal over its positions (mm).
double position_radius(const PoseCell& cell) {
  return cell.half.head<3>().norm();
}

// The cell's half-diagonal in the scaled pose norm (rotations weigh angle_scale_mm per rad).
double scaled_radius(const PoseCell& cell, double angle_scale_mm) {
  return std::hypot(cell.half.head<3>().norm(), angle_scale_mm * cell.half.tail<3>().norm());
}

// [cartesian] min and max on each controlled coordinate: exact over a box.
class EnvelopeConstraint final : public PoseConstraint {
 public:
  explicit EnvelopeConstraint(const machine::Machine& machine) {
    const machine::CartesianLimits& limits = machine.cartesian();
    for (int axis = 0; axis < geometry::kPoseSize; ++axis) {
      if (!machine.kinematics().dof().controls(axis)) continue;
      if (std::isfinite(limits.envelope_min[axis]))
        sides_.push_back({axis, -1, limits.envelope_min[axis]});
      if (std::isfinite(limits.envelope_max[axis]))
        sides_.push_back({axis, +1, limits.envelope_max[axis]});
    }
  }
  int count() const override { return static_cast<int>(sides_.size()); }
  void bound(const PoseCell& cell, std::span<Margin> margins, std::uint64_t) const override {
    for (std::size_t k = 0; k < sides_.size(); ++k) {
      const Side& side = sides_[k];
      // g = max - x (side +1) or x - min (side -1).
      const double at_centre = side.sign * (side.limit - cell.centre[side.axis]);
      margins[k] = {at_centre - cell.half[side.axis], at_centre + cell.half[side.axis]};
    }
  }
  kinematics::Status failure(int index) const override {
    return kinematics::Status::outside(sides_[static_cast<std::size_t>(index)].axis);
  }
  bool covers_orientation() const override { return true; }
  bool closed() const override { return true; }

 private:
  struct Side {
    int axis;
    int sign;
    double limit;
  };
  std::vector<Side> sides_;
};

// Each joint within [min, max]: q(x) lies within q(c) + J(c)(x - c) +- H r^2 / 2 over the cell,
// H the bound on the Hessian's norm over the ball of radius r (the cell's scaled half-diagonal)
// that bounds::inverse_hessian_bounds gives, the linear part bounded exactly over the box.
// Infinite H (the ball reaches a singularity or leaves the model's reach) bounds nothing.
class JointLimitConstraint final : public PoseConstraint {
 public:
  // The joints by the geometry alone (kinematics::joint_geometry): a cable robot's tensions are
  // ReachConstraint's.
  explicit JointLimitConstraint(const machine::Machine& machine)
      : machine_(machine),
        scale_(bounds::pose_angle_scale_mm(machine.kinematics())),
        geometry_(kinematics::joint_geometry(machine.kinematics())) {}
  int count() const override { return 2 * machine_.kinematics().joint_count(); }
  void bound(const PoseCell& cell, std::span<Margin> margins, std::uint64_t) const override {
    std::fill(margins.begin(), margins.end(), Margin{});
    const kinematics::Kinematics& model = *geometry_;
    // Pass-through joints are PassThroughConstraint's.
    for (int joint = 0; joint < model.joint_count(); ++joint) {
      if (model.passthrough_axis(joint) < 0) continue;
      margins[static_cast<std::size_t>(2 * joint)] = {1.0, 1.0};
      margins[static_cast<std::size_t>(2 * joint + 1)] = {1.0, 1.0};
    }
    if (!model.inverse_and_jacobian(geometry::Pose::from_vector(cell.centre), joints_, jacobian_)
             .ok()) {
      return;
    }
    const double r = scaled_radius(cell, scale_);
    const std::optional<kinematics::HessianBounds> curvature =
        bounds::inverse_hessian_bounds(model, cell.centre, r, scale_, kinematics::Chord{});
    if (!curvature) return;
    for (int joint = 0; joint < model.joint_count(); ++joint) {
      if (model.passthrough_axis(joint) >= 0) continue;
      const double curved = 0.5 * curvature->norm[static_cast<std::size_t>(joint)] * r * r;
      if (!std::isfinite(curved) || !std::isfinite(joints_[joint])) continue;
      const double spread = jacobian_.row(joint).cwiseAbs().dot(cell.half) + curved;
      const machine::JointSpec& spec = machine_.joints()[static_cast<std::size_t>(joint)];
      const double q = joints_[joint];
      margins[static_cast<std::size_t>(2 * joint)] = {q - spread - spec.min, q + spread - spec.min};
      margins[static_cast<std::size_t>(2 * joint + 1)] = {spec.max - q - spread,
                                                          spec.max - q + spread};
    }
  }
  kinematics::Status failure(int index) const override {
    return kinematics::Status::failure(kinematics::StatusCode::joint_limit, index / 2);
  }

 private:
  const machine::Machine& machine_;
  double scale_;
  std::unique_ptr<kinematics::Kinematics> geometry_;
  mutable kinematics::JointVector joints_;
  mutable kinematics::JointJacobian jacobian_;
};

// The mechanism reaches (a glide's struts their rails, a cable robot's cables clear of their
// anchors and its tensions holding the effector): the model's own bounds over the cell
// (DerivativeBounds::reach_over_cell, each margin in its own unit), in the scaled norm of its
// derivative bounds.
class ReachConstraint final : public PoseConstraint {
 public:
  ReachConstraint(const kinematics::Kinematics& model, const kinematics::DerivativeBounds& reach)
      : reach_(reach), scale_(bounds::pose_angle_scale_mm(model)) {}
  int count() const override { return reach_.reach_count(); }
  void bound(const PoseCell& cell, std::span<Margin> margins, std::uint64_t) const override {
    // A margin per joint at most, and a cable robot's tensions'.
    std::array<std::array<double, 2>, kinematics::kMaxJoints + 1> values;
    const auto n = static_cast<std::size_t>(reach_.reach_count());
    reach_.reach_over_cell(cell.centre, scaled_radius(cell, scale_), position_radius(cell), scale_,
                           std::span(values.data(), n));
    for (std::size_t i = 0; i < n; ++i) margins[i] = {values[i][0], values[i][1]};
  }
  kinematics::Status failure(int index) const override {
    return reach_.reach_margin(index).failure;
  }

 private:
  const kinematics::DerivativeBounds& reach_;
  double scale_;
};

// The machine stays in home's assembly mode over a cell, by the model's own bound
// (AssemblyModeBounds::mode_over_cell: a translating glide's det[struts] / (L1 L2 L3); the
// certified check bounds the same determinant over a ball) moved at most its rate times the
// cell's position radius.
class AssemblyOverCellConstraint final : public PoseConstraint {
 public:
  AssemblyOverCellConstraint(const kinematics::AssemblyModeBounds& modes, int home_mode)
      : modes_(modes), home_mode_(home_mode) {}
  int count() const override { return 1; }
  void bound(const PoseCell& cell, std::span<Margin> margins, std::uint64_t) const override {
    margins[0] = Margin{};
    const double rho = position_radius(cell);
    const std::optional<kinematics::ModeBound> mode =
        modes_.mode_over_cell(home_mode_, cell.centre, rho);
    if (!mode) return;
    margins[0] = {mode->value - mode->rate * rho, mode->value + mode->rate * rho};
  }
  kinematics::Status failure(int) const override {
    return kinematics::Status::failure(kinematics::StatusCode::other_assembly);
  }

 private:
  const kinematics::AssemblyModeBounds& modes_;
  int home_mode_;
};

// A hexapod stays in home's assembly mode (platform normal up): cos a cos b > 0, bounded over
// the cell's angle intervals (cos on [lo, hi] within (-pi, pi) is least at an end).
class HexapodAssemblyConstraint final : public PoseConstraint {
 public:
  int count() const override { return 1; }
  void bound(const PoseCell& cell, std::span<Margin> margins, std::uint64_t) const override {
    margins[0] = {kinematics::HexapodKinematics::tilt_low(cell.centre, cell.half), 1.0};
  }
  kinematics::Status failure(int) const override {
    return kinematics::Status::failure(kinematics::StatusCode::other_assembly);
  }
  bool covers_orientation() const override { return true; }
};

// A hexapod stays on home's side of its base plane: each platform joint's rise above (or below)
// its base joint, bounded over the cell by HexapodKinematics::base_side_bound, the bound
// certify uses along a move. Without it the mirror image below the base counts as workspace.
class HexapodBaseSideConstraint final : public PoseConstraint {
 public:
  explicit HexapodBaseSideConstraint(const kinematics::HexapodKinematics& model) : model_(model) {}
  int count() const override { return 1; }
  void bound(const PoseCell& cell, std::span<Margin> margins, std::uint64_t) const override {
    const kinematics::HexapodKinematics::BaseSideBound side =
        model_.base_side_bound(cell.centre, cell.half);
    margins[0] = {side.low, side.high};
  }
  kinematics::Status failure(int) const override {
    return kinematics::Status::failure(kinematics::StatusCode::other_assembly);
  }

 private:
  const kinematics::HexapodKinematics& model_;
};

// An ideal hanging plotter's cables both pull: the pen strictly between the anchors' verticals
// and below the line through them (both anchors of the pen's weight then lean up). Three
// linear functions of the pen, bounded exactly over the box.
class CablePullConstraint final : public PoseConstraint {
 public:
  explicit CablePullConstraint(const kinematics::CablePlotterGeometry& geometry)
      : left_(geometry.anchors_mm[0]), right_(geometry.anchors_mm[1]) {}
  int count() const override { return 3; }
  void bound(const PoseCell& cell, std::span<Margin> margins, std::uint64_t) const override {
    const Eigen::Vector2d pen = cell.centre.head<2>();
    const Eigen::Vector2d half = cell.half.head<2>();
    margins[0] = {pen.x() - left_.x() - half.x(), pen.x() - left_.x() + half.x()};
    margins[1] = {right_.x() - pen.x() - half.x(), right_.x() - pen.x() + half.x()};
    // Distance below the line from the left anchor to the right one.
    const Eigen::Vector2d along = (right_ - left_).normalized();
    const Eigen::Vector2d down(along.y(), -along.x());
    const double below = down.dot(pen - left_);
    const double spread = std::abs(down.x()) * half.x() + std::abs(down.y()) * half.y();
    margins[2] = {below - spread, below + spread};
  }
  bool covers_orientation() const override { return true; }
  kinematics::Status failure(int index) const override {
    // The cable on the far side would push: inverse names it (right of the right anchor: 0).
    if (index == 2) return kinematics::Status::failure(kinematics::StatusCode::unreachable);
    return kinematics::Status::failure(kinematics::StatusCode::unreachable, index == 0 ? 1 : 0);
  }

 private:
  Eigen::Vector2d left_, right_;
};

// A cable plotter as built (pulleys, a weighed or tilting effector, stretching cables): its
// balance bounded over the cell by bounds::cable_box_bound. Values: each cable's tension (its
// sign: the cable pulls; under a unit load where the effector has no mass), the sine of the
// angle between the cables, then where tension_limits are given each tension less the min and
// the max less it, then, where `joints` (no Hessian bound: the effector tilts or the cables
// stretch), each cable's joint less its min and its max less it; last 1 / t - 1 / max per
// cable, which decides the cells where the cables come into line.
class CableBalanceConstraint final : public PoseConstraint {
 public:
  CableBalanceConstraint(const machine::Machine& machine,
                         const kinematics::CablePlotterGeometry& geometry, bool joints)
      : machine_(machine), geometry_(geometry), joints_(joints) {}
  int count() const override { return 13; }
  bool covers_orientation() const override { return true; }
  void bound(const PoseCell& cell, std::span<Margin> margins, std::uint64_t) const override {
    std::fill(margins.begin(), margins.end(), Margin{1.0, 1.0});
    const bounds::CableBoxBound b =
        bounds::cable_box_bound(geometry_, cell.centre.head<2>(), cell.half.head<2>());
    if (!b.known) {
      std::fill(margins.begin(), margins.begin() + 3, Margin{});
      margins[11] = margins[12] = Margin{};
      if (b.no_balance) margins[2] = {-1.0, -1.0};  // refused everywhere
      if (geometry_.tension_limited) std::fill(margins.begin() + 3, margins.begin() + 7, Margin{});
      if (joints_) std::fill(margins.begin() + 7, margins.end(), Margin{});
      return;
    }
    const auto from = [](const bounds::Range& r, double offset, double sign) {
      return sign > 0.0 ? Margin{r.lo - offset, r.hi - offset}
                        : Margin{offset - r.hi, offset - r.lo};
    };
    for (std::size_t c = 0; c < 2; ++c) {
      margins[c] = from(b.tension_N[c], 0.0, 1.0);
      if (geometry_.tension_limited) {
        margins[3 + 2 * c] = from(b.tension_N[c], geometry_.tension_min_N, 1.0);
        margins[4 + 2 * c] = from(b.tension_N[c], geometry_.tension_max_N, -1.0);
      }
      if (joints_) {
        const machine::JointSpec& spec = machine_.joints()[c];
        margins[7 + 2 * c] = from(b.joint_mm[c], spec.min, 1.0);
        margins[8 + 2 * c] = from(b.joint_mm[c], spec.max, -1.0);
      }
    }
    margins[2] = from(b.apart, 0.0, 1.0);
    // 1 / t - 1 / max: refutes cells where a cable pushes, comes into line or passes its max,
    // across the line where the tension's own range is unbounded.
    const double inverse_max = 1.0 / geometry_.tension_max_N;  // 0 without a max
    for (std::size_t c = 0; c < 2; ++c)
      margins[11 + c] = from(b.inverse_tension_per_N[c], inverse_max, 1.0);
  }
  kinematics::Status failure(int index) const override {
    const bool weighed = geometry_.effector_mass_kg > 0.0;
    if (index < 2) {
      return kinematics::Status::failure(
          weighed ? kinematics::StatusCode::tension : kinematics::StatusCode::unreachable, index);
    }
    if (index == 2)
      return kinematics::Status::failure(
          kinematics::StatusCode::unreachable);  // in line, or no balance
    if (index < 7)
      return kinematics::Status::failure(kinematics::StatusCode::tension, (index - 3) / 2);
    if (index < 11)
      return kinematics::Status::failure(kinematics::StatusCode::joint_limit, (index - 7) / 2);
    return kinematics::Status::failure(
        weighed ? kinematics::StatusCode::tension : kinematics::StatusCode::unreachable,
        index - 11);
  }

 private:
  const machine::Machine& machine_;
  kinematics::CablePlotterGeometry geometry_;
  bool joints_;
};

// Each hexapod leg within [min, max] for every orientation of the cell. A leg's length
// |t + R b - a| is 1-Lipschitz in the position t for every R, so its largest (smallest) value
// over the cell's orientations is too: bracketed at the cell's middle position by
// OrientationSearch, it moves at most the cell's half-diagonal over the cell. No
// orientation box needs splitting; the branch and bound searches it.
class HexapodLegConstraint final : public PoseConstraint {
 public:
  HexapodLegConstraint(const machine::Machine& machine, const kinematics::HexapodKinematics& model)
      : machine_(machine), geometry_(model.geometry()) {}
  int count() const override { return 12; }
  bool covers_orientation() const override { return true; }
  void bound(const PoseCell& cell, std::span<Margin> margins,
             std::uint64_t settled) const override {
    const double rho = position_radius(cell);
    // One search (and its trees of boxes) per thread, kept from cell to cell and from worker to
    // worker (a worker lives for one top cell only).
    static thread_local OrientationSearch search;
    const Eigen::Vector3d orientation = cell.centre.tail<3>(), spread = cell.half.tail<3>();
    for (std::size_t i = 0; i < 6; ++i) {
      if (((settled >> (2 * i)) & 3u) == 3u) continue;
      const Eigen::Vector3d b = geometry_.platform_from_tip_mm(i);
      const Eigen::Vector3d v = cell.centre.head<3>() - geometry_.base_mm[i];
      const double offset = geometry_.leg_offset_mm[i];
      const double longest = machine_.joints()[i].max - offset;
      const double shortest = machine_.joints()[i].min - offset;
      const double base = v.squaredNorm() + b.squaredNorm();
      // Leg length (less its offset) as a function of s = v . R b, and its inverse.
      const auto length = [&](double s) { return std::sqrt(std::max(0.0, base + 2.0 * s)); };
      const auto s_at = [&](double l) { return 0.5 * (l * std::max(l, 0.0) - base); };
      const double tolerance = 0.05 * rho * std::max(std::abs(v.norm() - b.norm()), 1.0);
      const Bracket most = search.largest(v, b, orientation, spread,
                                          {s_at(longest + rho), s_at(longest - rho), tolerance});
      margins[2 * i + 1] = {longest - length(most.hi) - rho, longest - length(most.lo) + rho};
      // The smallest length: the largest of -s = (-v) . R b.
      const Bracket least =
          search.largest(-v, b, orientation, spread,
                         {-s_at(std::max(shortest - rho, 0.0)), -s_at(shortest + rho), tolerance});
      margins[2 * i] = {length(-least.hi) - rho - shortest, length(-least.lo) + rho - shortest};
    }
  }
  kinematics::Status failure(int index) const override {
    return kinematics::Status::failure(kinematics::StatusCode::joint_limit, index / 2);
  }

 private:
  const machine::Machine& machine_;
  kinematics::HexapodGeometry geometry_;
};

// Each hexapod joint end's angle within max_joint_angle for every orientation of the cell:
// cos(angle) >= cos(max), the smallest cosine over the orientations bracketed at the cell's
// middle position by largest_joint_turn (no orientation box needs splitting), moved at most
// rho / (shortest leg over the cell) over it (the leg's direction turns no faster than 1 / its
// length per mm of the platform joint; the platform end's axis does not depend on position).
class HexapodJointAngleConstraint final : public PoseConstraint {
 public:
  explicit HexapodJointAngleConstraint(const kinematics::HexapodKinematics& model)
      : geometry_(model.geometry()), limits_(model.leg_limits()) {}
  int count() const override { return 12; }
  bool covers_orientation() const override { return true; }
  void bound(const PoseCell& cell, std::span<Margin> margins,
             std::uint64_t settled) const override {
    const double rho = position_radius(cell);
    const Eigen::Vector3d orientation = cell.centre.tail<3>(), spread = cell.half.tail<3>();
    const Eigen::Matrix3d middle_rotation = geometry::rotation_from_abc(orientation);
    for (std::size_t i = 0; i < 6; ++i) {
      LegJointEnd end;
      end.p = geometry_.platform_from_tip_mm(i);
      end.v = cell.centre.head<3>() - geometry_.base_mm[i];
      // The leg's shortest over the cell: at the middle pose, less what the orientations and
      // positions of the cell can take off (|d(R p)| <= |p| per rad of each angle).
      const double middle = (end.v + middle_rotation * end.p).norm() - end.p.norm() * spread.sum();
      const double shortest = std::max(middle, end.v.norm() - end.p.norm()) - rho;
      const double drift = shortest > 0.0 ? rho / shortest : INFINITY;
      for (int side = 0; side < 2; ++side) {
        const std::size_t k = 2 * i + static_cast<std::size_t>(side);
        const double cos_max = limits_.cos_max_joint_angle(side);
        if (cos_max <= -1.0 || ((settled >> k) & 1u)) {
          margins[k] = {1.0, 1.0};
          continue;
        }
        if (!std::isfinite(drift)) {
          margins[k] = Margin{};
          continue;
        }
        end.axis = limits_.neutral_axis(static_cast<int>(i), side);
        end.turns_with_platform = side == kinematics::kPlatformEnd;
        // The largest of -cos: at most -(cos_max + drift) proves the end, past -(cos_max -
        // drift) at one orientation fails every position of the cell.
        const Bracket turn = largest_joint_turn(end, orientation, spread,
                                                {drift - cos_max, -drift - cos_max, 0.05 * drift});
        margins[k] = {-turn.hi - drift - cos_max, -turn.lo + drift - cos_max};
      }
    }
  }
  kinematics::Status failure(int index) const override {
    return kinematics::Status::failure(kinematics::StatusCode::joint_angle, index / 2);
  }

 private:
  kinematics::HexapodGeometry geometry_;
  const kinematics::LegLimits& limits_;
};

// Machine::inverse at the cell's centre and every corner: low 1 when all are ok, high -1 when
// all fail, else [-1, 1]. Not a proof: what it says holds at the samples.
class SampledConstraint final : public PoseConstraint {
 public:
  explicit SampledConstraint(const machine::Machine& machine) : machine_(machine) {
    const kinematics::Kinematics& model = machine.kinematics();
    for (int joint = 0; joint < model.joint_count(); ++joint) {
      const int axis = model.passthrough_axis(joint);
      const machine::JointSpec& spec = machine.joints()[static_cast<std::size_t>(joint)];
      if (axis >= 0) passthrough_.push_back({axis, {spec.min, spec.max}});
    }
  }
  int count() const override { return 1; }
  bool proven() const override { return false; }
  void bound(const PoseCell& cell, std::span<Margin> margins, std::uint64_t) const override {
    std::array<int, geometry::kPoseSize> spread{};
    int n = 0;
    for (int axis = 0; axis < geometry::kPoseSize; ++axis) {
      if (cell.half[axis] > 0.0) spread[static_cast<std::size_t>(n++)] = axis;
    }
    bool any_ok = false, any_failed = false;
    for (unsigned corner = 0; corner <= (1u << n); ++corner) {
      geometry::Vector6d pose = cell.centre;
      if (corner < (1u << n)) {
        for (int k = 0; k < n; ++k) {
          const int axis = spread[static_cast<std::size_t>(k)];
          pose[axis] += ((corner >> k) & 1u) ? cell.half[axis] : -cell.half[axis];
        }
      }
      // Pass-through coordinates are judged exactly by PassThroughConstraint: the samples ask
      // about the mechanism only.
      for (const auto& [axis, range] : passthrough_)
        pose[axis] = std::clamp(pose[axis], range[0], range[1]);
      const kinematics::Status status =
          machine_.inverse(geometry::Pose::from_vector(pose), joints_);
      if (status.ok()) {
        any_ok = true;
      } else {
        any_failed = true;
        last_failure_ = status;
      }
    }
    margins[0] = {any_failed ? -1.0 : 1.0, any_ok ? 1.0 : -1.0};
  }
  kinematics::Status failure(int) const override { return last_failure_; }

 private:
  const machine::Machine& machine_;
  std::vector<std::pair<int, std::array<double, 2>>> passthrough_;  // axis, joint's [min, max]
  mutable kinematics::JointVector joints_;
  mutable kinematics::Status last_failure_;
};

// Pass-through joints (a plotter's Z) within their limits: each is its coordinate, exact.
class PassThroughConstraint final : public PoseConstraint {
 public:
  explicit PassThroughConstraint(const machine::Machine& machine) {
    const kinematics::Kinematics& model = machine.kinematics();
    for (int joint = 0; joint < model.joint_count(); ++joint) {
      if (model.passthrough_axis(joint) >= 0) joints_.push_back(joint);
    }
    machine_ = &machine;
  }
  int count() const override { return 2 * static_cast<int>(joints_.size()); }
  bool covers_orientation() const override { return true; }
  bool closed() const override { return true; }
  void bound(const PoseCell& cell, std::span<Margin> margins, std::uint64_t) const override {
    for (std::size_t k = 0; k < joints_.size(); ++k) {
      const int joint = joints_[k];
      const int axis = machine_->kinematics().passthrough_axis(joint);
      const machine::JointSpec& spec = machine_->joints()[static_cast<std::size_t>(joint)];
      const double q = cell.centre[axis], spread = cell.half[axis];
      margins[2 * k] = {q - spread - spec.min, q + spread - spec.min};
      margins[2 * k + 1] = {spec.max - q - spread, spec.max - q + spread};
    }
  }
  kinematics::Status failure(int index) const override {
    return kinematics::Status::failure(kinematics::StatusCode::joint_limit,
                                       joints_[static_cast<std::size_t>(index / 2)]);
  }

 private:
  const machine::Machine* machine_ = nullptr;
  std::vector<int> joints_;
};

// Each joint end's angle and each leg pair's clearance (Kinematics::mechanism_limits, the
// values Machine::inverse refuses by): the margin at the cell's centre, moved at most
// bounds::mechanism_rate times the cell's scaled half-diagonal, the rate bound the certified job
// check proves moves with. Unknown where the centre has no legs (a glide out of reach) or the
// ball has no derivative bound.
class MechanismLimitConstraint final : public PoseConstraint {
 public:
  // `with_angles` false: the joint angles are another constraint's (a hexapod's); the leg
  // clearances only.
  MechanismLimitConstraint(const machine::Machine& machine, bool with_angles)
      : machine_(machine), scale_(bounds::pose_angle_scale_mm(machine.kinematics())) {
    machine.kinematics().mechanism_limits(machine.home(), values_);
    for (std::size_t k = 0; k < values_.size(); ++k) {
      if (!with_angles && values_[k].code == kinematics::StatusCode::joint_angle) continue;
      used_.push_back(k);
      failures_.push_back({values_[k].code, values_[k].leg});
    }
    total_ = values_.size();
  }
  int count() const override { return static_cast<int>(used_.size()); }
  void bound(const PoseCell& cell, std::span<Margin> margins, std::uint64_t) const override {
    std::fill(margins.begin(), margins.end(), Margin{});
    const kinematics::Kinematics& model = machine_.kinematics();
    const geometry::Pose centre = geometry::Pose::from_vector(cell.centre);
    if (!model.inverse_and_jacobian(centre, joints_, jacobian_).ok()) return;
    values_.clear();
    model.mechanism_limits(centre, values_);
    if (values_.size() != total_) return;
    const double r = scaled_radius(cell, scale_);
    const std::optional<kinematics::HessianBounds> curvature =
        bounds::inverse_hessian_bounds(model, cell.centre, r, scale_, kinematics::Chord{});
    if (!curvature) return;
    const kinematics::LegMotion motion =
        bounds::leg_motion(model, joints_, jacobian_, *curvature, r, scale_);
    const std::optional<kinematics::LegEnds> ends = bounds::legs_at(model, centre, joints_);
    for (std::size_t k = 0; k < used_.size(); ++k) {
      const kinematics::MechanismLimit& value = values_[used_[k]];
      const bounds::Reach reach =
          bounds::mechanism_reach(value, motion, r, ends ? &*ends : nullptr);
      // The margin falls as an angle rises or a clearance falls.
      const bool angle = value.code == kinematics::StatusCode::joint_angle;
      const double falls = angle ? reach.up : reach.down, rises = angle ? reach.down : reach.up;
      const double margin = value.margin();
      if (std::isfinite(falls) && std::isfinite(rises) && std::isfinite(margin))
        margins[k] = {margin - falls, margin + rises};
    }
  }
  kinematics::Status failure(int index) const override {
    const auto& [code, leg] = failures_[static_cast<std::size_t>(index)];
    return kinematics::Status::failure(code, leg);
  }

 private:
  const machine::Machine& machine_;
  double scale_;
  std::size_t total_ = 0;          // values mechanism_limits gives
  std::vector<std::size_t> used_;  // the ones bounded here
  std::vector<std::pair<kinematics::StatusCode, int>> failures_;
  mutable std::vector<kinematics::MechanismLimit> values_;
  mutable kinematics::JointVector joints_;
  mutable kinematics::JointJacobian jacobian_;
};

bool has_hessian_bounds(const machine::Machine& machine) {
  const kinematics::Kinematics& model = machine.kinematics();
  return bounds::inverse_hessian_bounds(model, machine.home().as_vector(), 0.0,
                                        bounds::pose_angle_scale_mm(model), kinematics::Chord{})
      .has_value();
}

// The hexapod's constraints: its legs and joint angles over every orientation of the cell
// (this module's OrientationSearch), its assembly mode (tilt, base side), its leg clearances.
void add_hexapod_constraints(const machine::Machine& machine,
                             const kinematics::HexapodKinematics& hexapod,
                             std::vector<std::unique_ptr<PoseConstraint>>& constraints) {
  constraints.push_back(std::make_unique<HexapodLegConstraint>(machine, hexapod));
  constraints.push_back(std::make_unique<HexapodAssemblyConstraint>());
  constraints.push_back(std::make_unique<HexapodBaseSideConstraint>(hexapod));
  if (hexapod.leg_limits().settings().checks_angles()) {
    constraints.push_back(std::make_unique<HexapodJointAngleConstraint>(hexapod));
  }
  if (hexapod.leg_limits().settings().leg_diameter_mm > 0.0) {
    constraints.push_back(std::make_unique<MechanismLimitConstraint>(machine, false));
  }
}

// What a model whose derivatives are bounded adds beyond its joints: its reach and assembly mode
// over a cell where it bounds them (a glide, a cable robot), an ideal plotter's pull region, else
// (a rotary delta) samples, unless the joint limits are all it refuses by (a matrix).
void add_reach_constraints(const machine::Machine& machine,
                           std::vector<std::unique_ptr<PoseConstraint>>& constraints) {
  const kinematics::Kinematics& model = machine.kinematics();
  const kinematics::DerivativeBounds& derivatives = *model.derivative_bounds();
  const kinematics::AssemblyModeBounds* modes = model.assembly_mode_bounds();
  const kinematics::HangingCables* cables = model.hanging_cables();
  const int home_mode = model.assembly_mode(machine.home());
  if (derivatives.reach_count() > 0) {
    constraints.push_back(std::make_unique<ReachConstraint>(model, derivatives));
    if (home_mode != 0 && modes != nullptr && modes->has_mode_over_cell()) {
      constraints.push_back(std::make_unique<AssemblyOverCellConstraint>(*modes, home_mode));
    }
    if (model.has_mechanism_limits()) {
      constraints.push_back(std::make_unique<MechanismLimitConstraint>(machine, true));
    }
  } else if (cables != nullptr) {
    if (cables->cable_geometry().ideal()) {
      constraints.push_back(std::make_unique<CablePullConstraint>(cables->cable_geometry()));
    } else {
      constraints.push_back(std::make_unique<SampledConstraint>(machine));
    }
  } else if (!derivatives.refuses_only_joint_limits()) {
    // A rotary delta: its joints are bounded, its reach and assembly mode are sampled.
    constraints.push_back(std::make_unique<SampledConstraint>(machine));
  }
}

}  // namespace

std::vector<std::unique_ptr<PoseConstraint>> machine_constraints(const machine::Machine& machine) {
  std::vector<std::unique_ptr<PoseConstraint>> constraints;
  if (machine.cartesian().has_envelope()) {
    constraints.push_back(std::make_unique<EnvelopeConstraint>(machine));
  }
  const kinematics::Kinematics& model = machine.kinematics();
  constraints.push_back(std::make_unique<PassThroughConstraint>(machine));
  if (const kinematics::HangingCables* cables = model.hanging_cables();
      cables != nullptr && !cables->cable_geometry().ideal() &&
      bounds::cable_bound_unavailable(cables->cable_geometry()).empty()) {
    // As built: the joints by their Hessian bound where the cables are rigid (second order),
    // else with the balance.
    const bool rigid = has_hessian_bounds(machine);
    if (rigid) constraints.push_back(std::make_unique<JointLimitConstraint>(machine));
    constraints.push_back(
        std::make_unique<CableBalanceConstraint>(machine, cables->cable_geometry(), !rigid));
    return constraints;
  }
  if (!has_hessian_bounds(machine)) {
    constraints.push_back(std::make_unique<SampledConstraint>(machine));
    return constraints;
  }
  // The one cast on a model class here: a hexapod's leg and joint-angle constraints search the
  // cell's orientation box with OrientationSearch (this module's branch and bound, which
  // kinematics/ cannot depend on) over the hexapod's own geometry and leg limits.
  if (const auto* hexapod = dynamic_cast<const kinematics::HexapodKinematics*>(&model)) {
    add_hexapod_constraints(machine, *hexapod, constraints);
    return constraints;
  }
  constraints.push_back(std::make_unique<JointLimitConstraint>(machine));
  add_reach_constraints(machine, constraints);
  return constraints;
}

}  // namespace pkm::workspace
