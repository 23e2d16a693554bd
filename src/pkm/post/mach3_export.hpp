// The Mach3 "formula axis correction" equations of a machine whose inverse kinematics is a closed
// formula, numbers filled in, as the Mach3 source document typed them by hand:
// f(a) = sqrt((x^2) + (y^2)). Each model gives its own (Kinematics::joint_formulas); here they
// are named by their joints' axis letters, the pass-through joints after them.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "pkm/machine/machine.hpp"

namespace pkm::post {

// One (axis letter, expression) per joint, in joint order. Throws std::invalid_argument for
// models with no closed formula in x y z (hexapods, glides that turn their platform).
std::vector<std::pair<char, std::string>> mach3_formulas(const machine::Machine& machine);

}  // namespace pkm::post
