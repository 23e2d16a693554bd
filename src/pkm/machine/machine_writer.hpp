// Writing machine files back: a calibrated geometry replaces the [kinematics] section, everything
// else in the file (comments, joints, Cartesian limits) stays as the user wrote it.
#pragma once

#include <string>

#include "pkm/machine/machine.hpp"

namespace pkm::machine {

// A number as machine files write it: its shortest form that reads back exactly, always
// recognisable as a TOML float ("270.0", "1e-06").
std::string toml_number(double value);
// A TOML basic string, quoted and escaped.
std::string toml_string(const std::string& text);

// The [kinematics] section (with its sub-tables) describing the model's current geometry, lengths
// in `units`. Numbers are written in their shortest form that reads back exactly.
std::string kinematics_toml(const kinematics::Kinematics& kinematics, LengthUnit units);

// `original_text` (the machine file `source_name`) with its [kinematics] section replaced by
// kinematics_toml(kinematics, units). Throws MachineFileError when the file does not define
// [kinematics] as a table header of its own.
std::string replace_kinematics_section(const std::string& original_text,
                                       const std::string& source_name,
                                       const kinematics::Kinematics& kinematics, LengthUnit units);

}  // namespace pkm::machine
