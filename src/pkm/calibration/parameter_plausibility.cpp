#include "pkm/calibration/parameter_plausibility.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>

namespace pkm::calibration {

namespace {

// Frame points, link lengths and joint zeros are built and measured to about the same share of
// the machine's size: a tape over the frame, a leg cut to length, a cable marked at its zero.
Plausibility size_relative(std::string kind, double size_mm) {
  return {std::move(kind), 2.0 + 0.02 * size_mm,
          "2 mm + 2 % of the machine's size of " + std::to_string(std::lround(size_mm)) + " mm"};
}

// A catalogue part (a pulley) or a weighed or looked-up property is known as a share of itself.
Plausibility value_relative(std::string kind, const kinematics::Parameter& parameter,
                            double share) {
  return {std::move(kind), share * std::abs(parameter.value),
          std::to_string(static_cast<int>(std::lround(100.0 * share))) + " % of its nominal value"};
}

Plausibility absolute(std::string kind, double deviation) {
  std::array<char, 32> text{};
  std::snprintf(text.data(), text.size(), "%g", deviation);
  return {std::move(kind), deviation, text.data()};
}

}  // namespace

double machine_size_mm(const std::vector<kinematics::Parameter>& parameters, double extent_mm) {
  double size = extent_mm;
  for (const kinematics::Parameter& p : parameters) {
    if (p.unit == "mm") size = std::max(size, std::abs(p.value));
  }
  return size;
}

Plausibility parameter_plausibility(const kinematics::Parameter& parameter, double size_mm) {
  const kinematics::BuiltAs& built = parameter.built_as;
  std::string kind(built.what);
  Plausibility result;
  switch (built.tolerance) {
    case kinematics::BuiltTolerance::none:
      break;
    case kinematics::BuiltTolerance::machine_size:
      result = size_relative(std::move(kind), size_mm);
      break;
    case kinematics::BuiltTolerance::own_value:
      result = value_relative(std::move(kind), parameter, built.amount);
      break;
    case kinematics::BuiltTolerance::absolute:
      result = absolute(std::move(kind), built.amount);
      break;
  }
  // A share of a nominal 0 (a cable without mass) judges nothing: such a parameter is held as
  // having no effect anyway.
  if (!(result.deviation > 0.0)) return {};
  return result;
}

}  // namespace pkm::calibration
