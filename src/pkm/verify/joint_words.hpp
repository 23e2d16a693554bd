// How a joint program's axis words name the machine's joints (each joint's letter, machine.hpp),
// shared by verify and view: the interpreter's options for a program that starts at home, and a
// block's end read as joint values (mm or rad inside; a rotary joint's word is in deg, a linear
// one's in the program's mm or inch).
#pragma once

#include <vector>

#include "pkm/gcode/interpreter.hpp"
#include "pkm/machine/machine.hpp"

namespace pkm::verify {

class JointWords {
 public:
  explicit JointWords(const machine::Machine& machine);

  // Index of joint i's letter in the interpreter's position (X Y Z A B C U V W: 0..8).
  int position_index(std::size_t joint) const { return index_[joint]; }
  // The options of a joint program that starts at `start` (joint values, internal units), with
  // the loop bounds of `bounds`, and the pen's commands as events on a machine with a pen channel.
  gcode::InterpreterOptions program_options(const kinematics::JointVector& start,
                                            const gcode::InterpreterOptions& bounds) const;
  // The joint values a motion command ends at.
  kinematics::JointVector read(const gcode::Canon& canon) const;

 private:
  const machine::Machine& machine_;
  std::vector<int> index_;
};

}  // namespace pkm::verify
