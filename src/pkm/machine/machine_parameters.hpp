// A machine with another geometry: its kinematic model's parameters changed the way calibration
// changes them (Kinematics::set_parameters), for studies that vary a geometry without writing
// machine files (the Python module's Machine.with_parameters).
#pragma once

#include <span>

#include "pkm/machine/machine.hpp"

namespace pkm::machine {

// `machine` with its model's parameters set to `values` (the order and units of
// Kinematics::parameters()), made again from its parts so that what a machine derives from its
// geometry when made (home's assembly mode, the model's home) is the new geometry's. Throws
// std::invalid_argument for an impossible geometry (set_parameters refuses it).
Machine with_kinematics_parameters(const Machine& machine, std::span<const double> values);

}  // namespace pkm::machine
