#include "pkm/machine/machine_parameters.hpp"

#include <memory>
#include <utility>

namespace pkm::machine {

Machine with_kinematics_parameters(const Machine& machine, std::span<const double> values) {
  std::unique_ptr<kinematics::Kinematics> kinematics = machine.kinematics().clone();
  kinematics->set_parameters(values);
  Machine out(machine.name(), machine.source(), machine.units(), std::move(kinematics),
              machine.joints(), machine.cartesian(), machine.home());
  out.set_tool(machine.tool());
  out.set_homing(machine.homing());
  out.set_controller(machine.controller());
  return out;
}

}  // namespace pkm::machine
