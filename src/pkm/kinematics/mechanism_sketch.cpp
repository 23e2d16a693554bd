#include "pkm/kinematics/mechanism_sketch.hpp"

#include <cmath>
#include <numbers>

namespace pkm::kinematics {

void sketch_loop(std::vector<SketchLine>& out, SketchPart part,
                 const std::vector<Eigen::Vector3d>& corners) {
  for (std::size_t i = 0; i < corners.size(); ++i) {
    out.push_back({part, corners[i], corners[(i + 1) % corners.size()]});
  }
}

void sketch_circle(std::vector<SketchLine>& out, SketchPart part, const Eigen::Vector3d& centre,
                   double radius, const Eigen::Vector3d& u, const Eigen::Vector3d& v) {
  std::vector<Eigen::Vector3d> corners;
  for (int k = 0; k < 24; ++k) {
    const double angle = 2.0 * std::numbers::pi * k / 24.0;
    corners.push_back(centre + radius * (std::cos(angle) * u + std::sin(angle) * v));
  }
  sketch_loop(out, part, corners);
}

}  // namespace pkm::kinematics
