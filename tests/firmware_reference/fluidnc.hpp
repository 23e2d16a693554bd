// FluidNC's WallPlotter as the firmware computes it (bdring/FluidNC,
// FluidNC/src/Kinematics/WallPlotter.cpp: init, xy_to_lengths, transform_cartesian_to_motors),
// written again from its source for the tests, with its own reading of config.yaml: independent
// of pkmkit's writer and reader (src/pkm/firmware/fluidnc*.cpp).
#pragma once

#include <Eigen/Core>
#include <array>
#include <map>
#include <string>

namespace pkm::test::fluidnc_reference {

// config.yaml's values by their lower-case dotted path ("kinematics.wallplotter.left_anchor_x").
std::map<std::string, std::string> read_config(const std::string& text);

struct WallPlotter {
  double left_anchor_x = -100.0, left_anchor_y = 100.0;  // FluidNC's defaults (WallPlotter.h)
  double right_anchor_x = 100.0, right_anchor_y = 100.0;
  bool has_z = false;
  // G54's origin in machine coordinates, from macros.startup_line0 "G10 L2 P1 X.. Y.. Z..".
  Eigen::Vector3d g54_origin = Eigen::Vector3d::Zero();
};
WallPlotter wall_plotter(const std::map<std::string, std::string>& config);

// The motor positions (mm) FluidNC commands for a point given in G54 work coordinates: the
// cords' lengths less their lengths at machine position (0, 0), the left one negated; Z as is.
std::array<double, 3> motors(const WallPlotter& plotter, const Eigen::Vector3d& work_mm);
// The same in FluidNC's own arithmetic: 32-bit floats from the settings on (hypot_f, float).
std::array<double, 3> motors_float(const WallPlotter& plotter, const Eigen::Vector3d& work_mm);

// FluidNC's parallel_delta (FluidNC/src/Kinematics/ParallelDelta.cpp: delta_calcAngleYZ,
// transform_cartesian_to_motors): the pivots on a triangle of side base_triangle_mm, arm 0 on
// the -y side swinging in the y z plane, arms 1 and 2 at +120 and +240 deg; the effector's
// joints on a triangle of side end_effector_triangle_mm; the elbow crank_mm from the pivot,
// linkage_mm from the effector's joint, the outer of the two elbows.
struct ParallelDelta {
  double crank_mm = 70.0, base_triangle_mm = 179.437, linkage_mm = 133.5,
         end_effector_triangle_mm = 86.603, up_degrees = -30.0;  // FluidNC's defaults
};
ParallelDelta parallel_delta(const std::map<std::string, std::string>& config);

// The arms' motor positions (deg: 0 horizontal, positive down) for a point (mm, FluidNC's frame,
// unhomed); false where FluidNC refuses it (no elbow, or an arm above up_degrees - 1).
bool arm_degrees(const ParallelDelta& delta, const Eigen::Vector3d& point_mm,
                 std::array<double, 3>& degrees);

}  // namespace pkm::test::fluidnc_reference
