#include "fluidnc.hpp"

#include <cmath>
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

}  // namespace pkm::test::fluidnc_reference
