// The marlin target (docs/firmware-marlin.md): under construction.
#pragma once

#include "pkm/firmware/target.hpp"

namespace pkm::firmware {

Target marlin_target();

}  // namespace pkm::firmware
