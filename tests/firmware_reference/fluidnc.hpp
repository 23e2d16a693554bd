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

}  // namespace pkm::test::fluidnc_reference
