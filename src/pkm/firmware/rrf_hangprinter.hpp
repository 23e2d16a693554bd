// RepRapFirmware's Hangprinter kinematics (M669 K6, its HangprinterKinematics;
// docs/firmware-rrf.md), the rrf target's cable robot: M669 A B C D (and N5 I) anchors, each a
// line's pivot on the frame less its tie point on the effector (mm); M666 Q R U O L H J, the
// spools (Q0 without); M666 F1 W S I X Y, flex compensation (F0 without). RRF's motor position for
// a line is its line position (its length, less the stretch with flex, less its length at x = y =
// z = 0, where RRF starts and homeall.g sets the position) through the spool model.
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
// for a missing anchor, a value that is not a number, an M666 array without one value per anchor,
// or what pkmkit's cable robot cannot hold: M666 F2, B1, P1, per-line planned force limits.
machine::ImportedMachine read_rrf_hangprinter(const std::vector<RrfCommand>& commands,
                                              const std::string& source);

}  // namespace pkm::firmware
