// The klipper target (docs/firmware-klipper.md): a linear delta as the printer.cfg settings of
// Klipper's `kinematics: delta` ([printer] delta_radius, print_radius, minimum_z_position and the
// speeds; [stepper_a..c] angle, arm_length, position_endstop and the steps), and such a
// printer.cfg read back; a cable robot as `kinematics: winch` (klipper_winch.hpp). Klipper's
// rotary_delta and deltesian are refused: the first would shift the machine's frame by the shoulder
// height, pkmkit has no form for the second.
#pragma once

#include <string>
#include <vector>

#include "pkm/firmware/target.hpp"

namespace pkm::firmware {

Target klipper_target();

// A number as the klipper target writes it: the fewest decimals (up to 12) that read back within
// 1e-9 of `value`, so that import then export gives the same text.
std::string klipper_number(double value);

// A stepper section's rotation_distance, microsteps and full_steps_per_rotation for `joint`'s
// steps_per_unit (200 full steps at 16 microsteps); a commented line and a warning naming
// `section` where the machine file gives none.
std::string klipper_steps(const machine::JointSpec& joint, const std::string& section,
                          std::vector<std::string>& warnings);

}  // namespace pkm::firmware
