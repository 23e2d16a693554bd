// The klipper target (docs/firmware-klipper.md): under construction.
#pragma once

#include "pkm/firmware/target.hpp"

namespace pkm::firmware {

Target klipper_target();

}  // namespace pkm::firmware
