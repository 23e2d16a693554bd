// A LinuxCNC 2.9 configuration for a pkmkit machine, running the pkmkins kinematics module: the
// INI ([KINS], [TRAJ], [JOINT_n] from the machine file's joints, [AXIS_x] from its work envelope
// and the joint-rate bound), the HAL files (motion and the servo thread; sim.hal loops every
// joint's command back to its feedback, or hardware.hal names the pins to wire), the machine
// file itself beside the INI; and writing them as one directory.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "pkm/linuxcnc/joint_rate_bound.hpp"
#include "pkm/machine/machine.hpp"

namespace pkm::linuxcnc {

struct ExportOptions {
  bool sim = false;               // sim.hal (loopback) instead of hardware.hal
  std::string machine_file_name;  // the machine file's name in the directory: "delta.toml"
  std::string machine_text;       // its text, copied as it is
  JointRateOptions bound_options;
};

struct ConfigFile {
  std::string name;  // within the directory
  std::string text;
};

struct LinuxcncConfig {
  std::string ini_name;
  std::vector<ConfigFile> files;
  EnvelopeBox requested;  // the file's envelope, or the reach box
  EnvelopeBox envelope;   // the axis limits written: requested, shrunk about home by `shrink`
  double shrink = 1.0;
  JointRateBound bound;
  AxisRateLimits limits;
  Dof moved;                      // the coordinates LinuxCNC moves ([TRAJ] COORDINATES)
  double bound_seconds = 0;       // wall time of the joint-rate bound
  std::vector<std::string> cost;  // what the bound costs, one line per axis (terminal and INI)
};

// Throws std::runtime_error (no finite reach, a singularity in the envelope, home unreachable).
LinuxcncConfig make_linuxcnc_config(const Machine& machine, const ExportOptions& options);

// Writes the files as one directory: built beside `directory` under a temporary name and renamed
// into place, so that a failed run leaves nothing (missing parent directories are created, as
// mkdir -p). A directory that exists and holds anything is
// refused unless `force`; then each file is replaced on its own (atomically), others are left.
// Throws std::runtime_error naming the path and the system's reason.
void write_config_directory(const std::filesystem::path& directory, const LinuxcncConfig& config,
                            bool force);
// The same for any files (names may hold subdirectories: "remap_subs/428remap.ngc").
void write_config_directory(const std::filesystem::path& directory,
                            const std::vector<ConfigFile>& files, bool force);

}  // namespace pkm::linuxcnc
