// `pkm home`'s programs, joint-space G-code for controllers without kinematics: the homing
// program of a machine with switches (the moves of machine/homing.hpp: pay the other cables out,
// probe towards the switch, set the joint to the switch's reading, back off; then go home), and
// the block that sets joint readings measured by hand at rest. Each dialect probes and sets
// positions with the words it takes (docs/homing.md):
//   linuxcnc, grbl, grblhal: G38.2 (fails when the switch does not trip), G10 L20 P1 (G54);
//   mach3:          G31 (its straight probe; it has no G38.2), G92 (it has no G10 L20).
#pragma once

#include <string>
#include <vector>

#include "pkm/machine/machine.hpp"
#include "pkm/post/joint_program.hpp"

namespace pkm::post {

// The homing program, header comments to M2. Throws std::invalid_argument (naming the machine
// file) when the machine has no [homing] table, when the dialect is not one of linuxcnc, mach3,
// grbl or grblhal, or cannot write the machine's axis letters, or cannot probe with a homed joint's
// letter (Mach3's G31 moves no rotary axis, A B C).
std::string homing_program(const machine::Machine& machine, Dialect dialect);

// Joint readings measured by hand, checked: every joint (pass-through joints at their home
// values) and the pose forward kinematics gives for them.
struct MeasuredJoints {
  kinematics::JointVector joints;  // mm, rad
  geometry::Pose pose;
  // Where the readings come from, for the program's comments.
  std::string source = "measured by hand at rest";
};

// The joints at the machine's home, for a machine without switches whose effector is put there by
// hand (a Hangprinter's lines set at the origin): its set-position block.
MeasuredJoints joints_at_home(const machine::Machine& machine);

// The joints of the mechanism, in order: those `pkm home --measured` takes (pass-through joints,
// such as a pen's Z, follow a pose coordinate and are not measured).
std::vector<int> measured_joint_indices(const machine::Machine& machine);

// `values`: one reading per joint of the mechanism, in the machine file's units (deg for rotary
// joints). Throws std::invalid_argument with the numbers when their count is wrong, when a
// reading passes its joint's limits, when no pose has these readings, or when that pose is not
// one the machine can take (its work envelope, the cables' pull).
MeasuredJoints measured_joints(const machine::Machine& machine, const std::vector<double>& values);

// The set-position block for readings measured at rest: header comments, the block, M2.
// The line that makes the controller read `joints` (mm or rad inside; one value per joint) where
// the machine stands, without moving it: "G10 L20 P1 X1000.000 Y1204.159" (G54's offsets; Mach3:
// G92). How a set-position block zeroes a machine measured by hand, and how `pkm stream --dry-run`
// puts grbl-sim, which starts at step 0, at the machine's home.
std::string set_position_line(const machine::Machine& machine, Dialect dialect,
                              const kinematics::JointVector& joints);

std::string set_position_program(const machine::Machine& machine, Dialect dialect,
                                 const MeasuredJoints& measured);

}  // namespace pkm::post
