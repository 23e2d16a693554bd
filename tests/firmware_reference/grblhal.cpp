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
