#include "maslow.hpp"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace pkm::test::maslow_reference {

Frame read_frame(const std::string& yaml) {
  Frame frame;
  std::istringstream lines(yaml);
  std::string line;
  bool inside = false;
  int found = 0;
  const std::string corner_names[4] = {"tl", "tr", "bl", "br"};
  while (std::getline(lines, line)) {
    if (line.find("MaslowKinematics:") != std::string::npos) {
      inside = true;
      continue;
    }
    if (!inside) continue;
    if (line.rfind("    ", 0) != 0) break;
    const auto colon = line.find(':');
    const std::string key = line.substr(4, colon - 4);
    const double value = std::stod(line.substr(colon + 1));
    ++found;
    if (key == "beltEndExtension") frame.belt_end_extension = value;
    if (key == "armLength") frame.arm_length = value;
    for (int k = 0; k < 4; ++k) {
      if (key == corner_names[k] + "X") frame.x[k] = value;
      if (key == corner_names[k] + "Y") frame.y[k] = value;
      if (key == corner_names[k] + "Z") frame.z[k] = value;
    }
  }
  if (found != 14) throw std::runtime_error("MaslowKinematics: expected 14 keys");
  // Maslow's slopes form: A the tr-bl diagonal, B the br-tl one.
  const double a = (frame.y[1] - frame.y[2]) / (frame.x[1] - frame.x[2]);
  const double b = (frame.y[3] - frame.y[0]) / (frame.x[3] - frame.x[0]);
  frame.centre_x = (frame.y[3] - b * frame.x[3] + a * frame.x[1] - frame.y[1]) / (a - b);
  frame.centre_y = a * (frame.centre_x - frame.x[1]) + frame.y[1];
  return frame;
}

std::array<double, 4> belts(const Frame& frame, double x, double y, double z) {
  std::array<double, 4> lengths{};
  for (int k = 0; k < 4; ++k) {
    const double dx = frame.x[k] - (x + frame.centre_x);
    const double dy = frame.y[k] - (y + frame.centre_y);
    const double dz = -(z + frame.z[k]);
    const double plan =
        std::sqrt(dx * dx + dy * dy) - (frame.belt_end_extension + frame.arm_length);
    lengths[k] = std::sqrt(plan * plan + dz * dz);
  }
  return lengths;
}

}  // namespace pkm::test::maslow_reference
