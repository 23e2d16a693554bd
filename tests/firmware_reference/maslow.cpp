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

std::array<double, 4> belts_float(const Frame& frame, double x, double y, double z) {
  std::array<float, 4> fx{}, fy{};
  for (int k = 0; k < 4; ++k) {
    fx[k] = static_cast<float>(frame.x[k]);
    fy[k] = static_cast<float>(frame.y[k]);
  }
  const float a = (fy[1] - fy[2]) / (fx[1] - fx[2]);
  const float b = (fy[3] - fy[0]) / (fx[3] - fx[0]);
  const float centre_x = (fy[3] - b * fx[3] + a * fx[1] - fy[1]) / (a - b);
  const float centre_y = a * (centre_x - fx[1]) + fy[1];
  // Maslow's x y are from its own (float) centre: the router's place in the frame is the same.
  const float px = static_cast<float>(x + frame.centre_x) - centre_x;
  const float py = static_cast<float>(y + frame.centre_y) - centre_y;
  const float pz = static_cast<float>(z);
  const float extension =
      static_cast<float>(frame.belt_end_extension) + static_cast<float>(frame.arm_length);
  std::array<double, 4> lengths{};
  for (int k = 0; k < 4; ++k) {
    const float dx = fx[k] - (px + centre_x);
    const float dy = fy[k] - (py + centre_y);
    const float dz = 0.0f - (pz + static_cast<float>(frame.z[k]));
    const float plan = std::sqrt(dx * dx + dy * dy) - extension;
    lengths[k] = std::sqrt(plan * plan + dz * dz);
  }
  return lengths;
}

}  // namespace pkm::test::maslow_reference
