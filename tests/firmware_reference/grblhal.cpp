#include "grblhal.hpp"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace pkm::test::grblhal_reference {
namespace {

// The line less its (...) comments and spaces.
std::string bare(const std::string& line) {
  std::string out;
  int depth = 0;
  for (const char c : line) {
    if (c == '(')
      ++depth;
    else if (c == ')')
      --depth;
    else if (depth == 0 && c != ' ' && c != '\r')
      out += c;
  }
  return out;
}

}  // namespace

WallPlotterFile parse(const std::string& text) {
  WallPlotterFile file;
  std::istringstream in(text);
  std::string raw;
  while (std::getline(in, raw)) {
    const std::string line = bare(raw);
    if (line.rfind("$", 0) == 0) {
      const std::size_t equals = line.find('=');
      file.settings[std::stoi(line.substr(1, equals - 1))] = std::stod(line.substr(equals + 1));
    } else if (line.rfind("G10L2P1", 0) == 0) {
      std::size_t at = 7;
      while (at < line.size()) {
        const char axis = line[at];
        std::size_t used = 0;
        const double value = std::stod(line.substr(at + 1), &used);
        file.g54[axis - 'X'] = value;
        at += 1 + used;
      }
    } else if (!line.empty()) {
      throw std::runtime_error("reference parser: unexpected line: " + raw);
    }
  }
  return file;
}

// wall_plotter.c transform_from_cartesian: A = sqrt(x^2 + y^2), B = sqrt((W - x)^2 + y^2), the
// axes after Y copied.
Eigen::Vector3d motors_mm(const WallPlotterFile& file, const Eigen::Vector3d& g54_position_mm) {
  const Eigen::Vector3d p = g54_position_mm + file.g54;
  const double w = file.width_mm();
  return {std::sqrt(p.x() * p.x() + p.y() * p.y()),
          std::sqrt((w - p.x()) * (w - p.x()) + p.y() * p.y()), p.z()};
}

Eigen::Vector3d motors_mm_float(const WallPlotterFile& file,
                                const Eigen::Vector3d& g54_position_mm) {
  // gc_state.position is float: the G54 offset is added in float, then the same formulas.
  const float x = static_cast<float>(g54_position_mm.x()) + static_cast<float>(file.g54.x());
  const float y = static_cast<float>(g54_position_mm.y()) + static_cast<float>(file.g54.y());
  const float z = static_cast<float>(g54_position_mm.z()) + static_cast<float>(file.g54.z());
  const float w = static_cast<float>(file.width_mm());
  const float b_x = w - x;
  return {static_cast<double>(std::sqrt(x * x + y * y)),
          static_cast<double>(std::sqrt(b_x * b_x + y * y)), static_cast<double>(z)};
}

// wall_plotter.c transform_to_cartesian: x from the two circles' radical line, y the positive root.
Eigen::Vector3d machine_position_mm(const WallPlotterFile& file, const Eigen::Vector3d& motors) {
  const double w = file.width_mm();
  const double x = (w * w + motors.x() * motors.x() - motors.y() * motors.y()) / (2.0 * w);
  const double rest = w - x;
  return {x, std::sqrt(motors.y() * motors.y() - rest * rest), motors.z()};
}

}  // namespace pkm::test::grblhal_reference

namespace pkm::test::grblhal_reference {
namespace {

// One arm in its own y z plane (delta_calcAngleYZ): the pivot at y1 = -f tan30 / 2, the point's
// joint e tan30 / 2 nearer -y; the elbow is where the bicep's circle meets the forearm's sphere,
// the outer of the two points; the angle is measured from the horizontal, down positive.
bool arm_angle(double f, double e, double rf, double re, double x0, double y0, double z0,
               double& theta) {
  const double tan30 = 1.0 / std::sqrt(3.0);
  const double y1 = -0.5 * tan30 * f;
  y0 -= 0.5 * tan30 * e;
  const double a = (x0 * x0 + y0 * y0 + z0 * z0 + rf * rf - re * re - y1 * y1) / (2.0 * z0);
  const double b = (y1 - y0) / z0;
  const double d = -(a + b * y1) * (a + b * y1) + rf * (b * b * rf + rf);
  if (d < 0.0) return false;
  const double yj = (y1 - a * b - std::sqrt(d)) / (b * b + 1.0);
  const double zj = a + b * yj;
  theta = std::atan(-zj / (y1 - yj)) + (yj > y1 ? M_PI : 0.0);
  return true;
}

}  // namespace

bool delta_angles_rad(const WallPlotterFile& file, const Eigen::Vector3d& p,
                      Eigen::Vector3d& angles_rad) {
  const double re = file.settings.at(641), rf = file.settings.at(642);
  const double f = file.settings.at(643), e = file.settings.at(644);
  const double c = std::cos(2.0 * M_PI / 3.0), s = std::sin(2.0 * M_PI / 3.0);
  // Arms B and C see the point turned by -120 and +120 deg (their planes at +120 and +240).
  return arm_angle(f, e, rf, re, p.x(), p.y(), p.z(), angles_rad[0]) &&
         arm_angle(f, e, rf, re, p.x() * c + p.y() * s, p.y() * c - p.x() * s, p.z(),
                   angles_rad[1]) &&
         arm_angle(f, e, rf, re, p.x() * c - p.y() * s, p.y() * c + p.x() * s, p.z(),
                   angles_rad[2]);
}

}  // namespace pkm::test::grblhal_reference
