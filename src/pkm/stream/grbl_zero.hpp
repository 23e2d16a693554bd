// The line that zeroes a grbl-class controller at known joint values: how `pkm stream --dry-run`
// puts grbl-sim, which starts at step 0, at the machine's home. The `$` settings it sends first
// are `pkm export grbl`'s (post/grbl_settings.hpp).
#pragma once

#include <string>

#include "pkm/machine/machine.hpp"

namespace pkm::stream {

// "G10 L20 P1 X1000.000 Y1204.159": grbl's work coordinates (G54) set so that where it stands
// reads as `joints` (mm or rad inside), how a machine without switches is zeroed at a known pose.
// grbl's machine position (MPos, its step counts) stays where it was.
std::string grbl_zero_line(const Machine& machine, const JointVector& joints);

}  // namespace pkm::stream
