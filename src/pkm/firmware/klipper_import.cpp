#include "pkm/firmware/klipper_import.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <sstream>

#include "pkm/firmware/klipper.hpp"
#include "pkm/firmware/klipper_cfg.hpp"
#include "pkm/firmware/klipper_winch.hpp"
#include "pkm/firmware/rrf_delta.hpp"
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

}  // namespace

std::optional<double> klipper_steps_per_mm(KlipperConfig& config, const std::string& section,
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
  // Klipper before 2021 had step_distance (mm per step) where it now has rotation_distance.
  if (const std::optional<double> step = config.number(section, "step_distance");
      step && !distance) {
    if (*step <= 0.0) config.fail(section, "step_distance", "must be above 0");
    notes.push_back("[" + section + "] step_distance (older Klipper's key): " +
                    klipper_number(1.0 / *step) + " steps/mm");
    return 1.0 / *step;
  }
  if (!distance || !microsteps) {
    notes.push_back("[" + section + "] has no rotation_distance and microsteps: no steps_per_unit");
    return std::nullopt;
  }
  return full_steps * *microsteps * gearing / *distance;
}

namespace {

std::array<TowerSettings, 3> read_towers(KlipperConfig& config, double radius,
                                         std::vector<std::string>& notes) {
  std::array<TowerSettings, 3> towers;
  // Klipper before 2019 read one rod length from [printer] delta_arm_length.
  const std::optional<double> old_arm = config.number("printer", "delta_arm_length");
  if (old_arm && !config.number("stepper_a", "arm_length")) {
    notes.push_back("[printer] delta_arm_length (older Klipper's key) is every tower's arm_length");
  }
  const double arm_a = old_arm && !config.number("stepper_a", "arm_length")
                           ? *old_arm
                           : config.required("stepper_a", "arm_length");
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
    tower.steps_per_mm = klipper_steps_per_mm(config, section, notes);
  }
  return towers;
}

// The kinematics line: delta, or why not.
void check_kinematics(KlipperConfig& config) {
  const std::optional<std::string> kinematics = config.text("printer", "kinematics");
  if (!kinematics) config.fail("printer", "kinematics", "must be given");
  if (*kinematics == "delta" || *kinematics == "winch") return;
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
              "'" + *kinematics +
                  "': pkmkit imports Klipper's delta (linear delta) and winch (cable robot) only");
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

// The tool with every carriage at its endstop (Klipper's home position), none where the
// carriages hold it nowhere. `lowered`: the same pose lowered by rounding's worth (from 1e-9 mm)
// until no carriage's reading passes its endstop, as the machine file's check of its home reads
// it (towers of different rods or endstops home off x = y = 0, where the solution's noise can put
// a carriage 1e-13 mm past its endstop).
std::optional<geometry::Pose> home_pose(const kinematics::Kinematics& model,
                                        const machine::ImportedMachine& imported, double seed_z,
                                        bool lowered) {
  kinematics::JointVector joints(3);
  std::array<double, 3> lowest{}, highest{};
  for (std::size_t i = 0; i < 3; ++i) {
    joints[static_cast<Eigen::Index>(i)] = imported.joints[i].home;
    lowest[i] = imported.joints[i].min;
    highest[i] = imported.joints[i].max;
  }
  geometry::Pose pose = geometry::Pose::from_mm_deg(0.0, 0.0, seed_z);
  if (!model.forward(joints, pose).ok()) return std::nullopt;
  // x and y within 1e-9 mm of 0 are 0 (the file would read 1e-14), before the lowering: a
  // rounding after it could put a carriage past its endstop again.
  for (int axis = 0; axis < 2; ++axis) {
    if (std::abs(pose.position_mm[axis]) < 1e-9) pose.position_mm[axis] = 0.0;
  }
  if (lowered && !lower_into_limits(model, lowest, highest, pose)) return std::nullopt;
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
  if (config.text("printer", "kinematics") == "winch") return read_klipper_winch(config, source);
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
    // cos 90 deg is 6e-17, not 0: a machine file would read "1.07e-14" for a tower on the y axis.
    form.towers[i].column_mm = form.towers[i].column_mm.unaryExpr(
        [](double value) { return std::abs(value) < 1e-12 ? 0.0 : value; });
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
  const std::optional<geometry::Pose> endstops = home_pose(*model, imported, max_z, false);
  const double top = std::max(max_z, endstops ? endstops->position_mm.z() : max_z);
  if (const std::optional<geometry::Pose> home = home_pose(*model, imported, max_z, true)) {
    const Eigen::Vector3d& at = home->position_mm;
    imported.home = std::vector<double>{at.x(), at.y(), at.z()};
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
