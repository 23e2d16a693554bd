#include "klipper.hpp"  // tests/firmware_reference/klipper.hpp

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>
#include <stdexcept>

namespace pkm::test::klipper_reference {
namespace {

std::string stripped(const std::string& text) {
  const std::size_t first = text.find_first_not_of(" \t\r");
  if (first == std::string::npos) return "";
  return text.substr(first, text.find_last_not_of(" \t\r") - first + 1);
}

double value(const Config& config, const std::string& section, const std::string& key,
             const double* fallback) {
  const auto found = config.find(section);
  if (found != config.end()) {
    const auto option = found->second.find(key);
    if (option != found->second.end()) return std::stod(option->second);
  }
  if (fallback == nullptr) throw std::runtime_error("[" + section + "] " + key + " missing");
  return *fallback;
}

}  // namespace

Config parse(const std::string& text) {
  Config config;
  std::istringstream lines(text);
  std::string section;
  for (std::string line; std::getline(lines, line);) {
    line = stripped(line.substr(0, line.find('#')));
    if (line.empty()) continue;
    if (line.front() == '[') {
      section = stripped(line.substr(1, line.find(']') - 1));
      continue;
    }
    const std::size_t colon = line.find_first_of(":=");
    std::string key = stripped(line.substr(0, colon));
    std::transform(key.begin(), key.end(), key.begin(), ::tolower);
    config[section][key] = stripped(line.substr(colon + 1));
  }
  return config;
}

Delta delta(const Config& config) {
  if (config.at("printer").at("kinematics") != "delta") throw std::runtime_error("not a delta");
  Delta result;
  result.radius = value(config, "printer", "delta_radius", nullptr);
  result.print_radius = value(config, "printer", "print_radius", &result.radius);
  const double zero = 0.0;
  result.min_z = value(config, "printer", "minimum_z_position", &zero);
  const double arm_a = value(config, "stepper_a", "arm_length", nullptr);
  const double endstop_a = value(config, "stepper_a", "position_endstop", nullptr);
  const std::array<double, 3> default_angles = {210.0, 330.0, 90.0};
  const std::array<std::string, 3> names = {"stepper_a", "stepper_b", "stepper_c"};
  result.max_z = endstop_a;
  for (int i = 0; i < 3; ++i) {
    const double angle =
        value(config, names[i], "angle", &default_angles[i]) * std::numbers::pi / 180.0;
    result.tower_x[i] = std::cos(angle) * result.radius;
    result.tower_y[i] = std::sin(angle) * result.radius;
    result.arm[i] = value(config, names[i], "arm_length", &arm_a);
    const double endstop = value(config, names[i], "position_endstop", &endstop_a);
    result.max_z = std::min(result.max_z, endstop);
    result.abs_endstop[i] =
        endstop + std::sqrt(result.arm[i] * result.arm[i] - result.radius * result.radius);
    const double none = 0.0, full = 200.0;
    const double distance = value(config, names[i], "rotation_distance", &none);
    if (distance > 0.0) {
      result.steps_per_mm[i] = value(config, names[i], "full_steps_per_rotation", &full) *
                               value(config, names[i], "microsteps", nullptr) / distance;
    }
  }
  return result;
}

std::array<double, 3> stepper_coordinates(const Delta& delta, double x, double y, double z) {
  std::array<double, 3> coordinates{};
  for (int i = 0; i < 3; ++i) {
    const double dx = delta.tower_x[i] - x, dy = delta.tower_y[i] - y;
    coordinates[i] = std::sqrt(delta.arm[i] * delta.arm[i] - dx * dx - dy * dy) + z;
  }
  return coordinates;
}

double rotary_arm_angle(double shoulder_radius, double shoulder_height, double angle_deg,
                        double upper_arm, double lower_arm, double x, double y, double z) {
  const double angle = angle_deg * std::numbers::pi / 180.0;
  // The tool in the arm's plane: outward from the shoulder, up from it, and across the plane.
  const double out = x * std::cos(angle) + y * std::sin(angle) - shoulder_radius;
  const double up = z - shoulder_height;
  const double across = -x * std::sin(angle) + y * std::cos(angle);
  const double lower2 = lower_arm * lower_arm - across * across;  // the forearm in the plane
  // The elbow: on the circle of upper_arm about the shoulder and of the in-plane forearm about
  // the tool; the two circles meet on the chord at `along` from the shoulder.
  const double distance = std::hypot(out, up);
  const double along = (upper_arm * upper_arm - lower2 + distance * distance) / (2.0 * distance);
  const double half_chord = std::sqrt(upper_arm * upper_arm - along * along);
  const double ux = out / distance, uy = up / distance;
  const double x1 = along * ux - half_chord * uy, y1 = along * uy + half_chord * ux;
  const double x2 = along * ux + half_chord * uy, y2 = along * uy - half_chord * ux;
  return x1 > x2 ? std::atan2(y1, x1) : std::atan2(y2, x2);
}

std::vector<std::array<double, 3>> winch_anchors(const Config& config) {
  if (config.at("printer").at("kinematics") != "winch") throw std::runtime_error("not a winch");
  std::vector<std::array<double, 3>> anchors;
  for (char letter = 'a'; letter <= 'z'; ++letter) {
    const std::string section = std::string("stepper_") + letter;
    if (letter > 'c' && config.find(section) == config.end()) break;
    anchors.push_back({value(config, section, "anchor_x", nullptr),
                       value(config, section, "anchor_y", nullptr),
                       value(config, section, "anchor_z", nullptr)});
  }
  return anchors;
}

std::vector<double> winch_stepper_coordinates(const std::vector<std::array<double, 3>>& anchors,
                                              double x, double y, double z) {
  std::vector<double> lines;
  for (const std::array<double, 3>& anchor : anchors) {
    const double dx = anchor[0] - x, dy = anchor[1] - y, dz = anchor[2] - z;
    lines.push_back(std::sqrt(dx * dx + dy * dy + dz * dz));
  }
  return lines;
}

}  // namespace pkm::test::klipper_reference
