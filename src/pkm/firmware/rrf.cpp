#include "pkm/firmware/rrf.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>

#include "pkm/firmware/one_circle_delta.hpp"
#include "pkm/firmware/rrf_config.hpp"
#include "pkm/firmware/rrf_delta.hpp"
#include "pkm/firmware/rrf_hangprinter.hpp"
#include "pkm/firmware/rrf_rotary.hpp"
#include "pkm/geometry/pose.hpp"

namespace pkm::firmware {
namespace {

// What the machine file says that RRF has no setting for (the same for every machine, so that an
// import exports the same text).
constexpr const char* kRrfNotHeld =
    "; Not held by RRF: the carriages' own speed and acceleration limits and their lowest "
    "readings (the joints' max_velocity, max_acceleration, min): RRF limits the effector's speed "
    "and acceleration along X Y (M203 X, M201 X) and along Z apart, keeps it above M208 Z and "
    "each carriage below its endstop\n"
    "; RRF keeps X Y within M665 B of x 0 y 0 and pulls a move beyond it back onto that circle: "
    "B is the largest such circle inside the machine's work envelope (its reach where it has "
    "none)";

// The joint reading (mm) at which the carriage of `joint` meets its endstop: its home switch,
// else the top of its travel. RRF homes a delta's carriages upwards only.
double endstop_reading(const machine::Machine& machine, int joint) {
  const machine::JointSpec& spec = machine.joints()[static_cast<std::size_t>(joint)];
  if (!spec.home_switch) return spec.max;
  if (!spec.home_switch->toward_max) {
    throw ExportRefused(machine.source() + ": joint '" + spec.name +
                        "' homes downwards to a switch; RRF's linear delta homes each carriage "
                        "up to an endstop at the top of its tower");
  }
  return spec.home_switch->position;
}

std::string millimetres(double value) {
  return rrf_number(value) + " mm";
}

// RRF's towers stand on one circle about the origin (M665 R): columns off it would need the
// frame moved or per-tower radii, which RRF has not.
double common_radius(const FirmwareMachine& fm, const kinematics::LinearDeltaForm& form) {
  std::array<double, 3> radii{};
  for (std::size_t k = 0; k < 3; ++k) radii[k] = form.towers[k].column_mm.norm();
  if (!towers_on_one_circle(form)) {
    throw ExportRefused(
        fm.machine.source() +
        ": rrf's linear delta puts its three towers on one circle about x 0 " +
        "y 0 (M665 R), and this machine's columns stand at " + millimetres(radii[0]) + ", " +
        millimetres(radii[1]) + " and " + millimetres(radii[2]) +
        " from it: RRF cannot move its frame or give a tower its own radius; --approximate "
        "writes the nearest delta on one circle and states the worst tool error that costs");
  }
  return (radii[0] + radii[1] + radii[2]) / 3.0;
}

// The settings for a linear delta machine, and which joint each tower is.
RrfLinearDelta linear_delta(const FirmwareMachine& fm, TowerAssignment& towers) {
  const auto& form = std::get<kinematics::LinearDeltaForm>(fm.form.geometry);
  const machine::Machine& machine = fm.machine;
  RrfLinearDelta delta;
  delta.radius_mm = common_radius(fm, form);
  std::array<double, 3> angles{};
  for (std::size_t k = 0; k < 3; ++k) {
    const Eigen::Vector2d& column = form.towers[k].column_mm;
    angles[k] = geometry::radians_to_degrees(std::atan2(column.y(), column.x()));
  }
  towers = assign_towers(angles, kRrfNominalTowerAngles);
  delta.angle_corrections_deg = towers.corrections_deg;
  // Each carriage's RRF motor position at its endstop (its joint reading there less its
  // carriage offset) = H + sqrt(L^2 - R^2) + endstop correction; H takes their mean.
  std::array<double, 3> homed{};
  for (std::size_t tower = 0; tower < 3; ++tower) {
    const int joint = towers.joint_of_tower[tower];
    const kinematics::LinearDeltaTower& column = form.towers[static_cast<std::size_t>(joint)];
    if (!(column.rod_mm > delta.radius_mm)) {
      throw ExportRefused(machine.source() + ": joint " + std::to_string(joint + 1) + "'s rod (" +
                          millimetres(column.rod_mm) + ") is not longer than the delta radius (" +
                          millimetres(delta.radius_mm) +
                          "): RRF's homed carriage height sqrt(L^2 - R^2) has no value");
    }
    delta.diagonals_mm[tower] = column.rod_mm;
    homed[tower] = endstop_reading(machine, joint) - column.carriage_offset_mm -
                   std::sqrt(column.rod_mm * column.rod_mm - delta.radius_mm * delta.radius_mm);
    delta.steps_per_mm[tower] = machine.joints()[static_cast<std::size_t>(joint)].steps_per_unit;
  }
  delta.homed_height_mm = (homed[0] + homed[1] + homed[2]) / 3.0;
  for (std::size_t tower = 0; tower < 3; ++tower) {
    delta.endstop_adjustments_mm[tower] = homed[tower] - delta.homed_height_mm;
  }
  const RrfBounds bounds = rrf_bounds(machine);
  delta.print_radius_mm = bounds.print_radius_mm;
  delta.z_min_mm = bounds.z_min_mm;
  delta.max_speed_mm_per_min.fill(machine.cartesian().max_feed_mm_per_min);
  delta.max_acceleration_mm_per_s2.fill(machine.cartesian().max_acceleration_mm_per_s2);
  return delta;
}

// "; drive X = tower A = joint 2 "tower_b": column x .. y .. mm, endstop at reading .. mm".
std::string tower_line(const FirmwareMachine& fm, const TowerAssignment& towers, int tower) {
  const int joint = towers.joint_of_tower[static_cast<std::size_t>(tower)];
  const auto& form = std::get<kinematics::LinearDeltaForm>(fm.form.geometry);
  const Eigen::Vector2d& column = form.towers[static_cast<std::size_t>(joint)].column_mm;
  return std::string("; drive ") + kRrfDriveLetters[static_cast<std::size_t>(tower)] + " = tower " +
         kRrfTowerNames[static_cast<std::size_t>(tower)] + " = joint " + std::to_string(joint + 1) +
         " \"" + fm.machine.joints()[static_cast<std::size_t>(joint)].name + "\": column x " +
         rrf_number(column.x()) + " y " + rrf_number(column.y()) + " mm, endstop at its reading " +
         millimetres(endstop_reading(fm.machine, joint));
}

ExportedFile write_linear_delta(const FirmwareMachine& fm, const ExportContext& context) {
  TowerAssignment towers;
  const RrfLinearDelta delta = linear_delta(fm, towers);
  ExportedFile file;
  file.text += header_comment(fm, context, "; ");
  file.text +=
      "; RepRapFirmware 3 config.g lines: they replace the kinematics, M92, M203, M201 and M208 "
      "lines of config.g\n";
  for (int tower = 0; tower < 3; ++tower) file.text += tower_line(fm, towers, tower) + "\n";
  file.text +=
      "; Each motor counts up as its carriage rises (set M569 S so); the carriages home up to "
      "their endstops (homedelta.g)\n";
  for (const std::string& line : rrf_delta_lines(delta)) file.text += line + "\n";
  file.text += std::string(kRrfNotHeld) + "\n";
  if (!delta.steps_per_mm[0] || !delta.steps_per_mm[1] || !delta.steps_per_mm[2]) {
    file.warnings.push_back(
        "the machine file gives no steps_per_unit for every tower: set M92 in config.g");
  }
  return file;
}

ExportedFile write(const FirmwareMachine& fm, const ExportContext& context) {
  if (std::holds_alternative<kinematics::CableRobotForm>(fm.form.geometry)) {
    return write_rrf_hangprinter(fm, context);
  }
  if (fm.form.passthrough.count() > 0) {
    throw ExportRefused(fm.machine.source() +
                        ": rrf's export writes the three towers only; this machine passes " +
                        std::to_string(fm.form.passthrough.count()) +
                        " more joint(s) through (declare them with M584 and M92 by hand)");
  }
  if (std::holds_alternative<kinematics::RotaryDeltaForm>(fm.form.geometry)) {
    return write_rrf_rotary_delta(fm, context);
  }
  const auto& form = std::get<kinematics::LinearDeltaForm>(fm.form.geometry);
  if (context.approximate && !towers_on_one_circle(form)) {
    const FirmwareMachine nearest = nearest_delta_on_one_circle(fm, "rrf's M665 R");
    ExportedFile file = write_linear_delta(nearest, context);
    file.cost = nearest.cost;
    return file;
  }
  return write_linear_delta(fm, context);
}

}  // namespace

Target rrf_target() {
  return Target{"rrf",
                "config.g",
                {FormKind::linear_delta, FormKind::rotary_delta, FormKind::cable_robot},
                write,
                [](std::string_view text, const std::string& source) {
                  return read_rrf_config(text, source);
                }};
}

}  // namespace pkm::firmware
