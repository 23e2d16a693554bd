// What a machine whose joints are lines wound on motor-driven spools answers: a motor's position
// from its line's joint and back, as RepRapFirmware's spool model (the wound radius growing with
// the line on it) turns them. Kinematics::line_spools() gives it (a cable_robot with spool keys,
// cable_robot_spool.cpp); calibration reads Hangprinter's motor-degree data through it.
#pragma once

#include <optional>

namespace pkm::kinematics {

class LineSpools {
 public:
  virtual ~LineSpools() = default;

  // Whether joint `joint` is a line on a spool (the others have no motor model here).
  virtual bool has_spool(int joint) const = 0;
  // Full steps of joint `joint`'s motor per turn (without a spool: 0).
  virtual int full_steps_per_rev(int joint) const = 0;
  // The motor position (full steps) for the joint's value `joint_mm`, counted from line
  // position 0 (the tool at x 0 y 0 z 0); none without a spool or where it would unwind past
  // its core.
  virtual std::optional<double> motor_full_steps(int joint, double joint_mm) const = 0;
  // Its inverse: the joint (mm) whose motor position is `full_steps`; none without a spool or
  // for a position no line length gives.
  virtual std::optional<double> joint_from_motor_full_steps(int joint, double full_steps) const = 0;
};

}  // namespace pkm::kinematics
