// The nearest delta whose towers stand on one circle about the origin, as Klipper's delta (one
// delta_radius) and RepRapFirmware's (M665 R) hold them, to a linear delta whose towers do not
// (docs/firmware.md): one radius, each tower's angle, rod and carriage offset fitted to the
// machine's joints over its workspace, with the tool error that costs.
#pragma once

#include <string>

#include "pkm/firmware/firmware_machine.hpp"

namespace pkm::firmware {

// Columns whose distances from the origin differ by more than this (mm) are not on one circle.
inline constexpr double kOneCircleTolerance_mm = 1e-6;

// Whether every tower's column is within kOneCircleTolerance_mm of one radius about the origin.
bool towers_on_one_circle(const kinematics::LinearDeltaForm& form);

// `exact` must hold a linear delta form (exactly, or an approximation: the cost is measured on
// the machine as built). The result's machine is the fitted form's (the joints, limits and home
// of `exact`), its cost measured as firmware_machine's approximations are
// (approximation_cost), its losses `exact`'s and "the towers' columns at different radii ...
// (`setting`)". Throws ExportRefused when the workspace has too few poses.
FirmwareMachine nearest_delta_on_one_circle(const FirmwareMachine& exact,
                                            const std::string& setting);

}  // namespace pkm::firmware
