// The pose-box joint-rate bound (pose_box_rate.hpp): cells of the box bounded from their centre,
// halved where the bound is infinite or passes what the cells' centres show.
#include "pkm/bounds/pose_box_rate.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <stdexcept>

#include "pkm/bounds/inverse_hessian.hpp"
#include "pkm/kinematics/cable_tensions.hpp"

namespace pkm::bounds {

namespace {

// Beyond this distance from home (mm) a reach is taken as not finite: reach_box stops at 1e6.
constexpr double kNoFiniteReachMm = 1e5;

// A cell of the box: its corners (mm, rad) and how often it was halved.
struct Cell {
  geometry::Vector6d min, max;
  int depth = 0;
};

// One cell's look: the model's joints, Jacobian and Hessian bound at and around its centre.
struct CellLook {
  bool finite = false;            // IK, Jacobian and Hessian bound all finite
  bool reached = false;           // the machine itself (limits, envelope) takes the centre
  bool outside = false;           // every pose of the cell passes a joint limit
  Eigen::MatrixXd upper;          // per joint and coordinate: the bound on |J_ij| over the cell
  Eigen::MatrixXd at_centre;      // |J_ij| at the centre
  std::vector<double> curvature;  // Hessian norm bound over the cell
  std::vector<double> centre_curvature;  // ... at the centre alone
};

class CellBounder {
 public:
  CellBounder(const machine::Machine& machine, double angle_scale_mm)
      : machine_(machine),
        geometry_(kinematics::joint_geometry(machine.kinematics())),
        model_(*geometry_),
        axes_(model_.dof().axes()),
        scale_(angle_scale_mm),
        joints_(model_.joint_count()) {}

  double scale(int axis) const { return axis < 3 ? 1.0 : scale_; }

  // Half the cell's diagonal in the scaled coordinates.
  double radius(const Cell& cell) const {
    double sum = 0.0;
    for (const int axis : axes_)
      sum += std::pow((cell.max[axis] - cell.min[axis]) * scale(axis), 2);
    return 0.5 * std::sqrt(sum);
  }

  geometry::Vector6d centre(const Cell& cell) const {
    geometry::Vector6d pose = machine_.home().as_vector();
    for (const int axis : axes_) pose[axis] = 0.5 * (cell.min[axis] + cell.max[axis]);
    return pose;
  }

  CellLook look(const Cell& cell) const {
    CellLook look;
    const geometry::Vector6d c = centre(cell);
    const double r = radius(cell);
    kinematics::JointVector q;
    kinematics::JointJacobian jacobian;
    const geometry::Pose pose = geometry::Pose::from_vector(c);
    if (!model_.inverse_and_jacobian(pose, q, jacobian).ok() || !kinematics::all_finite(q) ||
        !jacobian.allFinite()) {
      return look;
    }
    const auto around = inverse_hessian_bounds(model_, c, r, scale_, {});
    const auto at = inverse_hessian_bounds(model_, c, 0.0, scale_, {});
    if (!around || !at) return look;
    look.curvature = around->norm;
    look.centre_curvature = at->norm;
    if (!std::all_of(look.curvature.begin(), look.curvature.end(),
                     [](double h) { return std::isfinite(h); })) {
      return look;
    }
    kinematics::JointVector reached;
    look.reached = machine_.inverse(pose, reached).ok();
    look.finite = true;
    look.upper = Eigen::MatrixXd::Zero(joints_, geometry::kPoseSize);
    look.at_centre = Eigen::MatrixXd::Zero(joints_, geometry::kPoseSize);
    for (int i = 0; i < joints_; ++i) {
      const double h = look.curvature[static_cast<std::size_t>(i)];
      double gradient = 0.0;  // |grad q_i| in the scaled coordinates
      for (const int axis : axes_) {
        const double entry = std::abs(jacobian(i, axis));
        look.at_centre(i, axis) = entry;
        look.upper(i, axis) = entry + h * r * scale(axis);
        gradient += std::pow(entry / scale(axis), 2);
      }
      // q_i over the cell lies within q_i(c) +- (|grad| r + h r^2 / 2).
      const machine::JointSpec& spec = machine_.joints()[static_cast<std::size_t>(i)];
      const double spread = std::sqrt(gradient) * r + 0.5 * h * r * r;
      if (q[i] - spread > spec.max || q[i] + spread < spec.min) look.outside = true;
    }
    return look;
  }

  // The two halves of the cell across its longest scaled side.
  std::pair<Cell, Cell> split(const Cell& cell) const {
    int longest = axes_.front();
    for (const int axis : axes_) {
      if ((cell.max[axis] - cell.min[axis]) * scale(axis) >
          (cell.max[longest] - cell.min[longest]) * scale(longest)) {
        longest = axis;
      }
    }
    Cell low = cell, high = cell;
    const double middle = 0.5 * (cell.min[longest] + cell.max[longest]);
    low.max[longest] = middle;
    high.min[longest] = middle;
    low.depth = high.depth = cell.depth + 1;
    return {low, high};
  }

  double volume(const Cell& cell) const {
    double v = 1.0;
    for (const int axis : axes_) v *= (cell.max[axis] - cell.min[axis]) * scale(axis);
    return v;
  }

 private:
  const machine::Machine& machine_;
  // The joints' rates by the geometry alone: whether the machine takes a pose is `reached`.
  std::unique_ptr<kinematics::Kinematics> geometry_;
  const kinematics::Kinematics& model_;
  std::vector<int> axes_;
  double scale_;
  int joints_;
};

struct Leaf {
  Cell cell;
  CellLook look;
};

// Whether a leaf's bound passes the best values sampled so far by more than the slack (relative
// to each joint's largest entry, so that near-zero entries do not ask for endless halving).
bool needs_refining(const Leaf& leaf, const Eigen::MatrixXd& sampled,
                    const std::vector<double>& sampled_curvature, double slack) {
  for (int i = 0; i < sampled.rows(); ++i) {
    const double row = sampled.row(i).maxCoeff();
    for (int j = 0; j < sampled.cols(); ++j) {
      if (leaf.look.upper(i, j) > (1.0 + slack) * sampled(i, j) + slack * row) return true;
    }
    const std::size_t k = static_cast<std::size_t>(i);
    if (leaf.look.curvature[k] > (1.0 + slack) * sampled_curvature[k] + 1e-12) return true;
  }
  return false;
}

// Formula machines have no Hessian bound: the largest Jacobian entries and Hessian norms met on a
// grid of the box (the Hessian by differences of the Jacobian), reported as sampled.
JointRateBound sample_joint_rates(const machine::Machine& machine, const machine::PoseBox& box,
                                  double angle_scale_mm) {
  const kinematics::Kinematics& model = machine.kinematics();
  const std::vector<int> axes = model.dof().axes();
  const int n = model.joint_count();
  const int per_axis = std::max(3, static_cast<int>(std::pow(20000.0, 1.0 / axes.size())));
  JointRateBound bound;
  bound.angle_scale_mm = angle_scale_mm;
  bound.slope = Eigen::MatrixXd::Zero(n, geometry::kPoseSize);
  bound.curvature.assign(static_cast<std::size_t>(n), 0.0);
  long total = 1;
  for (std::size_t k = 0; k < axes.size(); ++k) total *= per_axis;
  kinematics::JointJacobian j0, j1;
  for (long index = 0; index < total; ++index) {
    geometry::Vector6d pose = machine.home().as_vector();
    long rest = index;
    for (const int axis : axes) {
      const double u = static_cast<double>(rest % per_axis) / (per_axis - 1);
      rest /= per_axis;
      pose[axis] = box.min[axis] + u * (box.max[axis] - box.min[axis]);
    }
    kinematics::JointVector q;
    if (!machine.inverse(geometry::Pose::from_vector(pose), q).ok()) continue;
    if (!model.jacobian(geometry::Pose::from_vector(pose), j0).ok()) continue;
    ++bound.cells;
    bound.slope = bound.slope.cwiseMax(Eigen::MatrixXd(j0.cwiseAbs()));
    for (int i = 0; i < n; ++i) {
      double sum = 0.0;
      for (const int axis : axes) {
        const double step = (axis < 3 ? 1e-3 : 1e-3 / angle_scale_mm);
        geometry::Vector6d moved = pose;
        moved[axis] += step;
        if (!model.jacobian(geometry::Pose::from_vector(moved), j1).ok()) continue;
        for (const int other : axes) {
          const double scale =
              (axis < 3 ? 1.0 : angle_scale_mm) * (other < 3 ? 1.0 : angle_scale_mm);
          sum += std::pow((j1(i, other) - j0(i, other)) / step / scale, 2);
        }
      }
      auto& h = bound.curvature[static_cast<std::size_t>(i)];
      h = std::max(h, std::sqrt(sum));
    }
  }
  bound.sampled_slope = bound.slope;
  bound.cell_slope = bound.slope;
  bound.cell_curvature = bound.curvature;
  for (int i = 0; i < n; ++i) bound.cell_joint.push_back(i);
  return bound;
}

}  // namespace

EnvelopeBox work_envelope(const machine::Machine& machine) {
  EnvelopeBox envelope;
  machine::PoseBox& box = envelope.box;
  box.axes = machine.kinematics().dof();
  const machine::CartesianLimits& cartesian = machine.cartesian();
  const bool needs_reach = [&] {
    for (const int axis : box.axes.axes()) {
      if (!std::isfinite(cartesian.envelope_min[axis]) ||
          !std::isfinite(cartesian.envelope_max[axis]))
        return true;
    }
    return false;
  }();
  const machine::PoseBox reach = needs_reach ? machine::reach_box(machine) : machine::PoseBox{};
  const geometry::Vector6d home = machine.home().as_vector();
  for (const int axis : box.axes.axes()) {
    const bool low_given = std::isfinite(cartesian.envelope_min[axis]);
    const bool high_given = std::isfinite(cartesian.envelope_max[axis]);
    box.min[axis] = low_given ? cartesian.envelope_min[axis] : reach.min[axis];
    box.max[axis] = high_given ? cartesian.envelope_max[axis] : reach.max[axis];
    if (low_given && high_given) envelope.from_file = envelope.from_file.with(axis);
    const std::string name(geometry::kAxisNames[axis]);
    if (axis < 3 && (std::abs(box.min[axis] - home[axis]) > kNoFiniteReachMm ||
                     std::abs(box.max[axis] - home[axis]) > kNoFiniteReachMm)) {
      throw std::runtime_error(
          "the machine's reach along " + name + " is not finite (it goes on past " +
          std::to_string(static_cast<long>(kNoFiniteReachMm / machine.mm_per_unit())) + " " +
          machine.length_unit() + " from home): give [cartesian] min and max for " + name);
    }
    if (!(box.max[axis] > box.min[axis])) {
      throw std::runtime_error("the work envelope is empty along " + name +
                               ": give [cartesian] min and max for " + name);
    }
  }
  return envelope;
}

namespace {

// The cells of a bound in the making: leaves with a finite bound, and the tally.
class CellTree {
 public:
  CellTree(const machine::Machine& machine, const CellBounder& bounder, JointRateBound& bound,
           double whole)
      : machine_(machine), bounder_(bounder), bound_(bound), whole_volume_(whole) {
    const int n = machine.kinematics().joint_count();
    sampled_ = Eigen::MatrixXd::Zero(n, geometry::kPoseSize);
    sampled_curvature_.assign(static_cast<std::size_t>(n), 0.0);
  }

  // Looks at a cell: a leaf when its bound is finite, nothing when it is proven outside the joint
  // limits, back to the caller (false) when its bound is infinite.
  bool place(const Cell& cell) {
    ++bound_.cells;
    CellLook look = bounder_.look(cell);
    if (!look.finite) return false;
    if (look.outside) {
      ++bound_.excluded;
      return true;
    }
    if (look.reached) {
      sampled_ = sampled_.cwiseMax(look.at_centre);
      for (std::size_t k = 0; k < sampled_curvature_.size(); ++k) {
        sampled_curvature_[k] = std::max(sampled_curvature_[k], look.centre_curvature[k]);
      }
    }
    leaves_.push_back({cell, std::move(look)});
    return true;
  }

  // A cell left with an infinite bound: its share of the volume, and whether the machine takes
  // its centre (then the box meets a singularity or the edge of reach where the machine goes).
  void leave_unbounded(const Cell& cell) {
    bound_.uncovered += bounder_.volume(cell) / whole_volume_;
    kinematics::JointVector q;
    const geometry::Vector6d c = bounder_.centre(cell);
    if (!bound_.reaches_unbounded && machine_.inverse(geometry::Pose::from_vector(c), q).ok()) {
      bound_.reaches_unbounded = true;
      bound_.unbounded_pose = c;
    }
  }

  // Halves the leaves whose bound passes the samples by more than the slack, pass after pass,
  // while the cells last.
  void refine(const JointRateOptions& options) {
    for (bool split_any = true; split_any;) {
      split_any = false;
      std::vector<Leaf> leaves = std::move(leaves_);
      leaves_.clear();
      for (Leaf& leaf : leaves) {
        if (bound_.cells + 2 <= options.max_cells && leaf.cell.depth < options.max_depth &&
            needs_refining(leaf, sampled_, sampled_curvature_, options.relative_slack)) {
          split_any = true;
          const auto [low, high] = bounder_.split(leaf.cell);
          for (const Cell& half : {low, high}) {
            if (!place(half)) leave_unbounded(half);
          }
        } else {
          leaves_.push_back(std::move(leaf));
        }
      }
    }
  }

  void finish() {
    const int n = static_cast<int>(sampled_.rows());
    bound_.slope = Eigen::MatrixXd::Zero(n, geometry::kPoseSize);
    bound_.curvature.assign(static_cast<std::size_t>(n), 0.0);
    bound_.cell_slope.resize(static_cast<Eigen::Index>(leaves_.size()) * n, geometry::kPoseSize);
    Eigen::Index row = 0;
    for (const Leaf& leaf : leaves_) {
      bound_.slope = bound_.slope.cwiseMax(leaf.look.upper);
      for (int i = 0; i < n; ++i) {
        const std::size_t k = static_cast<std::size_t>(i);
        bound_.curvature[k] = std::max(bound_.curvature[k], leaf.look.curvature[k]);
        bound_.cell_slope.row(row++) = leaf.look.upper.row(i);
        bound_.cell_joint.push_back(i);
        bound_.cell_curvature.push_back(leaf.look.curvature[k]);
      }
    }
    bound_.sampled_slope = sampled_;
  }

 private:
  const machine::Machine& machine_;
  const CellBounder& bounder_;
  JointRateBound& bound_;
  double whole_volume_;
  std::vector<Leaf> leaves_;
  Eigen::MatrixXd sampled_;
  std::vector<double> sampled_curvature_;
};

}  // namespace

JointRateBound bound_joint_rates(const machine::Machine& machine, const machine::PoseBox& box,
                                 const JointRateOptions& options) {
  const kinematics::Kinematics& model = machine.kinematics();
  const double angle_scale_mm = pose_angle_scale_mm(model);
  if (!inverse_hessian_bounds(model, machine.home().as_vector(), 0.0, angle_scale_mm, {})) {
    return sample_joint_rates(machine, box, angle_scale_mm);
  }
  const CellBounder bounder(machine, angle_scale_mm);
  JointRateBound bound;
  bound.proven = true;
  bound.angle_scale_mm = angle_scale_mm;
  const Cell whole{box.min, box.max, 0};
  CellTree tree(machine, bounder, bound, bounder.volume(whole));
  // Cells whose bound is infinite (too large for the Hessian bound, or reaching a singularity)
  // are halved first, largest first, with half of the cells at most.
  const auto smaller = [&](const Cell& a, const Cell& b) {
    return bounder.radius(a) < bounder.radius(b);
  };
  std::vector<Cell> unbounded;
  if (!tree.place(whole)) unbounded.push_back(whole);
  while (!unbounded.empty()) {
    std::pop_heap(unbounded.begin(), unbounded.end(), smaller);
    const Cell cell = unbounded.back();
    unbounded.pop_back();
    if (bound.cells + 2 > options.max_cells / 2 || cell.depth >= options.max_depth) {
      tree.leave_unbounded(cell);
      continue;
    }
    const auto [low, high] = bounder.split(cell);
    for (const Cell& half : {low, high}) {
      if (tree.place(half)) continue;
      unbounded.push_back(half);
      std::push_heap(unbounded.begin(), unbounded.end(), smaller);
    }
  }
  tree.refine(options);
  tree.finish();
  return bound;
}

namespace {

// Per joint: its rate per unit of tool motion summed over the axes (angles weighed by ratio).
Eigen::VectorXd weighted_row_sums(const Eigen::MatrixXd& slope, double angle_scale_mm) {
  Eigen::VectorXd sums = Eigen::VectorXd::Zero(slope.rows());
  for (int i = 0; i < slope.rows(); ++i) {
    for (int axis = 0; axis < geometry::kPoseSize; ++axis) {
      sums[i] += std::abs(slope(i, axis)) * (axis < 3 ? 1.0 : 1.0 / angle_scale_mm);
    }
  }
  return sums;
}

machine::PoseBox shrunk(const machine::PoseBox& box, const geometry::Vector6d& home,
                        double factor) {
  machine::PoseBox result = box;
  for (int axis = 0; axis < geometry::kPoseSize; ++axis) {
    if (!box.axes.controls(axis)) continue;
    const double centre = std::clamp(home[axis], box.min[axis], box.max[axis]);
    result.min[axis] = centre - factor * (centre - box.min[axis]);
    result.max[axis] = centre + factor * (box.max[axis] - centre);
  }
  return result;
}

}  // namespace

FittedEnvelope fit_envelope(const machine::Machine& machine, const EnvelopeBox& requested,
                            const JointRateOptions& options) {
  const geometry::Vector6d home = machine.home().as_vector();
  kinematics::JointJacobian at_home;
  if (!machine.kinematics().jacobian(machine.home(), at_home).ok()) {
    throw std::runtime_error("the machine is singular at home: no joint-rate bound around it");
  }
  const double scale = pose_angle_scale_mm(machine.kinematics());
  const Eigen::VectorXd home_rates = weighted_row_sums(Eigen::MatrixXd(at_home.cwiseAbs()), scale);
  const auto acceptable = [&](const JointRateBound& bound) {
    if (bound.uncovered > 0.0) return false;
    const Eigen::VectorXd rates = weighted_row_sums(bound.slope, bound.angle_scale_mm);
    for (int i = 0; i < rates.size(); ++i) {
      if (rates[i] > kMaxSlopeGrowth * home_rates[i] * (1.0 + 1e-9)) return false;
    }
    return true;
  };
  FittedEnvelope fitted{requested, 1.0, bound_joint_rates(machine, requested.box, options)};
  if (acceptable(fitted.bound) || !fitted.bound.proven) return fitted;
  JointRateOptions search = options;
  search.max_cells = options.max_cells / 4;
  double good = 0.0, bad = 1.0;
  for (int step = 0; step < kShrinkSteps; ++step) {
    const double middle = 0.5 * (good + bad);
    const machine::PoseBox smaller = shrunk(requested.box, home, middle);
    (acceptable(bound_joint_rates(machine, smaller, search)) ? good : bad) = middle;
  }
  if (good == 0.0) {
    throw std::runtime_error(
        "no box around home keeps every joint's rate within " +
        std::to_string(static_cast<int>(kMaxSlopeGrowth)) +
        " times its rate at home: the machine is at or next to a singularity there");
  }
  fitted.shrink = good;
  fitted.box.box = shrunk(requested.box, home, good);
  fitted.bound = bound_joint_rates(machine, fitted.box.box, options);
  return fitted;
}

}  // namespace pkm::bounds
