// The controller a machine runs on, when it is one without kinematics that pkmkit streams joint
// programs to (the machine file's [controller] table, docs/machine-file.md, docs/grbl.md): what its
// planner and its serial line can do, which decides how post chooses its blocks and how long a
// program takes; and the parser of that table.
#pragma once

#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace pkm::kinematics {
class ModelConfig;
}  // namespace pkm::kinematics

namespace pkm::machine {

struct JointSpec;

enum class ControllerKind { grbl, grblhal };

struct ControllerSettings {
  ControllerKind kind = ControllerKind::grbl;
  int axes = 3;  // axes the firmware is built with (grbl 1.1: 3; grblHAL 3..8)
  // The planner's buffer in blocks: grbl 1.1 BLOCK_BUFFER_SIZE 16, a ring that holds 15 (its $I
  // reports 15); grblHAL 35 here, its $398 (100 by default since December 2023), all usable.
  int planner_blocks = 16;
  // The serial receive buffer the sender counts characters into: grbl 128 (RX_BUFFER_SIZE, all
  // usable), grblHAL 1024.
  int rx_buffer_bytes = 128;
  int baud = 115200;                 // serial line speed, bit/s (10 bits per character: 8N1)
  double junction_deviation = 0.01;  // mm (machine file's length unit in the file, mm inside)
};

// "grbl" or "grblhal".
inline const char* controller_kind_name(ControllerKind kind) {
  return kind == ControllerKind::grblhal ? "grblhal" : "grbl";
}

// The axis letters of a controller built with `axes` axes, in its own order (the order of its
// $100.. settings): grbl X Y Z; grblHAL X Y Z A B C U V (its default letters, without the
// build option that renames A B C to U V W).
std::string_view controller_axis_letters(ControllerKind kind, int axes);

// The [controller] table: `controller` is its section, `joint_tables` the [[joints]] tables of
// `joints` (for errors located at a joint). Throws MachineFileError (file:line:key) for an unknown
// kind, an impossible number, a joint without steps_per_unit, more joints than the controller
// has axes, or a joint on a letter it lacks.
ControllerSettings read_controller_table(
    const kinematics::ModelConfig& controller, const std::vector<JointSpec>& joints,
    const std::vector<std::unique_ptr<kinematics::ModelConfig>>& joint_tables);

}  // namespace pkm::machine
