// An independent reading of Klipper's linear delta and cable winch, for the klipper target's proof
// (tests/test_firmware_klipper.cpp): its own parser of printer.cfg text and the stepper
// coordinates Klipper computes, written from Klipper's source (klippy/kinematics/delta.py,
// klippy/chelper/kin_delta.c, klippy/kinematics/winch.py, klippy/chelper/kin_winch.c,
// klippy/stepper.py), not from pkmkit's writer or reader.
#pragma once

#include <array>
#include <map>
#include <string>
#include <vector>

namespace pkm::test::klipper_reference {

// section -> key -> value, as Klipper reads them: text after '#' dropped, keys lowercased.
using Config = std::map<std::string, std::map<std::string, std::string>>;
Config parse(const std::string& text);

struct Delta {
  std::array<double, 3> tower_x{}, tower_y{}, arm{};
  // Each stepper's coordinate when its endstop triggers (delta.py's abs_endstops).
  std::array<double, 3> abs_endstop{};
  double radius = 0.0, print_radius = 0.0, min_z = 0.0, max_z = 0.0;
  std::array<double, 3> steps_per_mm{};  // 0 where the section gives no rotation_distance
};
// Klipper's defaults applied: angles 210 330 90; stepper_b and _c take stepper_a's arm_length
// and position_endstop; print_radius delta_radius; minimum_z_position 0. Throws
// std::runtime_error for a missing setting.
Delta delta(const Config& config);

// kin_delta.c's stepper coordinate (mm) for the tool at (x, y, z).
std::array<double, 3> stepper_coordinates(const Delta& delta, double x, double y, double z);

// Klipper's rotary delta (klippy/kinematics/rotary_delta.py, kin_rotary_delta.c): the arm's
// angle (rad, 0 horizontal and outward, positive with the elbow UP) for the tool at (x, y, z)
// in Klipper's frame, the shoulder at shoulder_radius along `angle_deg` and shoulder_height up;
// of the two elbows, the outer one.
double rotary_arm_angle(double shoulder_radius, double shoulder_height, double angle_deg,
                        double upper_arm, double lower_arm, double x, double y, double z);

// winch.py's anchors: [stepper_a] .. [stepper_c] always, then stepper_d .. stepper_z while the
// section exists, each anchor_x anchor_y anchor_z. Throws std::runtime_error for a missing one or
// a kinematics other than winch.
std::vector<std::array<double, 3>> winch_anchors(const Config& config);

// kin_winch.c's stepper coordinate (mm) for the tool at (x, y, z): the distance to each anchor.
std::vector<double> winch_stepper_coordinates(const std::vector<std::array<double, 3>>& anchors,
                                              double x, double y, double z);

}  // namespace pkm::test::klipper_reference
