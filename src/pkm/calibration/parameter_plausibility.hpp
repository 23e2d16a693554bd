// How far a built machine can plausibly be from its machine file at a parameter, by what the
// model says the parameter stands for in the hardware (Parameter::built_as): the yardstick a fit
// holds a poorly determined parameter with (its standard deviation beyond that deviation) and
// refuses a nonsense one with (fitted beyond three times it). The table is docs/calibration.md's.
#pragma once

#include <string>
#include <vector>

#include "pkm/kinematics/kinematics.hpp"

namespace pkm::calibration {

struct Plausibility {
  // What the parameter is, for messages ("a pulley's radius"); empty when the kind is unknown
  // (a formula's constants): such a parameter is judged by rank only.
  std::string kind;
  // How far the built machine plausibly is from the machine file's value, in the parameter's
  // unit; 0 when not judged.
  double deviation = 0.0;
  // How the deviation was made, for messages ("20 % of its nominal value", "2 mm + 2 % of the
  // machine's size of 2051 mm").
  std::string rule;
};

// A fitted value more than this many plausible deviations from nominal is nonsense: refused.
inline constexpr double kImplausibleDeviations = 3.0;

// The scale of frame positions and lengths: the larger of `extent_mm`, the size of what was
// measured (the diagonal of the measured positions' or marks' bounding box), and the largest
// length or coordinate of the machine file's geometry (a hexapod measured over 100 mm of its
// 600 mm frame).
double machine_size_mm(const std::vector<kinematics::Parameter>& parameters, double extent_mm);

// By what the model says the parameter stands for (Parameter::built_as); `size_mm` as
// machine_size_mm gives.
Plausibility parameter_plausibility(const kinematics::Parameter& parameter, double size_mm);

}  // namespace pkm::calibration
