// The klipper target; its cable robot is klipper_winch.cpp. Klipper's delta kinematics
// (klippy/kinematics/delta.py, klippy/chelper/kin_delta.c), as docs/firmware-klipper.md reads them:
// tower i stands at delta_radius from the origin at `angle` deg counter-clockwise from +X; its
// stepper's coordinate is z + sqrt(arm_length^2 - the tool's horizontal distance to the tower^2);
// homing sets it to position_endstop + sqrt(arm_length^2 - delta_radius^2), and the carriage never
// goes above that.
#include "pkm/firmware/klipper.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "pkm/firmware/klipper_import.hpp"
#include "pkm/firmware/klipper_winch.hpp"
#include "pkm/firmware/one_circle_delta.hpp"
#include "pkm/geometry/pose.hpp"

namespace pkm::firmware {
namespace {

constexpr std::array<const char*, 3> kSteppers = {"stepper_a", "stepper_b", "stepper_c"};
// The steps written: a rotation_distance for 200 full steps per turn at 16 microsteps.
constexpr int kFullSteps = 200;
constexpr int kMicrosteps = 16;

// The delta in Klipper's own terms (mm, deg, mm/s).
struct KlipperDelta {
  double radius = 0.0;
  std::array<double, 3> angle_deg{}, arm{}, endstop{}, endstop_reading{};
  double print_radius = 0.0, minimum_z = 0.0;
  double max_velocity = 0.0, max_accel = 0.0, max_z_velocity = 0.0, max_z_accel = 0.0;
};

std::string millimetres(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.6f", value);
  return text;
}

// The tower radii, one delta_radius, or the refusal naming them and what the nearest delta
// Klipper holds would cost.
std::array<double, 3> tower_radii(const FirmwareMachine& firmware) {
  const auto& form = std::get<kinematics::LinearDeltaForm>(firmware.form.geometry);
  std::array<double, 3> radii{};
  for (int i = 0; i < 3; ++i) radii[i] = form.towers[i].column_mm.norm();
  return radii;
}

double common_radius(const FirmwareMachine& firmware) {
  const std::array<double, 3> radii = tower_radii(firmware);
  const double radius = (radii[0] + radii[1] + radii[2]) / 3.0;
  if (towers_on_one_circle(std::get<kinematics::LinearDeltaForm>(firmware.form.geometry)))
    return radius;
  std::string text = firmware.machine.source() +
                     ": klipper's delta puts every tower at one delta_radius from the origin; "
                     "this machine's towers (their rods' columns) are " +
                     millimetres(radii[0]) + ", " + millimetres(radii[1]) + " and " +
                     millimetres(radii[2]) +
                     " mm from it, and Klipper's delta has no setting that moves the origin";
  if (!firmware.cost) {
    const ApproximationCost cost =
        nearest_delta_on_one_circle(firmware, "klipper's delta_radius").cost.value();
    const Eigen::Vector3d& at = cost.worst_at.position_mm;
    text +=
        ". The nearest delta it holds (one delta_radius; angles, rods and endstops fitted over " +
        std::to_string(cost.samples) + " workspace poses) would cost a tool error of up to " +
        millimetres(cost.worst_tool_error_mm) + " mm (at x " + millimetres(at.x()) + " y " +
        millimetres(at.y()) + " z " + millimetres(at.z()) + "); --approximate writes it";
  }
  throw ExportRefused(text);
}

// The reading at which joint i's carriage meets its endstop: its home switch (towards max), else
// its max (Klipper's carriages never go above their endstops).
double endstop_reading(const machine::JointSpec& joint, const std::string& source) {
  if (!joint.home_switch) return joint.max;
  if (!joint.home_switch->toward_max) {
    throw ExportRefused(
        source + ": joint '" + joint.name +
        "' homes downwards; klipper's delta homes every carriage up to its endstop");
  }
  return joint.home_switch->position;
}

// The largest circle about the origin inside the envelope's (else the reach's) x y.
double inscribed_radius(const machine::Machine& machine) {
  const machine::CartesianLimits& limits = machine.cartesian();
  geometry::Vector6d low = limits.envelope_min, high = limits.envelope_max;
  if (!low.head<2>().allFinite() || !high.head<2>().allFinite()) {
    const machine::PoseBox reach = machine::reach_box(machine);
    low = reach.min;
    high = reach.max;
  }
  return std::min({-low.x(), high.x(), -low.y(), high.y()});
}

double lowest_z(const machine::Machine& machine) {
  const double envelope = machine.cartesian().envelope_min.z();
  return std::isfinite(envelope) ? envelope : machine::reach_box(machine).min.z();
}

void check_delta(const KlipperDelta& delta, const std::string& source) {
  for (int i = 0; i < 3; ++i) {
    if (delta.arm[i] <= delta.radius) {
      throw ExportRefused(source + ": tower " + std::to_string(i + 1) + "'s rod " +
                          millimetres(delta.arm[i]) + " mm is not longer than delta_radius " +
                          millimetres(delta.radius) + " mm, as klipper's delta requires");
    }
    if (delta.endstop[i] <= 0.0) {
      throw ExportRefused(source + ": " + kSteppers[i] + "'s position_endstop would be " +
                          millimetres(delta.endstop[i]) +
                          " mm (the tool's z at x = y = 0 with that carriage at its endstop); "
                          "klipper's delta needs it above 0 (z up from the bed)");
    }
  }
  if (delta.print_radius <= 0.0) {
    throw ExportRefused(source + ": the work envelope does not hold x = y = 0; klipper's " +
                        "print_radius is a circle about the origin");
  }
  const double max_z = *std::min_element(delta.endstop.begin(), delta.endstop.end());
  if (delta.minimum_z > max_z) {
    throw ExportRefused(source + ": the envelope's lowest z " + millimetres(delta.minimum_z) +
                        " mm is above the lowest position_endstop " + millimetres(max_z) + " mm");
  }
}

KlipperDelta klipper_delta(const FirmwareMachine& firmware) {
  const machine::Machine& machine = firmware.machine;
  const auto& form = std::get<kinematics::LinearDeltaForm>(firmware.form.geometry);
  if (firmware.form.passthrough.count() > 0) {
    throw ExportRefused(machine.source() + ": klipper's delta moves x y z only; this machine has " +
                        std::to_string(firmware.form.passthrough.count()) +
                        " pass-through joint(s) it would not drive");
  }
  KlipperDelta delta;
  delta.radius = common_radius(firmware);
  for (int i = 0; i < 3; ++i) {
    const kinematics::LinearDeltaTower& tower = form.towers[i];
    double angle =
        geometry::radians_to_degrees(std::atan2(tower.column_mm.y(), tower.column_mm.x()));
    if (angle < 0.0) angle += 360.0;
    delta.angle_deg[i] = angle;
    delta.arm[i] = tower.rod_mm;
    delta.endstop_reading[i] = endstop_reading(machine.joints()[i], machine.source());
    // Klipper's stepper coordinate is the reading less the carriage offset.
    delta.endstop[i] = delta.endstop_reading[i] - tower.carriage_offset_mm -
                       std::sqrt(tower.rod_mm * tower.rod_mm - delta.radius * delta.radius);
  }
  delta.print_radius = inscribed_radius(machine);
  delta.minimum_z = lowest_z(machine);
  delta.max_velocity = machine.cartesian().max_feed_mm_per_s();
  delta.max_accel = machine.cartesian().max_acceleration_mm_per_s2;
  delta.max_z_velocity = delta.max_velocity;
  delta.max_z_accel = delta.max_accel;
  for (int i = 0; i < 3; ++i) {
    delta.max_z_velocity = std::min(delta.max_z_velocity, machine.joints()[i].max_velocity);
    delta.max_z_accel = std::min(delta.max_z_accel, machine.joints()[i].max_acceleration);
  }
  check_delta(delta, machine.source());
  return delta;
}

std::string option(const std::string& key, double value, const std::string& comment) {
  return key + ": " + klipper_number(value) + "  # " + comment + "\n";
}

std::string printer_section(const KlipperDelta& delta) {
  std::string text = "[printer]\nkinematics: delta\n";
  text += option("max_velocity", delta.max_velocity, "mm/s: the machine's max_feed");
  text += option("max_accel", delta.max_accel, "mm/s^2: the machine's max_acceleration");
  text += option("max_z_velocity", delta.max_z_velocity,
                 "mm/s: a z move drives every carriage at the tool's speed: the slowest "
                 "joint's max_velocity");
  text +=
      option("max_z_accel", delta.max_z_accel, "mm/s^2: the same for the joints' accelerations");
  text += option("delta_radius", delta.radius,
                 "mm: each tower's rod column from the origin (the effector's offset folded in)");
  text += option("print_radius", delta.print_radius,
                 "mm: the largest circle about the origin inside the work envelope");
  text += option("minimum_z_position", delta.minimum_z, "mm: the work envelope's lowest z");
  return text;
}

std::string stepper_section(const FirmwareMachine& firmware, const KlipperDelta& delta, int i,
                            std::vector<std::string>& warnings) {
  const machine::JointSpec& joint = firmware.machine.joints()[i];
  constexpr std::array<const char*, 3> kOrdinals = {"first", "second", "third"};
  std::string text =
      std::string("\n[") + kSteppers[i] + "]  # the machine's " + kOrdinals[i] + " joint\n";
  text += option("angle", delta.angle_deg[i], "deg counter-clockwise from +X");
  text += option("arm_length", delta.arm[i], "mm: the rod, joint to joint");
  text += option("position_endstop", delta.endstop[i],
                 "mm: the tool's z at x = y = 0 with this carriage at its endstop (joint reading " +
                     klipper_number(delta.endstop_reading[i]) + " mm)");
  return text + klipper_steps(joint, kSteppers[i], warnings);
}

ExportedFile write_klipper(const FirmwareMachine& firmware, const ExportContext& context) {
  if (form_kind(firmware.form.geometry) == FormKind::cable_robot) {
    return write_klipper_winch(firmware, context);
  }
  if (form_kind(firmware.form.geometry) == FormKind::rotary_delta) {
    throw ExportRefused(
        firmware.machine.source() +
        ": klipper's rotary_delta measures z up from the bed, with the shoulders at "
        "shoulder_height > 0 above it and every position_endstop at z >= 0; pkmkit's rotary delta "
        "has its pivots at z = 0 and the tool below them, so Klipper's frame would be this "
        "machine's shifted up by the shoulder height. Not exported: drive it with pkmkit's joint "
        "output, or move the frame in the machine file when pkmkit's rotary delta has an offset");
  }
  if (context.approximate &&
      !towers_on_one_circle(std::get<kinematics::LinearDeltaForm>(firmware.form.geometry))) {
    const FirmwareMachine nearest = nearest_delta_on_one_circle(firmware, "klipper's delta_radius");
    ExportedFile file = write_klipper(nearest, context);
    file.cost = nearest.cost;
    return file;
  }
  const KlipperDelta delta = klipper_delta(firmware);
  ExportedFile file;
  file.text += header_comment(firmware, context, "# ");
  file.text +=
      "# Klipper's delta (klippy/kinematics/delta.py). Merge into printer.cfg, or [include] this\n"
      "# file: Klipper merges sections of one name, so your pins and homing speeds stay yours.\n"
      "# Klipper checks a circle (print_radius, and arm_length - delta_radius) and z, not the\n"
      "# machine's envelope box or its joints' min; a SAVE_CONFIG block below your settings\n"
      "# overrides them.\n\n";
  file.text += printer_section(delta);
  for (int i = 0; i < 3; ++i) file.text += stepper_section(firmware, delta, i, file.warnings);
  return file;
}

}  // namespace

std::string klipper_steps(const machine::JointSpec& joint, const std::string& section,
                          std::vector<std::string>& warnings) {
  if (!joint.steps_per_unit) {
    warnings.push_back(section + ": the machine file gives joint '" + joint.name +
                       "' no steps_per_unit: set rotation_distance and microsteps");
    return "#rotation_distance:  # the machine file gives no steps_per_unit: set it\n";
  }
  std::string text = option("rotation_distance", kFullSteps * kMicrosteps / *joint.steps_per_unit,
                            "mm per motor turn: " + klipper_number(*joint.steps_per_unit) +
                                " steps/mm at the microsteps below");
  text += "microsteps: " + std::to_string(kMicrosteps) + "\n";
  text += "full_steps_per_rotation: " + std::to_string(kFullSteps) + "\n";
  return text;
}

std::string klipper_number(double value) {
  char text[64];
  for (int decimals = 0; decimals <= 12; ++decimals) {
    std::snprintf(text, sizeof text, "%.*f", decimals, value);
    if (std::abs(std::strtod(text, nullptr) - value) <= 1e-9) {
      const std::string written = text;
      return std::strtod(text, nullptr) == 0.0 ? "0" : written;
    }
  }
  std::snprintf(text, sizeof text, "%.17g", value);
  return text;
}

Target klipper_target() {
  return Target{"klipper",
                "printer.cfg",
                {FormKind::linear_delta, FormKind::rotary_delta, FormKind::cable_robot},
                write_klipper,
                read_klipper};
}

}  // namespace pkm::firmware
