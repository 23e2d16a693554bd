// The rrf target (docs/firmware-rrf.md): RepRapFirmware's config.g lines for a linear delta
// (M669 K3, M665, M666; rrf.cpp, rrf_delta.cpp) or a rotary delta (M669 K10, M666;
// rrf_rotary.cpp), with M92, M203, M201 and M208, and the reader of a config.g (rrf_config.cpp).
#pragma once

#include "pkm/firmware/target.hpp"

namespace pkm::firmware {

Target rrf_target();

}  // namespace pkm::firmware
