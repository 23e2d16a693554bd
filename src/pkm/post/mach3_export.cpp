#include "pkm/post/mach3_export.hpp"

#include <cctype>
#include <stdexcept>

namespace pkm::post {

std::vector<std::pair<char, std::string>> mach3_formulas(const machine::Machine& machine) {
  const kinematics::Kinematics& kinematics = machine.kinematics();
  const std::optional<std::vector<std::string>> mechanism = kinematics.joint_formulas();
  if (!mechanism) {
    throw std::invalid_argument("a " + std::string(kinematics.type()) +
                                " machine has no closed formula for Mach3's formula axes");
  }
  std::vector<std::string> expressions = *mechanism;
  // Pass-through joints (a matrix mill's A and C, a plotter's pen Z) follow the mechanism's.
  for (int joint = static_cast<int>(expressions.size()); joint < kinematics.joint_count();
       ++joint) {
    const int axis = kinematics.passthrough_axis(joint);
    if (axis < 0) throw std::logic_error("a joint of the mechanism has no formula");
    expressions.push_back(std::string(geometry::kAxisNames[axis]));
  }
  std::vector<std::pair<char, std::string>> formulas;
  for (std::size_t i = 0; i < expressions.size(); ++i) {
    formulas.emplace_back(static_cast<char>(std::tolower(machine.joints()[i].axis_letter)),
                          expressions[i]);
  }
  return formulas;
}

}  // namespace pkm::post
