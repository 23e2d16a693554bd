#include "pkm/firmware/klipper_import.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <sstream>

#include "pkm/firmware/klipper.hpp"
#include "pkm/firmware/klipper_cfg.hpp"
#include "pkm/firmware/target.hpp"
#include "pkm/kinematics/firmware_form.hpp"
#include "pkm/machine/machine.hpp"
#include "pkm/machine/machine_writer.hpp"

namespace pkm::firmware {
namespace {

constexpr std::array<const char*, 3> kSteppers = {"stepper_a", "stepper_b", "stepper_c"};
// Klipper's towers when a stepper gives no angle (delta.py).
constexpr std::array<double, 3> kDefaultAngles = {210.0, 330.0, 90.0};

// One tower's settings; stepper_b and stepper_c default to stepper_a's arm and endstop.
struct TowerSettings {
  double angle_deg = 0.0, arm = 0.0, endstop = 0.0;
  std::optional<double> steps_per_mm;
};

// Klipper's steps per mm: full_steps_per_rotation (200) x microsteps x gear_ratio over
// rotation_distance; none when rotation_distance or microsteps is missing.
std::optional<double> steps_per_mm(KlipperConfig& config, const std::string& section,
                                   std::vector<std::string>& notes) {
  const std::optional<double> distance = config.number(section, "rotation_distance");
  const std::optional<double> microsteps = config.number(section, "microsteps");
  const double full_steps = config.number(section, "full_steps_per_rotation").value_or(200.0);
  double gearing = 1.0;
  if (const std::optional<std::string> ratio = config.text(section, "gear_ratio")) {
    std::string pairs = *ratio;
    std::replace(pairs.begin(), pairs.end(), ',', '\n');
    std::istringstream lines(pairs);
    for (std::string pair; std::getline(lines, pair);) {
      const std::size_t colon = pair.find(':');
      const std::optional<double> driven = klipper_float(pair.substr(0, colon));
      const std::optional<double> driving =
          colon == std::string::npos ? std::nullopt : klipper_float(pair.substr(colon + 1));
      if (!driven || !driving || *driving <= 0.0) {
        config.fail(section, "gear_ratio", "'" + *ratio + "' is not a list of a:b ratios");
      }
      gearing *= *driven / *driving;
    }
  }
  if (distance && *distance <= 0.0) config.fail(section, "rotation_distance", "must be above 0");
  if (!distance || !microsteps) {
    notes.push_back("[" + section + "] has no rotation_distance and microsteps: no steps_per_unit");
    return std::nullopt;
  }
  return full_steps * *microsteps * gearing / *distance;
}

std::array<TowerSettings, 3> read_towers(KlipperConfig& config, double radius,
                                         std::vector<std::string>& notes) {
  std::array<TowerSettings, 3> towers;
  const double arm_a = config.required("stepper_a", "arm_length");
  const double endstop_a = config.required("stepper_a", "position_endstop");
  for (int i = 0; i < 3; ++i) {
    const std::string section = kSteppers[i];
    TowerSettings& tower = towers[i];
    tower.angle_deg = config.number(section, "angle").value_or(kDefaultAngles[i]);
    tower.arm = config.number(section, "arm_length").value_or(arm_a);
    tower.endstop = config.number(section, "position_endstop").value_or(endstop_a);
    if (tower.arm <= radius) {
      config.fail(section, "arm_length",
                  klipper_number(tower.arm) + " mm must be above delta_radius " +
                      klipper_number(radius) + " mm");
    }
    if (tower.endstop <= 0.0) config.fail(section, "position_endstop", "must be above 0");
    tower.steps_per_mm = steps_per_mm(config, section, notes);
  }
  return towers;
}

// The kinematics line: delta, or why not.
void check_kinematics(KlipperConfig& config) {
  const std::optional<std::string> kinematics = config.text("printer", "kinematics");
  if (!kinematics) config.fail("printer", "kinematics", "must be given");
  if (*kinematics == "delta") return;
  if (*kinematics == "rotary_delta") {
    config.fail("printer", "kinematics",
                "rotary_delta measures z up from the bed with the shoulders shoulder_height above "
                "it; pkmkit's rotary delta has its pivots at z = 0, so the machine would not be "
                "Klipper's frame: not imported");
  }
  if (*kinematics == "deltesian") {
    config.fail("printer", "kinematics", "deltesian: pkmkit has no model of that form");
  }
  config.fail("printer", "kinematics",
              "'" + *kinematics + "': pkmkit imports Klipper's delta (linear delta) only");
}

machine::ImportedJoint tower_joint(int i, const TowerSettings& tower, double radius,
                                   double minimum_z, double max_z_velocity, double max_z_accel) {
  machine::ImportedJoint joint;
  joint.name = kSteppers[i];
  // The carriage's reading is Klipper's stepper coordinate: z plus the rod's height, never below
  // the tool's lowest z; it homes to, and never passes, its endstop.
  joint.max = tower.endstop + std::sqrt(tower.arm * tower.arm - radius * radius);
  joint.min = minimum_z;
  joint.home = joint.max;
  joint.max_velocity = max_z_velocity;
  joint.max_acceleration = max_z_accel;
  joint.steps_per_unit = tower.steps_per_mm;
  return joint;
}

// Klipper's home: every carriage at its endstop, its pose by the model's forward kinematics
// (none where the endstops meet in no pose), x and y within 1e-9 mm of 0 written as 0. Each
// joint's max is raised to the model's reading at that pose where rounding (the round trip's
// 1e-13 mm, the 1e-9 mm to 0) put it above: else a calibrated delta's home (distinct endstops)
// would pass a limit by that rounding, and pkmkit refuse it.
std::optional<geometry::Pose> klipper_home(const kinematics::Kinematics& model,
                                           machine::ImportedMachine& imported, double seed_z) {
  kinematics::JointVector joints(3), back(3);
  for (int i = 0; i < 3; ++i) joints[i] = imported.joints[i].home;
  geometry::Pose pose = geometry::Pose::from_mm_deg(0.0, 0.0, seed_z);
  if (!model.forward(joints, pose).ok()) return std::nullopt;
  for (int axis = 0; axis < 2; ++axis) {
    if (std::abs(pose.position_mm[axis]) < 1e-9) pose.position_mm[axis] = 0.0;
  }
  if (!model.inverse(pose, back).ok()) return std::nullopt;
  for (int i = 0; i < 3; ++i) {
    machine::ImportedJoint& joint = imported.joints[i];
    if (back[i] > joint.max && back[i] - joint.max < 1e-7) joint.max = back[i];
  }
  return pose;
}

}  // namespace

machine::ImportedMachine read_klipper(std::string_view text, const std::string& source) {
  KlipperConfig config(text, source);
  if (config.section("printer") == nullptr) {
    std::string includes;
    for (const std::string& include : config.includes()) includes += " " + include;
    throw FirmwareFileError(source + ":1: no [printer] section: not a Klipper printer.cfg" +
                            (includes.empty() ? std::string()
                                              : " (it includes" + includes +
                                                    ": import the file that holds [printer])"));
  }
  check_kinematics(config);
  machine::ImportedMachine imported;
  imported.source = source;
  imported.origin = "Imported by `pkm import klipper` from " + source + " (kinematics delta).";
  imported.name = "Klipper delta (" + source.substr(source.find_last_of('/') + 1) + ")";
  const double max_velocity = config.required("printer", "max_velocity");
  const double max_accel = config.required("printer", "max_accel");
  const double max_z_velocity = config.number("printer", "max_z_velocity").value_or(max_velocity);
  const double max_z_accel = config.number("printer", "max_z_accel").value_or(max_accel);
  const double radius = config.required("printer", "delta_radius");
  if (radius <= 0.0) config.fail("printer", "delta_radius", "must be above 0");
  const double print_radius = config.number("printer", "print_radius").value_or(radius);
  const double minimum_z = config.number("printer", "minimum_z_position").value_or(0.0);
  const std::array<TowerSettings, 3> towers = read_towers(config, radius, imported.notes);

  kinematics::LinearDeltaForm form;
  double max_z = towers[0].endstop;
  for (int i = 0; i < 3; ++i) {
    const double angle = geometry::degrees_to_radians(towers[i].angle_deg);
    form.towers[i].column_mm = radius * Eigen::Vector2d(std::cos(angle), std::sin(angle));
    form.towers[i].rod_mm = towers[i].arm;
    imported.joints.push_back(
        tower_joint(i, towers[i], radius, minimum_z, max_z_velocity, max_z_accel));
    max_z = std::min(max_z, towers[i].endstop);
  }
  const std::unique_ptr<kinematics::Kinematics> model = kinematics::make_form_kinematics(form);
  imported.kinematics_section = machine::kinematics_toml(*model, machine::LengthUnit::mm);
  imported.max_feed_per_min = 60.0 * max_velocity;
  imported.max_acceleration = max_accel;
  imported.home_seed_z = max_z;
  // Klipper's z reaches the lowest endstop; its home (every carriage at its endstop) may be above.
  double top = max_z;
  if (const std::optional<geometry::Pose> home = klipper_home(*model, imported, max_z)) {
    const Eigen::Vector3d& at = home->position_mm;
    imported.home = std::vector<double>{at.x(), at.y(), at.z()};
    top = std::max(max_z, at.z());
  }
  imported.envelope_min = std::vector<double>{-print_radius, -print_radius, minimum_z};
  imported.envelope_max = std::vector<double>{print_radius, print_radius, top};
  imported.notes.push_back(
      "each carriage's reading is Klipper's stepper coordinate (z + the rod's height); its max is "
      "the endstop, its min minimum_z_position (Klipper has no carriage limits)");
  imported.notes.push_back(
      "the work envelope is the square around print_radius, from minimum_z_position to the lowest "
      "position_endstop");
  for (const std::string& note : config.unread()) imported.notes.push_back(note);
  return imported;
}

}  // namespace pkm::firmware
