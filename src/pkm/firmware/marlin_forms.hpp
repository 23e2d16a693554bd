// The marlin target's pieces (docs/firmware-marlin.md): the DELTA and POLARGRAPH writers and
// readers, and what they share: the steppers' rates in Marlin's X Y Z order, the line naming the
// machine's joints, the box the travel limits come from.
#pragma once

#include <Eigen/Core>
#include <array>
#include <optional>
#include <string>
#include <vector>

#include "pkm/firmware/marlin_defines.hpp"
#include "pkm/firmware/target.hpp"

namespace pkm::firmware {

ExportedFile write_marlin_delta(const FirmwareMachine& machine, const ExportContext& context);
ExportedFile write_marlin_polargraph(const FirmwareMachine& machine, const ExportContext& context);
machine::ImportedMachine read_marlin_delta(const MarlinDefines& defines);
machine::ImportedMachine read_marlin_polargraph(const MarlinDefines& defines);

// Marlin's stock Configuration.h values for an axis the machine file has no joint for.
inline constexpr double kMarlinStockSteps[3] = {80.0, 80.0, 400.0};
inline constexpr double kMarlinStockFeed[3] = {300.0, 300.0, 5.0};
inline constexpr double kMarlinStockAcceleration[3] = {3000.0, 3000.0, 100.0};

// Which machine joint each of Marlin's X Y Z steppers drives (-1: none, Marlin's stock values).
using StepperJoints = std::array<int, 3>;

// The file's opening comment lines, the name define, the line naming the joints and the
// motion defines (steps, rates, accelerations): the parts both forms write.
std::string marlin_preamble(const FirmwareMachine& machine, const ExportContext& context,
                            const char* kinematics_define);
std::string marlin_motion_defines(const FirmwareMachine& machine, const StepperJoints& joints);
std::string define_line(const std::string& name, const std::string& value,
                        const std::string& comment);
std::string marlin_list(const std::vector<double>& values);

// Each bound of the work envelope where the machine file gives it, else the reach's (mm).
struct WorkBox {
  Eigen::Vector3d min = Eigen::Vector3d::Zero();
  Eigen::Vector3d max = Eigen::Vector3d::Zero();
};
WorkBox work_box(const machine::Machine& machine);

// What the reader takes from the file for every form: name, joints' rates (in `order`: the
// machine joint each stepper was, from the pkmkit line, else X Y Z), notes of unused defines.
struct MarlinJointNames {
  std::array<std::string, 3> names;
  std::array<int, 3> order{0, 1, 2};  // machine joint index of stepper X Y Z
  bool stock_steps = false;           // the steps were Marlin's stock values, not the machine's
  int line = 0;                       // the pkmkit line's, 0 without one
};
// FirmwareFileError: a stepper of the pkmkit line is none of the joints 1 to 3, or one named twice.
MarlinJointNames read_joint_names(const MarlinDefines& defines,
                                  const std::array<std::string, 3>& default_names);
[[noreturn]] void joint_names_fail(const MarlinDefines& defines, const MarlinJointNames& names,
                                   const std::string& why);
struct StepperRates {
  std::array<double, 3> feed_mm_per_s{}, acceleration_mm_per_s2{};
  std::optional<std::array<double, 3>> steps_per_mm;
};
StepperRates read_stepper_rates(const MarlinDefines& defines, const MarlinJointNames& names,
                                const std::string& kinematics_define);
machine::ImportedMachine imported_base(const MarlinDefines& defines,
                                       const std::vector<std::string>& used);

}  // namespace pkm::firmware
