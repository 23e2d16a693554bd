#include "fluidnc.hpp"

#include <cmath>
#include <numbers>
#include <sstream>
#include <stdexcept>
#include <vector>

namespace pkm::test::fluidnc_reference {

std::map<std::string, std::string> read_config(const std::string& text) {
  std::map<std::string, std::string> values;
  std::vector<std::pair<std::size_t, std::string>> path;  // (indent, key) of open sections
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) {
    const std::size_t indent = line.find_first_not_of(' ');
    if (indent == std::string::npos || line[indent] == '#') continue;
    const std::size_t colon = line.find(':', indent);
    if (colon == std::string::npos) throw std::runtime_error("no ':' in '" + line + "'");
    while (!path.empty() && path.back().first >= indent) path.pop_back();
    std::string key = line.substr(indent, colon - indent);
    for (char& c : key) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    std::string full;
    for (const auto& [depth, name] : path) full += name + ".";
    full += key;
    std::string value = line.substr(colon + 1);
    value.erase(0, value.find_first_not_of(' '));
    values[full] = value;
    path.emplace_back(indent, key);
  }
  return values;
}

WallPlotter wall_plotter(const std::map<std::string, std::string>& config) {
  WallPlotter plotter;
  auto number = [&](const std::string& key, double& out) {
    const auto found = config.find(key);
    if (found != config.end()) out = std::stod(found->second);
  };
  number("kinematics.wallplotter.left_anchor_x", plotter.left_anchor_x);
  number("kinematics.wallplotter.left_anchor_y", plotter.left_anchor_y);
  number("kinematics.wallplotter.right_anchor_x", plotter.right_anchor_x);
  number("kinematics.wallplotter.right_anchor_y", plotter.right_anchor_y);
  plotter.has_z = config.count("axes.z") > 0;
  const auto startup = config.find("macros.startup_line0");
  if (startup != config.end()) {
    std::istringstream words(startup->second);
    std::string word;
    while (words >> word) {
      if (word[0] == 'X') plotter.g54_origin.x() = std::stod(word.substr(1));
      if (word[0] == 'Y') plotter.g54_origin.y() = std::stod(word.substr(1));
      if (word[0] == 'Z') plotter.g54_origin.z() = std::stod(word.substr(1));
    }
  }
  return plotter;
}

std::array<double, 3> motors(const WallPlotter& p, const Eigen::Vector3d& work_mm) {
  // Work coordinates are machine coordinates less G54's origin.
  const Eigen::Vector3d machine = work_mm + p.g54_origin;
  // init(): the cords' lengths at machine (0, 0), where the motors count from.
  const double zero_left = std::hypot(p.left_anchor_x, p.left_anchor_y);
  const double zero_right = std::hypot(p.right_anchor_x, p.right_anchor_y);
  const double left = std::hypot(p.left_anchor_x - machine.x(), p.left_anchor_y - machine.y());
  const double right = std::hypot(p.right_anchor_x - machine.x(), p.right_anchor_y - machine.y());
  return {-(left - zero_left), right - zero_right, machine.z()};
}

std::array<double, 3> motors_float(const WallPlotter& p, const Eigen::Vector3d& work_mm) {
  // G-code's coordinates reach the kinematics as floats, already in machine coordinates.
  const float x = static_cast<float>(work_mm.x() + p.g54_origin.x());
  const float y = static_cast<float>(work_mm.y() + p.g54_origin.y());
  const float lx = static_cast<float>(p.left_anchor_x), ly = static_cast<float>(p.left_anchor_y);
  const float rx = static_cast<float>(p.right_anchor_x), ry = static_cast<float>(p.right_anchor_y);
  const float zero_left = std::hypot(lx, ly);
  const float zero_right = std::hypot(rx, ry);
  const float left = std::hypot(lx - x, ly - y);
  const float right = std::hypot(rx - x, ry - y);
  return {-(left - zero_left), right - zero_right,
          static_cast<float>(work_mm.z() + p.g54_origin.z())};
}

ParallelDelta parallel_delta(const std::map<std::string, std::string>& config) {
  ParallelDelta delta;
  auto number = [&](const std::string& key, double& out) {
    const auto found = config.find("kinematics.parallel_delta." + key);
    if (found != config.end()) out = std::stod(found->second);
  };
  number("crank_mm", delta.crank_mm);
  number("base_triangle_mm", delta.base_triangle_mm);
  number("linkage_mm", delta.linkage_mm);
  number("end_effector_triangle_mm", delta.end_effector_triangle_mm);
  number("up_degrees", delta.up_degrees);
  return delta;
}

bool arm_degrees(const ParallelDelta& d, const Eigen::Vector3d& point_mm,
                 std::array<double, 3>& degrees) {
  // An equilateral triangle's inradius is its side / (2 sqrt 3).
  const double pivot = d.base_triangle_mm / (2.0 * std::sqrt(3.0));
  const double joint = d.end_effector_triangle_mm / (2.0 * std::sqrt(3.0));
  for (int arm = 0; arm < 3; ++arm) {
    // Turn the point by -120 deg per arm: each arm is then arm 0, on the -y side.
    const double turn = -2.0 * std::numbers::pi / 3.0 * arm;
    const double x = std::cos(turn) * point_mm.x() - std::sin(turn) * point_mm.y();
    const double y = std::sin(turn) * point_mm.x() + std::cos(turn) * point_mm.y();
    // The effector's joint J = (x, y - joint, z); the elbow E = (0, -pivot - crank cos t,
    // -crank sin t). |E - J| = linkage gives A cos t + B sin t = K with A = pivot + J.y,
    // B = J.z: t = atan2(B, A) -+ acos(K / hypot(A, B)); the outer elbow has the larger cos t.
    const double jy = y - joint, jz = point_mm.z();
    const double a = pivot + jy, b = jz;
    const double k =
        (d.linkage_mm * d.linkage_mm - x * x - a * a - b * b - d.crank_mm * d.crank_mm) /
        (2.0 * d.crank_mm);
    const double r = std::hypot(a, b);
    if (std::abs(k) > r) return false;
    const double alpha = std::atan2(b, a), beta = std::acos(k / r);
    const double t = std::cos(alpha - beta) > std::cos(alpha + beta) ? alpha - beta : alpha + beta;
    degrees[arm] = std::remainder(t, 2.0 * std::numbers::pi) * 180.0 / std::numbers::pi;
    if (!(degrees[arm] > d.up_degrees - 1.0)) return false;
  }
  return true;
}

}  // namespace pkm::test::fluidnc_reference
