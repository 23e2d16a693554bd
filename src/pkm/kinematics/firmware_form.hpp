// A model's geometry in the forms that controllers with their own kinematics implement (FluidNC,
// Klipper, RepRapFirmware, grblHAL, Marlin; docs/firmware.md): a two-cable wall plotter, a
// linear delta, a rotary delta, a cable robot (N straight cables to a translating effector, or
// Maslow 4's belts on swivel arms). A model answers `Kinematics::firmware_form()` with its
// nearest geometry in one form and what that form leaves out; `make_form_kinematics` builds the
// pkmkit model of a form back (an import, an approximation).
#pragma once

#include <Eigen/Core>
#include <array>
#include <memory>
#include <string>
#include <variant>
#include <vector>

#include "pkm/kinematics/kinematics.hpp"
#include "pkm/kinematics/passthrough.hpp"

namespace pkm::kinematics {

// Two straight cords from fixed points to the pen, in the machine's x y (mm): a joint reading is
// the cord's length from its anchor plus its offset (the reading at zero length).
struct WallPlotterForm {
  std::array<Eigen::Vector2d, 2> anchors_mm{Eigen::Vector2d::Zero(), Eigen::Vector2d::Zero()};
  std::array<double, 2> cable_offsets_mm{0.0, 0.0};
};

// Three vertical towers, each a carriage with a rod of its own length to the effector:
//   reading = z + sqrt(rod^2 - |(x, y) - column|^2) + carriage_offset
// where `column` is the tool's (x, y) at which the tower's rod hangs vertical (the tower's x y
// less the effector's joint offset) and `carriage_offset` the reading less the carriage's height
// above the tool (mm, machine frame, z up).
struct LinearDeltaTower {
  Eigen::Vector2d column_mm = Eigen::Vector2d::Zero();
  double rod_mm = 0.0;
  double carriage_offset_mm = 0.0;
};
struct LinearDeltaForm {
  std::array<LinearDeltaTower, 3> towers;
};

// Three arms on horizontal pivots, LinuxCNC's rotarydeltakins conventions (docs/kinematics.md):
// the pivots' plane at z = 0, z up; arm 0's pivot at (0, -base_radius) swinging in the y z
// plane, arms 1 and 2 at 120 and 240 deg counter-clockwise from it; a reading (rad) is 0 with
// the arm horizontal and outward, positive down.
struct RotaryDeltaForm {
  double base_radius_mm = 0.0;      // centre to each pivot axis
  double arm_length_mm = 0.0;       // pivot to elbow
  double forearm_length_mm = 0.0;   // elbow to the effector's joint (the parallelogram)
  double platform_radius_mm = 0.0;  // tool to each forearm's effector joint
};

// N straight cables from fixed points to one point of an effector that translates without
// turning (RepRapFirmware's Hangprinter, Klipper's winch): each anchor with the effector's tie
// point folded in (the anchor less the tie point's offset from the tool), so that
//   reading = |anchor - tool| + offset
// (mm, machine frame). Planar: the tool moves in x y at z = 0 (N >= 3); else x y z (N >= 4).
// Maslow 4 (planar, tie points riding on the tool's z, each belt on an arm of its own that turns
// to point at its anchor): reading = sqrt((|anchor - tool| in plan - arm)^2 + dz^2) + offset.
struct CableRobotForm {
  std::vector<Eigen::Vector3d> anchors_mm;
  std::vector<double> cable_offsets_mm;  // one per anchor
  std::vector<double> swivel_arms_mm;    // one per anchor (0: tied at the point); may be empty
  bool planar = false;
  bool cables_follow_z = false;  // planar only: the tie points at the tool's z, not z = 0
  // The joints are unstretched lengths (RepRapFirmware's flex compensation, M666 F1): a firmware
  // whose lines do not stretch moves other joints.
  bool flex_compensation = false;
};

using FormGeometry =
    std::variant<WallPlotterForm, LinearDeltaForm, RotaryDeltaForm, CableRobotForm>;

// Maslow 4's shape: a cable robot with swivel arms or tie points riding on z.
bool has_swivel_arms(const CableRobotForm& form);

// "two-cable wall plotter", "linear delta", "rotary delta", "cable robot", "cable robot on swivel
// arms".
const char* form_name(const FormGeometry& geometry);

struct FirmwareForm {
  FormGeometry geometry;
  // What the form leaves out of the model, each with its numbers ("pulley_radius 10.275 mm: the
  // cords leave their pulleys tangentially"); empty: the form is the model exactly.
  std::vector<std::string> losses;
  // What the model checks that the form does not (tension limits, leg limits): the firmware
  // follows the same joints without refusing those poses.
  std::vector<std::string> unchecked;
  PassThroughAxes passthrough;  // the model's pass-through joints, after the form's own
};

// One number in a loss's text ("pulley_radius %.3f mm: ..."): the models' firmware_form()s share
// it.
std::string loss_text(const char* format, double value);

// The pkmkit model of a form: a cable_plotter, a glide with three vertical rails, a
// rotary_delta, a cable_robot (its tie points at the tool, no mass or tension limits); its
// pass-through joints after them. Throws std::invalid_argument for a geometry the model refuses (a
// rod shorter than nothing).
std::unique_ptr<Kinematics> make_form_kinematics(const FormGeometry& geometry,
                                                 const PassThroughAxes& passthrough = {});

}  // namespace pkm::kinematics
