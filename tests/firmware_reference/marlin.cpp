#include "marlin.hpp"

#include <cmath>
#include <cstdlib>
#include <sstream>
#include <stdexcept>

namespace pkm::test::marlin_reference {
namespace {

std::vector<double> numbers_in(std::string value) {
  for (char& c : value) {
    if (c == '{' || c == '}' || c == ',') c = ' ';
  }
  std::istringstream in(value);
  std::vector<double> numbers;
  std::string word;
  while (in >> word) numbers.push_back(std::strtod(word.c_str(), nullptr));
  return numbers;
}

void read_joint_line(const std::string& line, Config& config) {
  // "// pkmkit joints: X = joint 2 tower_b, Y = joint 3 tower_c, Z = none"
  for (int k = 0; k < 3; ++k) {
    const std::string key = std::string(1, "XYZ"[k]) + " = ";
    const std::size_t at = line.find(key);
    if (at == std::string::npos) continue;
    const std::string rest = line.substr(at + key.size());
    config.joint_of_stepper[k] =
        rest.rfind("joint ", 0) == 0 ? std::atoi(rest.c_str() + 6) - 1 : -1;
  }
}

double at(const Config& config, const std::string& name, int index = 0) {
  const auto found = config.values.find(name);
  if (found == config.values.end() || static_cast<int>(found->second.size()) <= index) {
    throw std::runtime_error("reference: no " + name);
  }
  return found->second[index];
}

}  // namespace

Config parse(const std::string& text) {
  Config config;
  std::istringstream lines(text);
  std::string line;
  while (std::getline(lines, line)) {
    if (line.rfind("// pkmkit joints:", 0) == 0) read_joint_line(line, config);
    if (line.rfind("#define ", 0) != 0) continue;
    const std::size_t comment = line.find("//");
    std::istringstream words(
        line.substr(8, comment == std::string::npos ? std::string::npos : comment - 8));
    std::string name, value, word;
    words >> name;
    while (words >> word) value += word + " ";
    if (name == "DELTA") config.delta = true;
    if (name == "POLARGRAPH") config.polargraph = true;
    if (!value.empty() && value[0] != '"') config.values[name] = numbers_in(value);
  }
  return config;
}

std::array<double, 3> stepper_positions(const Config& c, const Eigen::Vector3d& p) {
  if (c.polargraph) {
    // Belts from (X_MIN_POS, Y_MAX_POS) and (X_MAX_POS, Y_MAX_POS): draw_area_min/max as
    // settings.cpp reset() sets them; Z is the pen's axis as it is.
    const double left = p.x() - at(c, "X_MIN_POS"), right = at(c, "X_MAX_POS") - p.x();
    const double below = p.y() - at(c, "Y_MAX_POS");
    return {std::hypot(left, below), std::hypot(right, below), p.z()};
  }
  std::array<double, 3> positions{};
  const double nominal[3] = {210.0, 330.0, 90.0};
  for (int t = 0; t < 3; ++t) {
    const double angle = (nominal[t] + at(c, "DELTA_TOWER_ANGLE_TRIM", t)) * M_PI / 180.0;
    const double radius = at(c, "DELTA_RADIUS") + at(c, "DELTA_RADIUS_TRIM_TOWER", t);
    const double rod = at(c, "DELTA_DIAGONAL_ROD") + at(c, "DELTA_DIAGONAL_ROD_TRIM_TOWER", t);
    const double dx = std::cos(angle) * radius - p.x(), dy = std::sin(angle) * radius - p.y();
    positions[t] = p.z() + std::sqrt(rod * rod - (dx * dx + dy * dy));
  }
  return positions;
}

}  // namespace pkm::test::marlin_reference
