// An independent reading of grblHAL's WallPlotter (grblHAL/core kinematics/wall_plotter.c, read at
// f80fc34): its own small parser of the exported `$` lines and G10 L2 P1 offset, and the
// firmware's inverse and forward kinematics written from that source, for the round-trip tests
// (tests/test_firmware_grblhal.cpp). Nothing here uses pkmkit's reader or writer.
#pragma once

#include <Eigen/Core>
#include <map>
#include <string>

namespace pkm::test::grblhal_reference {

struct WallPlotterFile {
  std::map<int, double> settings;                       // $N=value, comments stripped
  Eigen::Vector3d g54 = Eigen::Vector3d::Zero();        // G10 L2 P1 X Y Z (absent words: 0)
  double width_mm() const { return settings.at(130); }  // X max travel
};

WallPlotterFile parse(const std::string& text);

// Motor positions in mm (steps / $10N): x = motor A, y = motor B, z = Z, for a program position
// in G54 (grblHAL adds the G54 offset to get its machine position, then transform_from_cartesian).
Eigen::Vector3d motors_mm(const WallPlotterFile& file, const Eigen::Vector3d& g54_position_mm);
// The same in single precision, as the firmware computes it (its floats).
Eigen::Vector3d motors_mm_float(const WallPlotterFile& file,
                                const Eigen::Vector3d& g54_position_mm);
// grblHAL's machine position (not G54) of motor positions: transform_to_cartesian, y >= 0.
Eigen::Vector3d machine_position_mm(const WallPlotterFile& file, const Eigen::Vector3d& motors_mm);

}  // namespace pkm::test::grblhal_reference

namespace pkm::test::grblhal_reference {

// delta.c's inverse kinematics (delta_calcInverse): the three arms' angles in rad from a machine
// position (mm), read from the exported $641..$644; false where an arm cannot reach.
bool delta_angles_rad(const WallPlotterFile& file, const Eigen::Vector3d& position_mm,
                      Eigen::Vector3d& angles_rad);

}  // namespace pkm::test::grblhal_reference
