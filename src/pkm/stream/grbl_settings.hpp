// The `$` settings that make grbl move a machine's joints as the machine file says: steps per
// unit ($100..$102), max rate ($110..$112, per minute), acceleration ($120..$122, per second
// squared) of the axis each joint is written as, and the junction deviation ($11) of the
// [controller] table. `pkm stream --dry-run` sends them to grbl-sim before the program; `pkm
// export grbl` can print the same lines.
#pragma once

#include <string>
#include <vector>

#include "pkm/machine/machine.hpp"

namespace pkm::stream {

struct GrblSetting {
  std::string line;     // "$100=80.000"
  std::string comment;  // "left: steps per mm"
};

// One setting per joint and quantity, in grbl's units (mm or deg). A joint without
// steps_per_unit gets no $10x line (grbl keeps what it has). Throws std::invalid_argument when a
// joint's axis letter is not X, Y or Z (grbl's three axes).
std::vector<GrblSetting> grbl_settings(const Machine& machine);

// "G10 L20 P1 X1000.00000 Y1204.15946": grbl's work coordinates (G54) set so that where it
// stands reads as `joints` (mm or rad inside), how a machine without switches is zeroed at a
// known pose. grbl's machine position (MPos, its step counts) stays where it was.
std::string grbl_zero_line(const Machine& machine, const JointVector& joints);

}  // namespace pkm::stream
