// A machine read from another tool's configuration (`pkm import linuxcnc`, `pkm import fluidnc`,
// ...), in that configuration's own units, and the machine file that says it.
#pragma once

#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace pkm::machine {

struct ImportedJoint {
  std::string name;
  bool angular = false;  // deg, else the configuration's length unit
  double min = 0.0, max = 0.0, max_velocity = 0.0, max_acceleration = 0.0;
  double home = 0.0;  // where the joint homes: the pose at home, when `home` below is not given
  // Steps per unit of a stepper joint; none where the configuration does not say.
  std::optional<double> steps_per_unit;
};

// Everything the machine file will say, in the configuration's own units (mm or inch, deg).
struct ImportedMachine {
  std::string source;  // the configuration's path
  std::string origin;  // the file's first comment: "Imported by `pkm import ...` ..."
  std::string name;
  bool inch = false;
  std::string kinematics_section;  // "[kinematics]\ntype = ...", lengths in the unit above
  int pose_size = 3;               // coordinates of home: 3 (x y z) or 6 (x y z a b c)
  std::vector<ImportedJoint> joints;
  double max_feed_per_min = 0.0;
  double max_acceleration = 0.0;
  std::optional<std::vector<double>> home;                        // pose_size values
  std::optional<std::vector<double>> envelope_min, envelope_max;  // the work envelope
  double home_seed_z = 0.0;  // where forward kinematics of the joints' homes starts (unit above)
  std::vector<std::string> notes;     // decisions and what was not imported, for the file's header
  std::vector<std::string> warnings;  // what the user must act on (also among the notes)
};

// Why an imported machine has no machine file: the joints' homes give no pose, or pkmkit
// refuses the machine (its message, naming the output's line).
class ImportedMachineError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The machine file's text. The home pose is `home`, else the joints' homes through forward
// kinematics; the text is loaded back before it is returned (as `output_name`).
std::string machine_file_text(const ImportedMachine& imported, const std::string& output_name);

}  // namespace pkm::machine
