// `pkm linuxcnc migrate`: a LinuxCNC configuration of genhexkins, lineardeltakins,
// rotarydeltakins or matrixkins, switched to pkmkins with the fewest edits. Every file of the
// configuration's directory is kept (HAL wiring, panels, remaps, tool tables); the INI's [KINS]
// KINEMATICS becomes pkmkins with the machine file (copied beside the INI); HAL lines that name
// the old module's pins (its geometry setp lines, its pins in nets) and motion.switchkins-type
// (pkmkins has one kinematics) are commented out or lose those pins; a HAL file from LinuxCNC's
// library that needs such an edit is copied into the directory first. docs/linuxcnc.md lists the
// edits.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "pkm/linuxcnc/config_export.hpp"
#include "pkm/linuxcnc/hal_file.hpp"

namespace pkm::linuxcnc {

// The modules a configuration is migrated from.
const std::vector<std::string>& migratable_kinematics();

struct MigrateOptions {
  std::filesystem::path hallib = kDefaultHallib;
  std::string machine_file_name;  // its name in the new directory: "hexapod.toml"
  std::string machine_text;       // copied as it is
  int machine_joints = 0;         // the machine file's joints: [KINS] JOINTS must agree
  std::string machine_units;      // "mm" or "inch": units= is added when the INI's differ
};

struct Migration {
  std::string module;              // the module migrated from: "genhexkins"
  std::string ini_name;            // the INI's name in the directory
  std::vector<ConfigFile> files;   // every file of the new directory, edited or as it was
  std::vector<std::string> edits;  // "hexapod.ini:71: KINEMATICS = genhexkins -> ..."
  std::vector<std::string> warnings;
};

// Reads the configuration (its INI's directory and the HAL files it names) and makes the
// migrated directory's files. Throws ConfigError (file:line) for a configuration whose module is
// not one of migratable_kinematics(), whose [KINS] JOINTS is not the machine file's number of
// joints, or whose HAL file names the old module's pins in a Tcl line the migration cannot edit.
Migration migrate_linuxcnc_config(const std::filesystem::path& ini_path,
                                  const MigrateOptions& options);

}  // namespace pkm::linuxcnc
