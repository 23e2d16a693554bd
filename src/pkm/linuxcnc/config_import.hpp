// `pkm import linuxcnc`: a pkmkit machine file from a LinuxCNC configuration (its INI and HAL
// files). The kinematics module of [KINS] KINEMATICS and its HAL pins give the model
// (genhexkins -> hexapod, lineardeltakins -> glide, rotarydeltakins -> rotary_delta,
// matrixkins and trivkins -> matrix); [JOINT_n] the joints and their limits; [TRAJ] and [AXIS_x]
// the Cartesian limits, the work envelope, the units and the home pose. docs/linuxcnc-import.md
// says what each module maps to and what is not imported.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "pkm/linuxcnc/hal_file.hpp"
#include "pkm/linuxcnc/ini_file.hpp"
#include "pkm/machine/imported_machine.hpp"

namespace pkm::linuxcnc {

// The kinematics modules the import understands.
const std::vector<std::string>& importable_kinematics();

using machine::ImportedJoint;

// Everything the machine file will say, in the configuration's own units (LINEAR_UNITS, deg):
// the INI's path as `source`, [EMC] MACHINE (else the INI's file name) as `name`, the joints'
// [JOINT_n] HOME as their homes; the warnings are limits that are placeholders (the same -M..M,
// M >= 1000 units, on every linear joint, or on X Y Z; docs/linuxcnc-import.md). Steps per unit
// are |STEP_SCALE|, else |SCALE| (stepconf's and pncconf's key for stepgen's position-scale);
// none where the config gives neither (a servo's INPUT_SCALE counts encoder lines, not steps).
struct ImportedConfig : machine::ImportedMachine {
  std::string module;  // "genhexkins"
};

struct ImportOptions {
  std::filesystem::path hallib = kDefaultHallib;
};

// Reads the configuration. Throws ConfigError (file:line[:key]) for a file that is missing, a
// value that is not a number, a kinematics module it cannot import (naming the supported ones),
// and geometry that is not a constant of the configuration.
ImportedConfig read_linuxcnc_config(const std::filesystem::path& ini_path,
                                    const ImportOptions& options = {});

// The machine file's text. The home pose is [TRAJ] HOME, else the joints' HOME through forward
// kinematics; the text is loaded back before it is returned, so a machine that pkmkit refuses
// (a home outside the joint limits) is a MachineFileError naming `output_name`'s line.
std::string machine_file_text(const ImportedConfig& config, const std::string& output_name);

}  // namespace pkm::linuxcnc
