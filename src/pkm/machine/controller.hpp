// The controller a machine runs on, when it is one without kinematics that pkmkit streams joint
// programs to (the machine file's [controller] table, docs/grbl.md): what its planner and its
// serial line can do, which decides how post chooses its blocks and how long a program takes.
#pragma once

#include <string>

namespace pkm {

enum class ControllerKind { grbl, grblhal };

struct ControllerSettings {
  ControllerKind kind = ControllerKind::grbl;
  int planner_blocks = 16;           // blocks grbl plans ahead (grblHAL: 35)
  int rx_buffer_bytes = 128;         // the serial receive buffer the sender counts characters into
  int baud = 115200;                 // serial line speed, bit/s (10 bits per character: 8N1)
  double junction_deviation = 0.01;  // mm (machine file's length unit in the file, mm inside)
};

// "grbl" or "grblhal".
inline const char* controller_kind_name(ControllerKind kind) {
  return kind == ControllerKind::grblhal ? "grblhal" : "grbl";
}

}  // namespace pkm
