// A machine: its kinematics, its joints with their limits, axis letters and home switches, its
// Cartesian limits (feed, acceleration, work envelope), home pose and homing procedure;
// explanations of the poses it cannot take, in
// the machine file's units; the machine file's parser.
#pragma once

#include <filesystem>
#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "pkm/kinematics/kinematics.hpp"
#include "pkm/machine/controller.hpp"
#include "pkm/machine/homing.hpp"
#include "pkm/machine/machine_file_error.hpp"

namespace pkm::machine {

enum class LengthUnit { mm, inch };

// Joint positions are mm for linear joints and rad for rotary ones (deg in the file); velocities,
// accelerations and jerks are the same units per second, second squared and second cubed.
struct JointSpec {
  std::string name;
  kinematics::JointKind kind = kinematics::JointKind::linear;
  double min = 0.0;
  double max = 0.0;
  double max_velocity = 0.0;
  double max_acceleration = 0.0;
  // The joint's jerk limit: a machine with one on any joint plans jerk-limited (S-curves).
  double max_jerk = 0.0;                  // 0: none
  char axis_letter = 'X';                 // letter of this joint in joint-space G-code
  std::optional<HomeSwitch> home_switch;  // where its switch trips, if it has one
  // Motor steps per mm (linear) or per deg (rotary) on a controller without kinematics (grbl's
  // $100..$102); none where the machine file does not say.
  std::optional<double> steps_per_unit;

  // Joint values cross the interfaces (files, joint-space G-code, command line) in mm or deg.
  double to_interface(double internal_value) const {
    return kind == kinematics::JointKind::rotary ? geometry::radians_to_degrees(internal_value)
                                                 : internal_value;
  }
  double from_interface(double interface_value) const {
    return kind == kinematics::JointKind::rotary ? geometry::degrees_to_radians(interface_value)
                                                 : interface_value;
  }
  const char* interface_unit() const {
    return kind == kinematics::JointKind::rotary ? "deg" : "mm";
  }
};

// What a machine without a Z joint does with the program's Z (the machine file's [tool] table).
// A plotter's pen: programmed Z on the drawing side of `pen_height_mm` (below it, or above it for
// `down_above`) puts the pen down, on the other side or at the height lifts it; the commands are
// written by post and the delay is spent by plan (a dwell) and post (G4). Where along a job the
// pen changes is motion/pen_path.hpp's.
enum class ToolZ {
  none,    // no [tool] table: Z is an ordinary coordinate (a joint of the model, or ignored)
  pen,     // Z drives the pen channel
  ignore,  // Z is dropped: no pen, no joint
};
struct ToolChannel {
  ToolZ z = ToolZ::none;
  double pen_height_mm = 0.0;  // [tool] down_below or down_above
  bool down_above = false;     // the pen draws above pen_height_mm (LinuxCNC polargraphs: Z90)
  std::string down_command = "M3 S1000";
  std::string up_command = "M5";
  double delay_s = 0.0;

  // Whether the program's Z (mm, machine coordinates) is on the drawing side.
  bool pen_down(double z_mm) const {
    return down_above ? z_mm > pen_height_mm : z_mm < pen_height_mm;
  }
  // The [tool] key that sets the height: "down_below" or "down_above".
  const char* height_key() const { return down_above ? "down_above" : "down_below"; }
};

struct CartesianLimits {
  double max_feed_mm_per_min = 0.0;
  double max_feed_mm_per_s() const { return max_feed_mm_per_min / 60.0; }
  double max_acceleration_mm_per_s2 = 0.0;
  // The work envelope ([cartesian] min and max, LinuxCNC's axis limits): mm and rad, infinite
  // where the file gives none. Only the coordinates the machine controls are checked.
  geometry::Vector6d envelope_min =
      geometry::Vector6d::Constant(-std::numeric_limits<double>::infinity());
  geometry::Vector6d envelope_max =
      geometry::Vector6d::Constant(std::numeric_limits<double>::infinity());
  bool has_envelope() const {
    return envelope_min.array().isFinite().any() || envelope_max.array().isFinite().any();
  }
};

class Machine {
 public:
  Machine(std::string name, std::string source, LengthUnit units,
          std::unique_ptr<kinematics::Kinematics> kinematics, std::vector<JointSpec> joints,
          CartesianLimits cartesian, geometry::Pose home);
  Machine(const Machine& other);
  Machine& operator=(const Machine& other);
  Machine(Machine&&) noexcept = default;
  Machine& operator=(Machine&&) noexcept = default;

  const std::string& name() const { return name_; }
  const std::string& source() const { return source_; }  // file the machine came from
  LengthUnit units() const { return units_; }
  const kinematics::Kinematics& kinematics() const { return *kinematics_; }
  kinematics::Kinematics& kinematics() { return *kinematics_; }
  const std::vector<JointSpec>& joints() const { return joints_; }
  const std::vector<std::string>& joint_names() const { return joint_names_; }
  const CartesianLimits& cartesian() const { return cartesian_; }
  const geometry::Pose& home() const { return home_; }
  const ToolChannel& tool() const { return tool_; }
  void set_tool(ToolChannel tool) { tool_ = std::move(tool); }
  // The [homing] table, if the file has one (homing.hpp).
  const std::optional<HomingTable>& homing() const { return homing_; }
  void set_homing(std::optional<HomingTable> homing) { homing_ = std::move(homing); }
  // The [controller] table, if the file has one (controller.hpp).
  const std::optional<ControllerSettings>& controller() const { return controller_; }
  void set_controller(std::optional<ControllerSettings> controller) {
    controller_ = std::move(controller);
  }
  // A joint's steps per mm or deg (JointSpec::steps_per_unit), as the machine file's joint sets it.
  void set_steps_per_unit(std::size_t joint, std::optional<double> steps) {
    joints_.at(joint).steps_per_unit = steps;
  }

  // The work envelope, IK (finite joints only), the assembly mode of home, then the joint limits.
  kinematics::Status inverse(const geometry::Pose& pose, kinematics::JointVector& joints) const;
  // Joint limits first, then FK seeded with pose_inout; a result in another assembly mode than
  // home's is solved again from home, and refused if it stays there.
  kinematics::Status forward(const kinematics::JointVector& joints,
                             geometry::Pose& pose_inout) const;
  // The same for the next sample of a path: the model's forward_along with `track` (the path's
  // scratch, kinematics.hpp) before the fall-back to home.
  kinematics::Status forward(const kinematics::JointVector& joints, geometry::Pose& pose_inout,
                             kinematics::ForwardTrack& track) const;
  // Refuses NaN as well as values beyond [min, max].
  kinematics::Status check_joint_limits(const kinematics::JointVector& joints) const;
  kinematics::Status check_envelope(const geometry::Pose& pose) const;
  std::string describe(const kinematics::Status& status) const {
    return kinematics::describe(status, joint_names_);
  }

  // What a user needs to act on a pose the machine refused (inverse's status): the pose, the
  // joint, its value and the limit it passes, in the machine file's units, e.g.
  // "pose x 1234.000 y -20.000 mm: joint 'left' = 2345.678 mm passes its max 2100.000 mm".
  std::string explain(const geometry::Pose& pose, const kinematics::Status& status) const;
  // "joint_angle: the platform joint of 'leg3' is at 31.200 deg from its axis; max_joint_angle is
  // 30.000 deg", "interference: 'leg2' and 'leg5' are 31.400 mm apart (axis to axis);
  // leg_diameter is 40.000 mm", in the machine file's units.
  std::string mechanism_limit_text(const kinematics::MechanismLimit& limit) const;
  // "joint 'left' = 2345.678 mm passes its max 2100.000 mm" (value in mm or rad inside).
  std::string explain_joint(int joint, double value) const;
  // A joint value (mm or rad inside) as the machine file writes it: "12.500 mm", "0.4921 in".
  std::string joint_value_text(int joint, double value) const;
  // A move the machine cannot follow, given as its poses for u in [0, 1] (mm, rad): explains
  // where it first leaves the reach (found by sampling and bisection, so every caller names the
  // same pose and joint), with how far the failing joint goes along the move.
  std::string explain_path(const std::function<geometry::Vector6d(double)>& pose_at) const;

  // The interface units of ik, fk, check and the explanations: the machine file's length unit
  // (mm or inch) and degrees.
  double mm_per_unit() const { return units_ == LengthUnit::inch ? 25.4 : 1.0; }
  const char* length_unit() const { return units_ == LengthUnit::inch ? "in" : "mm"; }
  double joint_to_file(int joint, double internal) const;
  double joint_from_file(int joint, double value) const;
  const char* joint_file_unit(int joint) const;
  double axis_to_file(int axis, double internal) const;  // pose coordinate 0..5
  double axis_from_file(int axis, double value) const;
  const char* axis_file_unit(int axis) const { return axis < 3 ? length_unit() : "deg"; }
  // "x 1234.000 y -20.000 mm" (the controlled coordinates; angles "a 10.000 deg").
  std::string format_pose(const geometry::Pose& pose) const;

 private:
  // forward() with the model's forward_along where `track` is given, forward where it is null.
  kinematics::Status forward_with(const kinematics::JointVector& joints, geometry::Pose& pose_inout,
                                  kinematics::ForwardTrack* track) const;
  // The envelope part of explain_path: where the move crosses the envelope on `axis`, and how far
  // beyond it the move goes.
  // The joint_angle or interference part of explain().
  std::string explain_mechanism_limit(const geometry::Pose& pose,
                                      const kinematics::Status& status) const;
  // The other_assembly part of explain(): a hexapod's leg past the base plane with its numbers.
  std::string explain_other_assembly(const geometry::Pose& pose) const;
  std::string explain_envelope_crossing(
      const geometry::Pose& pose, int axis,
      const std::function<geometry::Vector6d(double)>& pose_at) const;

  std::string name_;
  std::string source_;
  LengthUnit units_ = LengthUnit::mm;
  std::unique_ptr<kinematics::Kinematics> kinematics_;
  std::vector<JointSpec> joints_;
  std::vector<std::string> joint_names_;
  CartesianLimits cartesian_;
  geometry::Pose home_;
  ToolChannel tool_;
  std::optional<HomingTable> homing_;
  std::optional<ControllerSettings> controller_;
  int home_assembly_mode_ = 0;
  bool checks_envelope_ = false;  // cartesian_.has_envelope(), asked once, not per sample
};

// Parses a machine file's text; `source_name` is used in error locations.
Machine parse_machine(std::string_view toml_text, const std::string& source_name);
// Reads and parses a machine file. Throws MachineFileError (file:line:key) on any problem.
Machine load_machine(const std::filesystem::path& path);

// Per-axis reachable range along lines through home (mm, or rad for a b c), found by bisection on
// the machine's inverse (IK, joint limits, work envelope): what `pkm check` reports as the
// workspace extent.
struct AxisExtent {
  int axis = 0;
  double min = 0.0;
  double max = 0.0;
};
std::vector<AxisExtent> reachable_extent(const Machine& machine);

// An axis-aligned box of pose coordinates (mm, rad); `axes` says which coordinates it bounds.
struct PoseBox {
  geometry::Dof axes;
  geometry::Vector6d min = geometry::Vector6d::Zero();
  geometry::Vector6d max = geometry::Vector6d::Zero();
  bool contains(const PoseBox& inner) const;
};
// The reachable extent as a box over the machine's controlled coordinates.
PoseBox reach_box(const Machine& machine);
// When a job's bounding box (program coordinates, mm and rad, over the axes it uses) placed at
// `origin` (mm, rad; where program zero sits, as --origin) does not fit in the machine's reach:
// both boxes in the machine file's units and the --origin that would centre the job, e.g.
// "the job spans x 0.000..500.000 y ... mm; the machine reaches x ...; try --origin 650 -900".
// Empty when the job's box fits.
std::string outside_reach_hint(const Machine& machine, const PoseBox& job,
                               const geometry::Vector6d& origin);

// Smallest over largest singular value of the machine's jacobian at home, each column scaled to
// unit length (so mm and rad columns compare): 0 at a singular machine (a hexapod with parallel
// legs), near 1 at a well-conditioned one.
double relative_conditioning_at_home(const Machine& machine);
// Below this the machine is singular (or nearly) at home, and its file is refused.
inline constexpr double kSingularAtHome = 1e-6;
// Why the machine is singular at home, with the numbers (its conditioning there and the motion of
// the tool that moves no joint); empty when it is not.
std::string singular_at_home(const Machine& machine);

}  // namespace pkm::machine
