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

namespace pkm::linuxcnc {

// The kinematics modules the import understands.
const std::vector<std::string>& importable_kinematics();

struct ImportedJoint {
  std::string name;
  bool angular = false;  // deg, else the config's length unit
  double min = 0.0, max = 0.0, max_velocity = 0.0, max_acceleration = 0.0;
  double home = 0.0;  // [JOINT_n] HOME
  // Steps per unit of a stepper joint: |STEP_SCALE|, else |SCALE| (stepconf's and pncconf's key
  // for stepgen's position-scale); none where the config gives neither (a servo's INPUT_SCALE
  // counts encoder lines, not steps).
  std::optional<double> steps_per_unit;
};

// Everything the machine file will say, in the configuration's own units (LINEAR_UNITS, deg).
struct ImportedConfig {
  std::string source;              // the INI's path
  std::string module;              // "genhexkins"
  std::string name;                // [EMC] MACHINE, else the INI's file name
  bool inch = false;               // [TRAJ] LINEAR_UNITS
  std::string kinematics_section;  // "[kinematics]\ntype = ...", lengths in the config's unit
  int pose_size = 3;               // coordinates of home: 3 (x y z) or 6 (x y z a b c)
  std::vector<ImportedJoint> joints;
  double max_feed_per_min = 0.0;
  double max_acceleration = 0.0;
  std::optional<std::vector<double>> home;                        // [TRAJ] HOME, pose_size values
  std::optional<std::vector<double>> envelope_min, envelope_max;  // [AXIS_x] limits
  std::vector<std::string> notes;  // decisions and what was not imported, for the file's header
  // What the user must act on (also among the notes): limits that are placeholders (the same
  // -M..M, M >= 1000 units, on every linear joint, or on X Y Z; docs/linuxcnc-import.md).
  std::vector<std::string> warnings;
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
