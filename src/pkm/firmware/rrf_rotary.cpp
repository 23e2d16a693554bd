#include "pkm/firmware/rrf_rotary.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <memory>

#include "pkm/firmware/rrf_delta.hpp"
#include "pkm/geometry/pose.hpp"
#include "pkm/kinematics/firmware_form.hpp"
#include "pkm/machine/machine_writer.hpp"

namespace pkm::firmware {
namespace {

// Arms pointing elsewhere than pkmkit's (deg) are not its rotary delta.
constexpr double kAngleTolerance_deg = 1e-6;

// Where pkmkit's arm `arm` points (deg ccw from +x): arm 0 towards -y, then every 120 deg.
double pkmkit_arm_angle_deg(int arm) {
  return -90.0 + 120.0 * arm;
}

std::string list3(const std::array<double, 3>& values) {
  return rrf_number(values[0]) + ":" + rrf_number(values[1]) + ":" + rrf_number(values[2]);
}

std::string per_drive(double value) {
  return "X" + rrf_number(value) + " Y" + rrf_number(value) + " Z" + rrf_number(value);
}

constexpr const char* kRotaryNotHeld =
    "; Not held by RRF: the arms' own speed and acceleration limits (the joints' max_velocity, "
    "max_acceleration): RRF limits the effector's speed and acceleration along X Y (M203 X, "
    "M201 X) and along Z apart; it homes each arm up to its endstop and keeps Z within M208\n"
    "; RRF keeps X Y within M669 B of x 0 y 0 and pulls a move beyond it back onto that circle: "
    "B is the largest such circle inside the machine's work envelope (its reach where it has "
    "none)";

// The arm reading (rad) at which `joint`'s endstop trips: its home switch, else its arm at its
// highest (the joint's min: pkmkit's angle is positive down).
double endstop_reading_rad(const machine::Machine& machine, int joint) {
  const machine::JointSpec& spec = machine.joints()[static_cast<std::size_t>(joint)];
  if (!spec.home_switch) return spec.min;
  if (spec.home_switch->toward_max) {
    throw ExportRefused(machine.source() + ": joint '" + spec.name +
                        "' homes downwards to a switch; RRF's rotary delta homes each arm up to "
                        "an endstop");
  }
  return spec.home_switch->position;
}

RrfRotaryDelta rotary_settings(const FirmwareMachine& fm, TowerAssignment& towers) {
  const auto& form = std::get<kinematics::RotaryDeltaForm>(fm.form.geometry);
  const machine::Machine& machine = fm.machine;
  RrfRotaryDelta delta;
  towers =
      assign_towers({pkmkit_arm_angle_deg(0), pkmkit_arm_angle_deg(1), pkmkit_arm_angle_deg(2)},
                    kRrfRotaryNominalAngles);
  delta.angle_corrections_deg = towers.corrections_deg;
  delta.radius_mm = form.base_radius_mm - form.platform_radius_mm;
  std::array<double, 3> endstops{};
  double lowest_arm_deg = 0.0;  // RRF's, the least of -(each joint's max)
  for (std::size_t tower = 0; tower < 3; ++tower) {
    const int joint = towers.joint_of_tower[tower];
    const machine::JointSpec& spec = machine.joints()[static_cast<std::size_t>(joint)];
    delta.arm_lengths_mm[tower] = form.arm_length_mm;
    delta.rod_lengths_mm[tower] = form.forearm_length_mm;
    endstops[tower] = -geometry::radians_to_degrees(endstop_reading_rad(machine, joint));
    lowest_arm_deg = std::min(lowest_arm_deg, -geometry::radians_to_degrees(spec.max));
    delta.steps_per_deg[tower] = spec.steps_per_unit;
  }
  delta.max_arm_angle_deg = (endstops[0] + endstops[1] + endstops[2]) / 3.0;
  delta.min_arm_angle_deg = lowest_arm_deg;
  for (std::size_t tower = 0; tower < 3; ++tower) {
    delta.endstop_adjustments_deg[tower] = endstops[tower] - delta.max_arm_angle_deg;
  }
  const RrfBounds bounds = rrf_bounds(machine);
  delta.print_radius_mm = bounds.print_radius_mm;
  delta.z_min_mm = bounds.z_min_mm;
  delta.z_max_mm = bounds.z_max_mm;
  delta.max_speed_mm_per_min = machine.cartesian().max_feed_mm_per_min;
  delta.max_acceleration_mm_per_s2 = machine.cartesian().max_acceleration_mm_per_s2;
  return delta;
}

std::string arm_line(const FirmwareMachine& fm, const TowerAssignment& towers, int tower) {
  const std::size_t t = static_cast<std::size_t>(tower);
  const int joint = towers.joint_of_tower[t];
  return std::string("; drive ") + kRrfDriveLetters[t] + " = arm " + kRrfTowerNames[t] +
         " = joint " + std::to_string(joint + 1) + " \"" +
         fm.machine.joints()[static_cast<std::size_t>(joint)].name + "\": towards " +
         rrf_number(pkmkit_arm_angle_deg(joint)) +
         " deg; RRF's arm angle is minus its reading, the endstop at its reading " +
         rrf_number(geometry::radians_to_degrees(endstop_reading_rad(fm.machine, joint))) + " deg";
}

}  // namespace

std::vector<std::string> rrf_rotary_lines(const RrfRotaryDelta& delta) {
  std::string steps;
  for (std::size_t k = 0; k < 3; ++k) {
    if (delta.steps_per_deg[k]) {
      steps += " " + std::string(1, kRrfDriveLetters[k]) + rrf_number(*delta.steps_per_deg[k]);
    }
  }
  return {
      "M669 K10 U" + list3(delta.arm_lengths_mm) + " L" + list3(delta.rod_lengths_mm) + " H" +
          list3(delta.bearing_heights_mm) + " A" + rrf_number(delta.min_arm_angle_deg) + ":" +
          rrf_number(delta.max_arm_angle_deg) + " R" + rrf_number(delta.radius_mm) + " B" +
          rrf_number(delta.print_radius_mm) + " X" + rrf_number(delta.angle_corrections_deg[0]) +
          " Y" + rrf_number(delta.angle_corrections_deg[1]) + " Z" +
          rrf_number(delta.angle_corrections_deg[2]) +
          " ; rotary delta: arms and rods A:B:C (mm), pivot heights (mm), arm angles min:max "
          "(deg, up positive), pivot radius less the effector's (mm), printable radius (mm), "
          "arm angle corrections (deg)",
      "M666 X" + rrf_number(delta.endstop_adjustments_deg[0]) + " Y" +
          rrf_number(delta.endstop_adjustments_deg[1]) + " Z" +
          rrf_number(delta.endstop_adjustments_deg[2]) + " ; endstop corrections (deg)",
      steps.empty() ? "; M92: the machine file gives no steps per degree: set them here"
                    : "M92" + steps + " ; motor steps per degree of arm",
      "M203 " + per_drive(delta.max_speed_mm_per_min) + " ; maximum speeds (mm/min)",
      "M201 " + per_drive(delta.max_acceleration_mm_per_s2) + " ; maximum accelerations (mm/s^2)",
      "M208 Z" + rrf_number(delta.z_min_mm) + ":" + rrf_number(delta.z_max_mm) + " ; Z range (mm)",
  };
}

ExportedFile write_rrf_rotary_delta(const FirmwareMachine& fm, const ExportContext& context) {
  TowerAssignment towers;
  const RrfRotaryDelta delta = rotary_settings(fm, towers);
  ExportedFile file;
  file.text += header_comment(fm, context, "; ");
  file.text +=
      "; RepRapFirmware 3 config.g lines: they replace the kinematics, M92, M203, M201 and M208 "
      "lines of config.g; the firmware needs rotary delta support (SUPPORT_ROTARY_DELTA)\n";
  for (int tower = 0; tower < 3; ++tower) file.text += arm_line(fm, towers, tower) + "\n";
  file.text +=
      "; Each motor counts up as its arm rises (set M569 S so); the arms home up to their "
      "endstops (homedelta.g)\n";
  for (const std::string& line : rrf_rotary_lines(delta)) file.text += line + "\n";
  file.text += std::string(kRotaryNotHeld) + "\n";
  file.warnings.push_back(
      "RRF's rotary delta (M669 K10) is left out of the Duet 2 WiFi/Ethernet firmware "
      "(SUPPORT_ROTARY_DELTA 0 in its Pins_DuetNG.h): run it on a board whose build has it");
  if (!delta.steps_per_deg[0] || !delta.steps_per_deg[1] || !delta.steps_per_deg[2]) {
    file.warnings.push_back(
        "the machine file gives no steps_per_unit for every arm: set M92 in config.g");
  }
  return file;
}

namespace {

// pkmkit's joint (arm) k is RRF's tower joint_of_arm[k]: the one pointing where arm k does.
std::array<int, 3> towers_of_arms(const RrfRotaryDelta& delta) {
  std::array<int, 3> tower_of_arm{-1, -1, -1};
  std::string directions;
  for (std::size_t tower = 0; tower < 3; ++tower) {
    const double angle = kRrfRotaryNominalAngles[tower] + delta.angle_corrections_deg[tower];
    directions += (tower > 0 ? ", " : "") + rrf_number(angle);
    for (int arm = 0; arm < 3; ++arm) {
      const double off = std::remainder(angle - pkmkit_arm_angle_deg(arm), 360.0);
      if (std::abs(off) < kAngleTolerance_deg) {
        tower_of_arm[static_cast<std::size_t>(arm)] = static_cast<int>(tower);
      }
    }
  }
  if (std::count(tower_of_arm.begin(), tower_of_arm.end(), -1) > 0) {
    throw RrfSettingRefused(
        "M669 X", "the arms point at " + directions +
                      " deg: pkmkit's rotary delta has them at -90, 30 and 150 deg (X60 Y60 "
                      "Z60), and RRF cannot turn its frame");
  }
  return tower_of_arm;
}

void check_equal(const std::array<double, 3>& values, const char* key, const char* what) {
  if (values[1] != values[0] || values[2] != values[0]) {
    throw RrfSettingRefused(key, std::string(what) + " of " + list3(values) +
                                     " mm: pkmkit's rotary delta has one for every arm");
  }
}

// An arm's speed (deg per mm) where the effector moves vertically at `pose`.
double arm_deg_per_mm(const kinematics::Kinematics& model, const geometry::Pose& pose, int arm) {
  kinematics::JointVector low(3), high(3);
  geometry::Pose up = pose;
  up.position_mm.z() += 0.5;
  geometry::Pose down = pose;
  down.position_mm.z() -= 0.5;
  if (!model.inverse(up, high).ok() || !model.inverse(down, low).ok()) return 1.0;
  return std::abs(geometry::radians_to_degrees(high[arm] - low[arm]));
}

// Where the effector is with every arm at its endstop (rad), or x 0 y 0 at M208's Z max where
// that is above it (RRF homes there, then moves down; pkmkit's home is inside the envelope).
geometry::Pose rotary_home(const kinematics::Kinematics& model,
                           const kinematics::JointVector& endstops, const RrfRotaryDelta& delta,
                           std::vector<std::string>& notes) {
  geometry::Pose home = geometry::Pose::from_mm_deg(0.0, 0.0, delta.z_min_mm);
  if (!model.forward(endstops, home).ok()) {
    throw RrfSettingRefused("M669 A", "the arms at their endstops hold the effector nowhere");
  }
  if (home.position_mm.z() > delta.z_max_mm) {
    notes.push_back("RRF homes the arms up to z " + rrf_number(home.position_mm.z()) +
                    " mm, above M208's Z max: home is x 0 y 0 at Z max");
    return geometry::Pose::from_mm_deg(0.0, 0.0, delta.z_max_mm);
  }
  for (int axis = 0; axis < 2; ++axis) {
    if (std::abs(home.position_mm[axis]) < 1e-9) home.position_mm[axis] = 0.0;
  }
  const double highest_rad = geometry::degrees_to_radians(-delta.min_arm_angle_deg);
  if (!lower_into_limits(model, {endstops[0], endstops[1], endstops[2]},
                         {highest_rad, highest_rad, highest_rad}, home)) {
    throw RrfSettingRefused("M669 A", "the arms at their endstops hold the effector nowhere");
  }
  return home;
}

}  // namespace

machine::ImportedMachine rrf_rotary_machine(const RrfRotaryDelta& delta) {
  check_equal(delta.arm_lengths_mm, "M669 U", "arms");
  check_equal(delta.rod_lengths_mm, "M669 L", "rods");
  if (delta.bearing_heights_mm != std::array<double, 3>{}) {
    throw RrfSettingRefused("M669 H", "pivots at heights " + list3(delta.bearing_heights_mm) +
                                          " mm: pkmkit's rotary delta has them at z 0, and "
                                          "RRF's Z would be another (set H0:0:0 and Z from the "
                                          "pivots' plane)");
  }
  const std::array<int, 3> tower_of_arm = towers_of_arms(delta);
  for (std::size_t tower = 0; tower < 3; ++tower) {
    const double endstop = delta.max_arm_angle_deg + delta.endstop_adjustments_deg[tower];
    if (!(endstop > delta.min_arm_angle_deg)) {
      throw RrfSettingRefused("M669 A", "arm " + std::string(1, kRrfTowerNames[tower]) +
                                            "'s endstop at " + rrf_number(endstop) +
                                            " deg is not above A's min " +
                                            rrf_number(delta.min_arm_angle_deg) + " deg");
    }
  }
  kinematics::RotaryDeltaForm form;
  form.base_radius_mm = std::max(delta.radius_mm, 0.0);
  form.platform_radius_mm = std::max(-delta.radius_mm, 0.0);
  form.arm_length_mm = delta.arm_lengths_mm[0];
  form.forearm_length_mm = delta.rod_lengths_mm[0];
  const std::unique_ptr<kinematics::Kinematics> model = kinematics::make_form_kinematics(form);
  machine::ImportedMachine result;
  result.kinematics_section = machine::kinematics_toml(*model, machine::LengthUnit::mm);
  // Every arm at its endstop: where the rate of a vertical move is measured.
  kinematics::JointVector endstops(3);
  for (int arm = 0; arm < 3; ++arm) {
    const std::size_t tower = static_cast<std::size_t>(tower_of_arm[static_cast<std::size_t>(arm)]);
    endstops[arm] = -geometry::degrees_to_radians(delta.max_arm_angle_deg +
                                                  delta.endstop_adjustments_deg[tower]);
  }
  const geometry::Pose home = rotary_home(*model, endstops, delta, result.notes);
  for (int arm = 0; arm < 3; ++arm) {
    const std::size_t tower = static_cast<std::size_t>(tower_of_arm[static_cast<std::size_t>(arm)]);
    machine::ImportedJoint joint;
    joint.name = std::string("arm_") + static_cast<char>(std::tolower(kRrfDriveLetters[tower]));
    joint.angular = true;
    joint.min = geometry::radians_to_degrees(endstops[arm]);
    joint.max = -delta.min_arm_angle_deg;
    joint.home = joint.min;
    const double rate = arm_deg_per_mm(*model, home, arm);
    joint.max_velocity = rate * delta.max_speed_mm_per_min / 60.0;
    joint.max_acceleration = rate * delta.max_acceleration_mm_per_s2;
    joint.steps_per_unit = delta.steps_per_deg[tower];
    result.joints.push_back(joint);
  }
  result.max_feed_per_min = delta.max_speed_mm_per_min;
  result.max_acceleration = delta.max_acceleration_mm_per_s2;
  const double b = delta.print_radius_mm;
  result.envelope_min = std::vector<double>{-b, -b, delta.z_min_mm};
  result.envelope_max = std::vector<double>{b, b, delta.z_max_mm};
  result.home =
      std::vector<double>{home.position_mm.x(), home.position_mm.y(), home.position_mm.z()};
  result.home_seed_z = home.position_mm.z();
  result.notes.push_back(
      "joints arm_* are RRF's drives, in pkmkit's order (the arm towards -90 deg first); a "
      "reading is minus RRF's arm angle, its min the endstop (M669 A max + M666), home there");
  result.notes.push_back(
      "RRF limits no arm's own speed: each joint takes M203 Z and M201 Z times its rate in a "
      "vertical move at home");
  return result;
}

}  // namespace pkm::firmware
