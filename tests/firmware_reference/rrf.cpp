#include "rrf.hpp"

#include <cmath>
#include <sstream>
#include <stdexcept>
#include <vector>

namespace pkm::test::rrf_reference {
namespace {

constexpr double kPi = 3.14159265358979323846;
double radians(double degrees) {
  return degrees * kPi / 180.0;
}

std::vector<double> colon_list(const std::string& text) {
  std::vector<double> values;
  std::stringstream stream(text);
  std::string item;
  while (std::getline(stream, item, ':')) values.push_back(std::stod(item));
  return values;
}

void apply(LinearDelta& delta, const std::string& code, char letter, const std::string& value) {
  const std::string key = code + " " + letter;
  if (code == "M665" && letter == 'L') {
    const std::vector<double> rods = colon_list(value);
    for (std::size_t k = 0; k < 3; ++k) delta.diagonals[k] = k < rods.size() ? rods[k] : rods[0];
    return;
  }
  const double number = std::stod(value);
  if (code == "M665") {
    if (letter == 'R') delta.radius = number;
    if (letter == 'H') delta.homed_height = number;
    if (letter == 'B') delta.print_radius = number;
    if (letter == 'X') delta.angle_corrections[0] = number;
    if (letter == 'Y') delta.angle_corrections[1] = number;
    if (letter == 'Z') delta.angle_corrections[2] = number;
  } else if (code == "M666") {
    if (letter == 'X') delta.endstop_adjustments[0] = number;
    if (letter == 'Y') delta.endstop_adjustments[1] = number;
    if (letter == 'Z') delta.endstop_adjustments[2] = number;
    if (letter == 'A') delta.x_tilt = number * 0.01;
    if (letter == 'B') delta.y_tilt = number * 0.01;
  }
  delta.settings[key] = number;
}

// "; drive Y = tower B = joint 3 ..." names joint 3 (from 1) for drive Y.
void read_drive_comment(LinearDelta& delta, const std::string& comment) {
  std::istringstream words(comment);
  std::string semicolon, drive_word, drive, eq1, tower_word, tower, eq2, joint_word;
  int joint = 0;
  words >> semicolon >> drive_word >> drive >> eq1 >> tower_word >> tower >> eq2 >> joint_word >>
      joint;
  if (drive_word != "drive" || joint_word != "joint" || drive.size() != 1) return;
  const int index = drive[0] - 'X';
  if (index >= 0 && index < 3) delta.joint_of_drive[static_cast<std::size_t>(index)] = joint - 1;
}

}  // namespace

LinearDelta parse(const std::string& config_text) {
  LinearDelta delta;
  std::istringstream lines(config_text);
  std::string line;
  while (std::getline(lines, line)) {
    if (line.rfind("; drive ", 0) == 0) read_drive_comment(delta, line);
    const std::string code_part = line.substr(0, line.find(';'));
    std::istringstream words(code_part);
    std::string code, word;
    if (!(words >> code)) continue;
    while (words >> word) apply(delta, code, word[0], word.substr(1));
  }
  return delta;
}

std::array<double, 2> tower_position(const LinearDelta& delta, int tower) {
  const double r = delta.radius;
  const std::array<double, 3>& c = delta.angle_corrections;
  switch (tower) {
    case 0:
      return {-r * std::cos(radians(30.0 + c[0])), -r * std::sin(radians(30.0 + c[0]))};
    case 1:
      return {r * std::cos(radians(30.0 - c[1])), -r * std::sin(radians(30.0 - c[1]))};
    case 2:
      return {-r * std::sin(radians(c[2])), r * std::cos(radians(c[2]))};
    default:
      throw std::out_of_range("tower");
  }
}

double motor_position(const LinearDelta& delta, int tower, double x, double y, double z) {
  const std::array<double, 2> at = tower_position(delta, tower);
  const double rod = delta.diagonals[static_cast<std::size_t>(tower)];
  return std::sqrt(rod * rod - (x - at[0]) * (x - at[0]) - (y - at[1]) * (y - at[1])) + z +
         x * delta.x_tilt + y * delta.y_tilt;
}

double homed_carriage_height(const LinearDelta& delta, int tower) {
  const double rod = delta.diagonals[static_cast<std::size_t>(tower)];
  return delta.homed_height + std::sqrt(rod * rod - delta.radius * delta.radius) +
         delta.endstop_adjustments[static_cast<std::size_t>(tower)];
}

}  // namespace pkm::test::rrf_reference
