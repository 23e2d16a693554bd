// A machine: its kinematics, its joints with their limits, its Cartesian limits and home pose.
#pragma once

#include <filesystem>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "pkm/kinematics/kinematics.hpp"
#include "pkm/machine/machine_file_error.hpp"

namespace pkm {

enum class LengthUnit { mm, inch };

// Joint positions are mm for linear joints and rad for rotary ones (deg in the file); velocities
// and accelerations are the same units per second and per second squared.
struct JointSpec {
  std::string name;
  JointKind kind = JointKind::linear;
  double min = 0.0;
  double max = 0.0;
  double max_velocity = 0.0;
  double max_acceleration = 0.0;
  char axis_letter = 'X';  // letter of this joint in joint-space G-code

  // Joint values cross the interfaces (files, joint-space G-code, command line) in mm or deg.
  double to_interface(double internal_value) const {
    return kind == JointKind::rotary ? radians_to_degrees(internal_value) : internal_value;
  }
  double from_interface(double interface_value) const {
    return kind == JointKind::rotary ? degrees_to_radians(interface_value) : interface_value;
  }
  const char* interface_unit() const { return kind == JointKind::rotary ? "deg" : "mm"; }
};

// What a machine without a Z joint does with the program's Z (the machine file's [tool] table).
// A plotter's pen: programmed Z below `down_below_mm` puts the pen down, at or above lifts it; the
// commands are written by post and the delay is spent by plan (a dwell) and post (G4).
enum class ToolZ {
  none,    // no [tool] table: Z is an ordinary coordinate (a joint of the model, or ignored)
  pen,     // Z drives the pen channel
  ignore,  // Z is dropped: no pen, no joint
};
struct ToolChannel {
  ToolZ z = ToolZ::none;
  double down_below_mm = 0.0;
  std::string down_command = "M3 S1000";
  std::string up_command = "M5";
  double delay_s = 0.0;

  // Whether the program's Z (mm, machine coordinates) leaves the pen on the paper.
  bool pen_down(double z_mm) const { return z_mm < down_below_mm; }
};

struct CartesianLimits {
  double max_feed_mm_per_min = 0.0;
  double max_acceleration_mm_per_s2 = 0.0;
};

class Machine {
 public:
  Machine(std::string name, std::string source, LengthUnit units,
          std::unique_ptr<Kinematics> kinematics, std::vector<JointSpec> joints,
          CartesianLimits cartesian, Pose home);
  Machine(const Machine& other);
  Machine& operator=(const Machine& other);
  Machine(Machine&&) noexcept = default;
  Machine& operator=(Machine&&) noexcept = default;

  const std::string& name() const { return name_; }
  const std::string& source() const { return source_; }  // file the machine came from
  LengthUnit units() const { return units_; }
  const Kinematics& kinematics() const { return *kinematics_; }
  Kinematics& kinematics() { return *kinematics_; }
  const std::vector<JointSpec>& joints() const { return joints_; }
  const std::vector<std::string>& joint_names() const { return joint_names_; }
  const CartesianLimits& cartesian() const { return cartesian_; }
  const Pose& home() const { return home_; }
  const ToolChannel& tool() const { return tool_; }
  void set_tool(ToolChannel tool) { tool_ = std::move(tool); }

  // IK, then the assembly mode of home, then the joint limits of the machine file.
  Status inverse(const Pose& pose, JointVector& joints) const;
  // Joint limits first, then FK seeded with pose_inout; a result in another assembly mode than
  // home's is solved again from home, and refused if it stays there.
  Status forward(const JointVector& joints, Pose& pose_inout) const;
  Status check_joint_limits(const JointVector& joints) const;
  std::string describe(const Status& status) const { return pkm::describe(status, joint_names_); }

 private:
  std::string name_;
  std::string source_;
  LengthUnit units_ = LengthUnit::mm;
  std::unique_ptr<Kinematics> kinematics_;
  std::vector<JointSpec> joints_;
  std::vector<std::string> joint_names_;
  CartesianLimits cartesian_;
  Pose home_;
  ToolChannel tool_;
  int home_assembly_mode_ = 0;
};

// Parses a machine file's text; `source_name` is used in error locations.
Machine parse_machine(std::string_view toml_text, const std::string& source_name);
// Reads and parses a machine file. Throws MachineFileError (file:line:key) on any problem.
Machine load_machine(const std::filesystem::path& path);

// Per-axis reachable range along lines through home (mm, or rad for a b c), found by bisection on
// the machine's IK and joint limits: what `pkm check` reports as the workspace extent.
struct AxisExtent {
  int axis = 0;
  double min = 0.0;
  double max = 0.0;
};
std::vector<AxisExtent> reachable_extent(const Machine& machine);

}  // namespace pkm
