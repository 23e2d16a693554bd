// Homing on switches, as the machine file describes it: each joint's `home_switch` (the joint
// reading at which its switch trips, and which way the joint moves to reach it), the [homing]
// table (the order of the joints, the slack, the feeds), their reading and checks, and the moves
// of the procedure (docs/homing.md), with every joint whose position is known kept within its
// limits. Writing them as G-code is the post module's part (post/homing_program.hpp).
#pragma once

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "pkm/kinematics/model_config.hpp"

namespace pkm::machine {

class Machine;
struct JointSpec;

// A joint's home switch: where it trips (mm, rad inside) and which way the joint moves towards it.
struct HomeSwitch {
  double position = 0.0;
  // False: the joint decreases towards its switch (a cable pulled in); true: it increases.
  bool toward_max = false;
};

// The [homing] table. Its distances and feeds are in the machine file's units: its length unit
// for linear joints, deg for rotary ones; feeds per minute.
struct HomingTable {
  std::vector<int> sequence;  // joints in the order they find their switches
  double slack = 0.0;         // the other cables are paid out by this before each joint homes
  double probe_feed = 0.0;    // towards the switch
  double feed = 0.0;          // paying out, backing off, the move to home
  double backoff = 0.0;       // away from the switch once it has tripped
  // The longest probe; none: as far as the joint can be from its switch (below).
  std::optional<double> probe_travel;
};

enum class HomingMoveKind {
  pay_out,       // the other joints of the mechanism lengthen by the slack (relative)
  probe,         // the homed joint moves towards its switch until it trips (relative)
  set_position,  // the homed joint reads its switch's position from here on
  back_off,      // the homed joint moves away from its switch (relative)
  go_home,       // the homed joints move to the home pose's joints (absolute)
};

struct HomingMove {
  HomingMoveKind kind = HomingMoveKind::pay_out;
  int homed_joint = -1;  // the joint whose step this is; -1 for go_home
  // Joint and value, mm or rad: a distance for the relative moves, a position otherwise.
  std::vector<std::pair<int, double>> targets;
  // At the interface (mm/min, deg/min when the first joint moved is rotary); 0 for set_position.
  double feed_per_min = 0.0;
  // Probes: how far past its switch the joint stops from probe_feed at its max_acceleration (mm,
  // rad): the controller sets the position where it stopped, this much off.
  double stop_distance = 0.0;
};

// `home_switch` and `home_toward` of a [[joints]] table (the joint as read so far, its limits
// in mm or rad; `scale`: mm or rad per file unit); none without home_switch.
std::optional<HomeSwitch> read_home_switch(const kinematics::ModelConfig& joint_table,
                                           const JointSpec& joint, double scale);

// The [homing] table: every joint its sequence names exists, has a home_switch and is named
// once; every joint of the mechanism is named (`passthrough[i]`: joint i follows a pose
// coordinate and may be left out); numbers positive and finite. Fails through the section
// (file:line:key).
HomingTable read_homing_table(const kinematics::ModelConfig& section,
                              const std::vector<JointSpec>& joints,
                              const std::vector<bool>& passthrough, double mm_per_unit);

// The moves of the machine's homing procedure, in order. Every joint whose position is known
// (after its switch) stays within its limits, or the procedure fails through `section` (the
// [homing] table: file:line:key), or with std::invalid_argument without one. Throws
// std::invalid_argument when the machine has no [homing] table.
std::vector<HomingMove> homing_moves(const Machine& machine,
                                     const kinematics::ModelConfig* section = nullptr);

}  // namespace pkm::machine
