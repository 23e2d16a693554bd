#include "pkm/post/deviation_bound.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

namespace pkm::post {

using bounds::inverse_hessian_bounds;
using bounds::piece_motion;
using bounds::PieceMotion;
using bounds::pose_angle_scale_mm;
using kinematics::HessianBounds;
using motion::Segment;

DeviationBound::DeviationBound(const machine::Machine& machine, double tolerance_mm)
    : machine_(machine),
      reach_mm_(std::min(3.0 * tolerance_mm, 1.5)),
      axes_(machine.kinematics().dof().axes()) {
  const kinematics::Kinematics& model = machine.kinematics();
  angle_scale_mm_ = pose_angle_scale_mm(model);
  available_ = model.joint_count() == static_cast<int>(axes_.size()) &&
               inverse_hessian_bounds(model, machine.home().as_vector(), 0.0, angle_scale_mm_, {})
                   .has_value();
}

namespace {

// The inverse of the Jacobian at a pose in scaled coordinates, and its rows for x y z; nothing
// where it is singular.
struct CentreInverse {
  Eigen::MatrixXd all, position;
};

std::optional<CentreInverse> centre_inverse(const kinematics::Kinematics& model,
                                            const geometry::Vector6d& pose,
                                            const std::vector<int>& axes, double angle_scale_mm) {
  kinematics::JointJacobian full;
  if (!model.jacobian(geometry::Pose::from_vector(pose), full).ok()) return std::nullopt;
  const int n = static_cast<int>(axes.size());
  Eigen::MatrixXd jacobian(n, n);
  std::vector<int> position_rows;
  for (int k = 0; k < n; ++k) {
    const int axis = axes[static_cast<std::size_t>(k)];
    jacobian.col(k) = full.col(axis) / (axis >= 3 ? angle_scale_mm : 1.0);
    if (axis < 3) position_rows.push_back(k);
  }
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(jacobian, Eigen::ComputeFullU | Eigen::ComputeFullV);
  const double smallest = svd.singularValues()[n - 1];
  if (!(smallest > 0.0) || !std::isfinite(smallest)) return std::nullopt;
  CentreInverse inverse{svd.solve(Eigen::MatrixXd::Identity(n, n)),
                        Eigen::MatrixXd(static_cast<int>(position_rows.size()), n)};
  for (std::size_t r = 0; r < position_rows.size(); ++r) {
    inverse.position.row(static_cast<int>(r)) = inverse.all.row(position_rows[r]);
  }
  return inverse;
}

// The largest |M e| over the box |e_i| <= half_width_i: a convex function is largest at a
// corner of the box, and e and -e give the same norm, so half the corners are enough. Unlike
// |M| |half_width|, it lets a joint whose error is large but moves the tool little (a strut
// nearly square to its rail) weigh only as much as it moves the tool.
double largest_over_box(const Eigen::MatrixXd& m, const Eigen::VectorXd& half_width) {
  const int n = static_cast<int>(half_width.size());
  if (m.rows() == 0 || n == 0) return 0.0;
  // An infinite half-width (a curvature bound at a singularity) makes M e infinite, since M
  // (invertible) has no zero column, but inf - inf within M e reads NaN, which std::max drops.
  if (!half_width.allFinite()) return INFINITY;
  double largest = 0.0;
  for (unsigned signs = 0; signs < (1u << (n - 1)); ++signs) {
    Eigen::VectorXd e = half_width;
    for (int i = 1; i < n; ++i) {
      if ((signs >> (i - 1)) & 1u) e[i] = -e[i];
    }
    largest = std::max(largest, (m * e).norm());
  }
  return largest;
}

// How far J^-1 may drift, relative to its value M at the centre, per mm from the centre: bounds
// on |M (J(x) - J(c))| / |x - c| and on its position rows.
struct Drift {
  double all = 0.0, position = 0.0;
};

// Where along the block the joints and the drift are: the poses the argument visits at fraction
// lambda lie within |lambda - 1/2| `chord_mm` + `sagitta_mm` (at most `half_length_mm`) + the
// reach of the centre, and the programmed point is within 4 lambda (1 - lambda) `sagitta_mm` of
// the chord.
struct BlockShape {
  double chord_mm = 0.0, sagitta_mm = 0.0, half_length_mm = 0.0, reach_mm = 0.0;
};

// Joint errors e(lambda) = 4 lambda (1 - lambda) (exact + a) + b, a in the box `shaped` and b in
// the box `flat`.
struct JointError {
  Eigen::VectorXd exact, shaped, flat;
};

// Bounds on |m e(lambda)|: shaped at(f) = f shaped + flat, and never above the whole at f = 1.
struct ErrorImage {
  double shaped = 0.0, flat = 0.0, whole = 0.0;
  double at(double f) const { return std::min(f * shaped + flat, whole); }
};

ErrorImage image(const Eigen::MatrixXd& m, const JointError& error) {
  const double exact = (m * error.exact).norm();
  return {exact + largest_over_box(m, error.shaped), largest_over_box(m, error.flat),
          exact + largest_over_box(m, error.shaped + error.flat)};
}

constexpr int kStretches = 8;  // of lambda in [0, 1/2]; the bound is symmetric about 1/2

// The tool tip's distance from the programmed point at the same fraction (docs/post.md, "The
// bound", steps 4 and 5), the largest over stretches of lambda, each taken at its largest error
// and drift; infinity where J's drift reaches 1 or the joint error could carry the pose beyond
// the reach.
double tool_distance(const CentreInverse& inverse, const JointError& error, const Drift& per_mm,
                     const BlockShape& shape) {
  const ErrorImage moved = image(inverse.all, error);
  const ErrorImage position = image(inverse.position, error);
  double worst = 0.0;
  for (int k = 0; k < kStretches; ++k) {
    const double from = 0.5 * k / kStretches, to = 0.5 * (k + 1) / kStretches;
    const double f = 4.0 * to * (1.0 - to);
    const double radius =
        std::min((0.5 - from) * shape.chord_mm + shape.sagitta_mm, shape.half_length_mm) +
        shape.reach_mm;
    const double drift = per_mm.all * radius;
    if (!(drift < 1.0)) return INFINITY;
    const double y = moved.at(f);
    if (!(y / (1.0 - drift) < shape.reach_mm)) return INFINITY;
    worst = std::max(worst, position.at(f) + per_mm.position * radius / (1.0 - drift) * y +
                                f * shape.sagitta_mm);
  }
  return worst;
}

// The chord error from the joints at the chord's middle: e(lambda) - 4 lambda (1 - lambda)
// e(1/2) vanishes at 0, 1/2 and 1, so it is within |G'''| max|lambda (lambda - 1/2)
// (lambda - 1)| / 6 = |G'''| sqrt(3) / 216 (the remainder of quadratic interpolation), and
// 4 lambda (1 - lambda) <= 1.
double middle_tool_distance(const kinematics::Kinematics& model, const geometry::Vector6d& start,
                            const geometry::Vector6d& end, const BlockEnds& ends,
                            const CentreInverse& inverse, const kinematics::HessianBounds& hessians,
                            const Eigen::VectorXd& rounding, const Drift& drift,
                            const BlockShape& shape) {
  kinematics::JointVector middle;
  if (!model.inverse(geometry::Pose::from_vector(0.5 * (start + end)), middle).ok())
    return INFINITY;
  const int n = static_cast<int>(rounding.size());
  Eigen::VectorXd at_middle(n), spread(n);
  for (int i = 0; i < n; ++i) {
    at_middle[i] = 0.5 * (ends.exact0[i] + ends.exact1[i]) - middle[i];
    spread[i] = rounding[i] + std::sqrt(3.0) / 216.0 * hessians.third[static_cast<std::size_t>(i)];
  }
  return tool_distance(inverse, {at_middle, Eigen::VectorXd::Zero(n), spread}, drift, shape);
}

}  // namespace

// The argument (docs/post.md, "The bound"): C, the straight chord in pose space between the
// piece's programmed ends, is within |S''| / 8 of the programmed point at the same fraction. The
// joint error e of the block against IK(C) is its ends' rounding plus the chord error of IK along
// C: at most |H[C', C']| / 8 per joint, or, where the model bounds IK's third derivative, the
// error at the chord's middle (one inverse kinematics) spread as 4 lambda (1 - lambda) plus a
// cubic remainder. Where J(c)^-1 (J(x) - J(c)) stays below 1 over the ball of the piece plus the
// reach, that joint error moves the tool tip at most |J(c)^-1 e| / (1 - drift) from C.
double DeviationBound::operator()(const Segment& segment, double u0, double u1,
                                  const BlockEnds& ends) const {
  if (!available_) return INFINITY;
  const kinematics::Kinematics& model = machine_.kinematics();
  const PieceMotion piece = piece_motion(segment, u0, u1, axes_, angle_scale_mm_);
  const std::optional<CentreInverse> inverse =
      centre_inverse(model, piece.centre, axes_, angle_scale_mm_);
  if (!inverse) return INFINITY;
  const double radius = 0.5 * piece.length + reach_mm_;
  const auto hessians =
      inverse_hessian_bounds(model, piece.centre, radius, angle_scale_mm_, piece.chord);
  if (!hessians) return INFINITY;
  const int n = static_cast<int>(hessians->norm.size());
  // Each joint's gradient moves at most |H_i| per mm over the ball: the drift of J^-1.
  Eigen::VectorXd curvature(n), rounding(n), chord_error(n);
  for (int i = 0; i < n; ++i) {
    const std::size_t k = static_cast<std::size_t>(i);
    curvature[i] = hessians->norm[k];
    rounding[i] = std::max(std::abs(ends.written0[i] - ends.exact0[i]),
                           std::abs(ends.written1[i] - ends.exact1[i]));
    chord_error[i] = hessians->along[k] / 8.0;
  }
  const Drift drift{largest_over_box(inverse->all, curvature),
                    largest_over_box(inverse->position, curvature)};
  const BlockShape shape{std::hypot(piece.chord.position.norm(), piece.chord.angle),
                         piece.acceleration / 8.0, 0.5 * piece.length, reach_mm_};
  double distance =
      tool_distance(*inverse, {Eigen::VectorXd::Zero(n), chord_error, rounding}, drift, shape);
  if (static_cast<int>(hessians->third.size()) == n) {
    distance =
        std::min(distance, middle_tool_distance(model, segment.at(u0), segment.at(u1), ends,
                                                *inverse, *hessians, rounding, drift, shape));
  }
  return distance;
}

}  // namespace pkm::post
