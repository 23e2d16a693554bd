// The rrf target (docs/firmware-rrf.md): under construction.
#pragma once

#include "pkm/firmware/target.hpp"

namespace pkm::firmware {

Target rrf_target();

}  // namespace pkm::firmware
