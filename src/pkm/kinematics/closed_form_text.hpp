// The pieces of the closed formulas models give in Kinematics::joint_formulas() (muParser's
// syntax, what Mach3's formula axes take): numbers as plain decimals, coordinates shifted by a
// constant.
#pragma once

#include <string>

namespace pkm::kinematics {

// The shortest plain decimal that reads back as the same double (no exponent: a formula parser
// may not take one).
std::string plain_decimal(double value);

// "(x + 12.5)" or "(x - 3)" or "x": coordinate `axis` shifted by `offset`.
std::string shifted_coordinate(const char* axis, double offset);

}  // namespace pkm::kinematics
