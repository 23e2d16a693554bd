// The marlin target (docs/firmware-marlin.md): the Configuration.h defines of Marlin's DELTA and
// POLARGRAPH kinematics (with M665/M666 for a delta), written from a machine and read back.
#pragma once

#include "pkm/firmware/target.hpp"

namespace pkm::firmware {

Target marlin_target();

}  // namespace pkm::firmware
