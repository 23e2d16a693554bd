// RepRapFirmware's Hangprinter kinematics (M669 K6, its HangprinterKinematics;
// docs/firmware-rrf.md), the rrf target's cable robot: M669 A B C D (and N5 I) anchors, each a
// line's pivot on the frame less its tie point on the effector (mm); M666 Q0 F0 (no spool
// buildup, no flex compensation). RRF's motor position for a line is its length less its length
// at x = y = z = 0, where RRF starts and where homeall.g sets the position.
#pragma once

#include <string>
#include <vector>

#include "pkm/firmware/rrf_config.hpp"
#include "pkm/firmware/target.hpp"

namespace pkm::firmware {

// The config.g lines of a spatial cable robot of 4 or 5 cables whose home is x = y = z = 0;
// ExportRefused for anything else, saying why.
ExportedFile write_rrf_hangprinter(const FirmwareMachine& machine, const ExportContext& context);

// Whether config.g selects the Hangprinter (an M669 with K6).
bool rrf_is_hangprinter(const std::vector<RrfCommand>& commands);

// The machine of config.g's Hangprinter lines. Throws FirmwareFileError ("file:line: key: why")
// for a missing anchor, a value that is not a number, or what pkmkit's cable robot cannot hold:
// flex compensation (M666 F1, F2).
machine::ImportedMachine read_rrf_hangprinter(const std::vector<RrfCommand>& commands,
                                              const std::string& source);

}  // namespace pkm::firmware
