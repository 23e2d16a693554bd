// A LinuxCNC 2.9 configuration for a pkmkit machine, running the pkmkins kinematics module: the
// INI ([KINS], [TRAJ], [JOINT_n] from the machine file's joints, [AXIS_x] from its work envelope
// and the joint-rate bound), the HAL files (motion and the servo thread; sim.hal loops every
// joint's command back to its feedback, or hardware.hal names the pins to wire), the machine
// file itself beside the INI; and writing them as one directory, or over an existing one as one
// swap.
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
  bounds::JointRateOptions bound_options;
};

struct ConfigFile {
  std::string name;  // within the directory
  std::string text;
  // What is not the export's once written: LinuxCNC's own state, which it rewrites as it runs
  // (the tool table, the parameter file with the work offsets), and hardware.hal, which the user
  // wires. Written only where the directory has none yet.
  bool keep_existing = false;
};

struct LinuxcncConfig {
  std::string ini_name;
  std::vector<ConfigFile> files;
  bounds::EnvelopeBox requested;  // the file's envelope, or the reach box
  bounds::EnvelopeBox
      envelope;  // the axis limits written: requested, shrunk about home by `shrink`
  double shrink = 1.0;
  bounds::JointRateBound bound;
  AxisRateLimits limits;
  geometry::Dof moved;            // the coordinates LinuxCNC moves ([TRAJ] COORDINATES)
  double bound_seconds = 0;       // wall time of the joint-rate bound
  std::vector<std::string> cost;  // what the bound costs, one line per axis (terminal and INI)
};

// Throws std::runtime_error (no finite reach, a singularity in the envelope, home unreachable).
LinuxcncConfig make_linuxcnc_config(const machine::Machine& machine, const ExportOptions& options);

// What writing over an existing configuration (`force`) kept of it.
struct KeptFiles {
  std::vector<std::string> state;   // files marked keep_existing that it had (kept as they were)
  std::vector<std::string> others;  // files the configuration does not write (the user's own)
};

// Writes the files as one directory: built beside `directory` under a temporary name and renamed
// into place, so that a failed run leaves nothing (missing parent directories are created, as
// mkdir -p). A directory that exists and holds anything is refused unless `force`; then the new
// directory is built beside it with its state files and the user's files carried over (hard
// links, or copies where the file system has none), and swapped with it in one step
// (TemporaryTree::replace): a failure or a signal leaves the old configuration as it was, never
// new files beside old ones. A user's file or directory where the configuration writes a
// directory or file of the same name is refused, naming it.
// Throws std::runtime_error naming the path and the system's reason.
KeptFiles write_config_directory(const std::filesystem::path& directory,
                                 const LinuxcncConfig& config, bool force);
// The same for any files (names may hold subdirectories: "remap_subs/428remap.ngc").
KeptFiles write_config_directory(const std::filesystem::path& directory,
                                 const std::vector<ConfigFile>& files, bool force);

}  // namespace pkm::linuxcnc
