// The grblhal target (docs/firmware-grblhal.md): under construction.
#pragma once

#include "pkm/firmware/target.hpp"

namespace pkm::firmware {

Target grblhal_target();

}  // namespace pkm::firmware
