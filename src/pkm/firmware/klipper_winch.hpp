// Klipper's cable winch kinematics (klippy/kinematics/winch.py, klippy/chelper/kin_winch.c), the
// klipper target's cable robot (docs/firmware-klipper.md): [stepper_a] .. [stepper_z] each with
// its anchor_x, anchor_y, anchor_z (mm); a stepper's coordinate is its line's length, the
// distance from its anchor to the tool. Klipper does not home a winch: it takes the tool at
// x = y = z = 0 at start and after G28.
#pragma once

#include <string>

#include "pkm/firmware/klipper_cfg.hpp"
#include "pkm/firmware/target.hpp"

namespace pkm::firmware {

// The [printer] and [stepper_*] sections of a spatial cable robot whose home is x = y = z = 0;
// ExportRefused for a planar one, a pass-through joint, more than 26 cables or a home elsewhere.
ExportedFile write_klipper_winch(const FirmwareMachine& firmware, const ExportContext& context);

// A printer.cfg with `kinematics: winch` as the machine it describes; FirmwareFileError
// ("file:line: [section] key: why") for a missing or bad setting.
machine::ImportedMachine read_klipper_winch(KlipperConfig& config, const std::string& source);

}  // namespace pkm::firmware
