// `pkm import klipper`: a printer.cfg with `[printer] kinematics: delta` as the machine it
// describes (docs/firmware-klipper.md); rotary_delta and deltesian are refused with the reason.
#pragma once

#include <string>
#include <string_view>

#include "pkm/machine/imported_machine.hpp"

namespace pkm::firmware {

// Throws FirmwareFileError ("file:line: [section] key: why") for a missing or bad setting or a
// kinematics pkmkit cannot hold as Klipper means it.
machine::ImportedMachine read_klipper(std::string_view text, const std::string& source);

}  // namespace pkm::firmware
