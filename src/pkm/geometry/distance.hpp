// Distances between points and polylines, for measuring deviations from a path.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <limits>

namespace pkm {

// Distance from p to the line segment from a to b (mm).
inline double distance_to_segment(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                  const Eigen::Vector3d& b) {
  const Eigen::Vector3d ab = b - a;
  const double squared = ab.squaredNorm();
  const double u = squared > 0.0 ? std::clamp((p - a).dot(ab) / squared, 0.0, 1.0) : 0.0;
  return (a + u * ab - p).norm();
}

// Distance from p to the polyline through `points` (a container of Eigen::Vector3d).
template <class Points>
double distance_to_polyline(const Eigen::Vector3d& p, const Points& points) {
  double nearest = std::numeric_limits<double>::infinity();
  for (std::size_t k = 1; k < points.size(); ++k) {
    nearest = std::min(nearest, distance_to_segment(p, points[k - 1], points[k]));
  }
  return nearest;
}

}  // namespace pkm
