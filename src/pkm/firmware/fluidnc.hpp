// The fluidnc target (docs/firmware-fluidnc.md): under construction.
#pragma once

#include "pkm/firmware/target.hpp"

namespace pkm::firmware {

Target fluidnc_target();

}  // namespace pkm::firmware
