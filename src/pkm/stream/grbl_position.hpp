// Where the tool is by grbl's word: the position of its X Y Z axes in the program's coordinates
// (a status report's work position: MPos less the offset of G10 L20 or G92) as the machine's
// joints, and through the machine's forward kinematics as the tool's pose.
#pragma once

#include <array>
#include <optional>

#include "pkm/machine/machine.hpp"

namespace pkm::stream {

// grbl's axis of a joint, 0 1 2 for X Y Z. Throws std::invalid_argument for another letter
// (grbl has three axes).
int grbl_axis(const machine::JointSpec& joint);

// The joints (mm or rad inside) of grbl's axis values (mm or deg: X Y Z in that order), each
// joint read from the axis its letter names. Throws std::invalid_argument for a letter other
// than X Y Z.
kinematics::JointVector joints_from_axes(const machine::Machine& machine,
                                         const std::array<double, 3>& axes);

// The tool's pose for grbl's axis values, seeded with `seed` (the last pose known, or home);
// nullopt where forward kinematics refuses the joints (past a limit, no assembly).
std::optional<geometry::Pose> tool_pose(const machine::Machine& machine,
                                        const std::array<double, 3>& axes,
                                        const geometry::Pose& seed);

}  // namespace pkm::stream
