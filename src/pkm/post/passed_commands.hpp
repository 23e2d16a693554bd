// The job's commands that are neither motion nor the spindle and coolant words post writes
// itself: pauses (M0, M1, M60), tool selection and change (T, M6), the override switches
// (M48-M53), digital and analog I/O (M62-M68) and user M-codes (M100-M199). Each goes into the
// joint program at its place when the dialect's controller has it; one it cannot carry out is
// refused at its line, and one that changes nothing a joint program does (an override switch on
// a controller without it) is left out with a warning. None is dropped silently.
#pragma once

#include <optional>
#include <string>

#include "pkm/gcode/canon.hpp"
#include "pkm/post/joint_program.hpp"

namespace pkm::post {

struct PassedCommand {
  std::string line;     // what the joint program gets; empty when nothing
  std::string refusal;  // why the dialect cannot carry it (the job is refused at its line)
  std::string warning;  // why it is left out, or what the controller does differently
};

// What becomes of `canon` in `dialect`, or nothing when it is none of these commands.
std::optional<PassedCommand> passed_command(const gcode::Canon& canon, Dialect dialect);

}  // namespace pkm::post
