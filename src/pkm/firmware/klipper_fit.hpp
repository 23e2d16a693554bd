// The nearest delta Klipper can hold to a linear delta whose towers are not on one circle about
// the origin (docs/firmware-klipper.md): one delta_radius, each tower's angle, rod and carriage
// offset fitted to the machine's joints over its workspace, with the tool error that costs.
#pragma once

#include "pkm/firmware/firmware_machine.hpp"

namespace pkm::firmware {

// `exact` must hold a linear delta form. The result's machine is the fitted form's (the joints,
// limits and home of `exact`), its cost measured as firmware_machine's approximations are: the
// form's joints for each workspace pose, driven through `exact`'s own forward kinematics.
// Throws ExportRefused when the workspace has too few poses or the fit leaves the form.
FirmwareMachine klipper_nearest_delta(const FirmwareMachine& exact);

}  // namespace pkm::firmware
