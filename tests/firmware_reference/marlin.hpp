// An independent reading of Marlin's own inverse kinematics, written from its source
// (MarlinFirmware/Marlin: Marlin/src/module/delta.cpp recalc_delta_settings and delta.h DELTA_Z;
// Marlin/src/module/polargraph.cpp inverse_kinematics; settings.cpp reset() for where the
// polargraph's draw area comes from): it reads an exported Configuration.h block with its own
// small parser and gives the steppers' positions for a tool position. Shares no code with
// src/pkm/firmware/marlin*.
#pragma once

#include <Eigen/Core>
#include <array>
#include <map>
#include <string>
#include <vector>

namespace pkm::test::marlin_reference {

struct Config {
  std::map<std::string, std::vector<double>> values;  // every numeric define, a list or one
  bool delta = false, polargraph = false;
  std::array<int, 3> joint_of_stepper{0, 1, 2};  // from the "pkmkit joints:" comment; -1: none
};

Config parse(const std::string& text);

// Marlin's positions of the X Y Z steppers (mm) for the tool at `tool_mm`.
std::array<double, 3> stepper_positions(const Config& config, const Eigen::Vector3d& tool_mm);

}  // namespace pkm::test::marlin_reference
