#include "pkm/kinematics/cable_force_polytope.hpp"

#include <Eigen/Geometry>
#include <cmath>
#include <limits>

namespace pkm::kinematics {

namespace {

// Cables closer to parallel than this (the sine of their angle) give no facet of their own: the
// facets of the others hold theirs.
constexpr double kParallelSine = 1e-9;

// The facet with unit normal `normal` through cables `first` and `second` (-1: none).
void add_facet(const StructureMatrix& a, const TensionTargets& targets, Eigen::Vector3d normal,
               int first, int second, CableForcePolytope& polytope) {
  const double size = normal.norm();
  if (!(size > kParallelSine)) return;
  normal /= size;
  ForceFacet& facet = polytope.facets[static_cast<std::size_t>(polytope.count++)];
  facet = ForceFacet{normal, 0.0, 0.0, first, second, 0u, 0u};
  const int d = static_cast<int>(a.rows());
  for (int k = 0; k < a.cols(); ++k) {
    if (k == first || k == second) continue;  // perpendicular: 0, even times an infinite max
    const double s = normal.head(d).dot(a.col(k));
    if (s == 0.0) continue;
    const double at_min = s * targets.min_N[k], at_max = s * targets.max_N[k];
    facet.low_N += std::min(at_min, at_max);
    facet.high_N += std::max(at_min, at_max);
    (s > 0.0 ? facet.along : facet.against) |= std::uint32_t{1} << k;
  }
}

}  // namespace

bool cable_force_polytope(const StructureMatrix& a, const TensionTargets& targets,
                          CableForcePolytope& polytope) {
  polytope.count = 0;
  polytope.dimensions = static_cast<int>(a.rows());
  const int d = polytope.dimensions, n = static_cast<int>(a.cols());
  if ((d != 2 && d != 3) || n > kMaxCables || targets.min_N.size() != n ||
      targets.max_N.size() != n || !a.allFinite()) {
    return false;
  }
  // The cables span the effector's d directions: det(A A^T) well above rounding (each column is
  // a unit vector, so the trace of A A^T is n).
  const Eigen::Matrix3d gram = [&] {
    Eigen::Matrix3d g = Eigen::Matrix3d::Identity();
    g.topLeftCorner(d, d) = a * a.transpose();
    return g;
  }();
  if (!(gram.determinant() > 1e-12 * std::pow(static_cast<double>(n) / d, d))) return false;
  if (d == 2) {
    for (int i = 0; i < n; ++i) {
      add_facet(a, targets, Eigen::Vector3d(-a(1, i), a(0, i), 0.0), i, -1, polytope);
    }
    return polytope.count > 0;
  }
  for (int i = 0; i < n; ++i) {
    for (int j = i + 1; j < n; ++j) {
      const Eigen::Vector3d normal = Eigen::Vector3d(a.col(i)).cross(Eigen::Vector3d(a.col(j)));
      add_facet(a, targets, normal, i, j, polytope);
    }
  }
  return polytope.count > 0;
}

double CableForcePolytope::margin_N(const Eigen::Vector3d& force_N, int& facet, bool& high) const {
  double margin = std::numeric_limits<double>::infinity();
  facet = -1;
  high = false;
  for (int f = 0; f < count; ++f) {
    const ForceFacet& here = facets[static_cast<std::size_t>(f)];
    const double value = here.normal.dot(force_N);
    if (here.high_N - value < margin) {
      margin = here.high_N - value;
      facet = f;
      high = true;
    }
    if (value - here.low_N < margin) {
      margin = value - here.low_N;
      facet = f;
      high = false;
    }
  }
  return margin;
}

}  // namespace pkm::kinematics
