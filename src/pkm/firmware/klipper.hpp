// The klipper target (docs/firmware-klipper.md): a linear delta as the printer.cfg settings of
// Klipper's `kinematics: delta` ([printer] delta_radius, print_radius, minimum_z_position and the
// speeds; [stepper_a..c] angle, arm_length, position_endstop and the steps), and such a
// printer.cfg read back. Klipper's rotary_delta and deltesian are refused: the first would shift
// the machine's frame by the shoulder height, pkmkit has no form for the second.
#pragma once

#include <string>

#include "pkm/firmware/target.hpp"

namespace pkm::firmware {

Target klipper_target();

// A number as the klipper target writes it: the fewest decimals (up to 12) that read back within
// 1e-9 of `value`, so that import then export gives the same text.
std::string klipper_number(double value);

}  // namespace pkm::firmware
