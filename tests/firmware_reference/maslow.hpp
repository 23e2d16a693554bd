// Maslow 4's belt lengths rewritten from its firmware's source (MaslowCNC/Maslow_4,
// FluidNC/src/Kinematics/MaslowKinematics.cpp: calculateCenter, computeTL..computeBR), with a
// parser of its own for the `kinematics: MaslowKinematics:` keys: what the firmware would command
// for an exported maslow.yaml.
#pragma once

#include <array>
#include <string>

namespace pkm::test::maslow_reference {

struct Frame {
  std::array<double, 4> x{}, y{}, z{};  // tl, tr, bl, br: the keys as written
  double belt_end_extension = 0.0, arm_length = 0.0;
  double centre_x = 0.0, centre_y = 0.0;  // the diagonals' crossing
};

Frame read_frame(const std::string& yaml);
// Belt lengths (mm) for the router at Maslow's x y z (from the centre).
std::array<double, 4> belts(const Frame& frame, double x, double y, double z);
// The same in single precision throughout, as the firmware computes them (its keys, centre and
// router position are floats): what the firmware's own rounding adds.
std::array<double, 4> belts_float(const Frame& frame, double x, double y, double z);

}  // namespace pkm::test::maslow_reference
