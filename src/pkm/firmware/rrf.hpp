// The rrf target (docs/firmware-rrf.md): RepRapFirmware's config.g lines for a linear delta
// (M669 K3, M665, M666; rrf.cpp, rrf_delta.cpp), a rotary delta (M669 K10, M666;
// rrf_rotary.cpp) or a Hangprinter (M669 K6, M666's spools and flex; rrf_hangprinter.cpp), with
// M92, M203, M201 and M208, and the reader of a config.g (rrf_config.cpp).
#pragma once

#include "pkm/firmware/target.hpp"

namespace pkm::firmware {

Target rrf_target();

}  // namespace pkm::firmware
