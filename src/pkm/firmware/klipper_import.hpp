// `pkm import klipper`: a printer.cfg with `[printer] kinematics: delta` or `winch` as the machine
// it describes (docs/firmware-klipper.md); rotary_delta and deltesian are refused with the reason.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "pkm/firmware/klipper_cfg.hpp"

#include "pkm/machine/imported_machine.hpp"

namespace pkm::firmware {

// Throws FirmwareFileError ("file:line: [section] key: why") for a missing or bad setting or a
// kinematics pkmkit cannot hold as Klipper means it.
machine::ImportedMachine read_klipper(std::string_view text, const std::string& source);

// A stepper section's steps per mm: full_steps_per_rotation (200) x microsteps x gear_ratio over
// rotation_distance (or older Klipper's 1 / step_distance); none, with a note, when
// rotation_distance or microsteps is missing.
std::optional<double> klipper_steps_per_mm(KlipperConfig& config, const std::string& section,
                                           std::vector<std::string>& notes);

}  // namespace pkm::firmware
