// Marlin's DELTA (docs/firmware-marlin.md): towers A B C (steppers X Y Z) at 210, 330 and 90 deg
// plus DELTA_TOWER_ANGLE_TRIM, on DELTA_RADIUS plus DELTA_RADIUS_TRIM_TOWER, rods
// DELTA_DIAGONAL_ROD plus DELTA_DIAGONAL_ROD_TRIM_TOWER; a carriage's position is
// z + sqrt(rod^2 - |tower - (x, y)|^2); G28 sets (X_HOME_POS, Y_HOME_POS, DELTA_HEIGHT) once each
// carriage has found its endstop and moved DELTA_ENDSTOP_ADJ (<= 0) from it.
#include <algorithm>
#include <cmath>
#include <numeric>

#include "pkm/firmware/marlin_forms.hpp"
#include "pkm/geometry/pose.hpp"
#include "pkm/machine/machine_writer.hpp"

namespace pkm::firmware {
namespace {

constexpr double kNominalDeg[3] = {210.0, 330.0, 90.0};
constexpr const char* kTowerLetters[3] = {"A", "B", "C"};

double wrapped_deg(double degrees) {
  double value = std::fmod(degrees + 180.0, 360.0);
  if (value < 0) value += 360.0;
  return value - 180.0;
}

double angle_deg(const Eigen::Vector2d& column) {
  return geometry::radians_to_degrees(std::atan2(column.y(), column.x()));
}

// The machine joint each Marlin tower takes: the assignment with the smallest largest angle trim.
StepperJoints nearest_towers(const kinematics::LinearDeltaForm& form) {
  StepperJoints best{0, 1, 2}, order{0, 1, 2};
  double best_worst = 1e9;
  do {
    double worst = 0.0;
    for (int k = 0; k < 3; ++k) {
      worst = std::max(worst, std::abs(wrapped_deg(angle_deg(form.towers[order[k]].column_mm) -
                                                   kNominalDeg[k])));
    }
    if (worst < best_worst - 1e-9) {
      best_worst = worst;
      best = order;
    }
  } while (std::next_permutation(order.begin(), order.end()));
  return best;
}

// The carriage's position (Marlin's scale: the machine's reading less the carriage offset) where
// its endstop trips: the joint's home switch, else the home pose's.
double endstop_position(const FirmwareMachine& fm, int joint) {
  const kinematics::LinearDeltaForm& form = std::get<kinematics::LinearDeltaForm>(fm.form.geometry);
  const kinematics::LinearDeltaTower& tower = form.towers[joint];
  const machine::JointSpec& spec = fm.machine.joints()[joint];
  if (spec.home_switch) {
    if (!spec.home_switch->toward_max) {
      throw ExportRefused(fm.machine.source() + ": joint '" + spec.name +
                          "' homes downwards (home_toward min); Marlin's DELTA homes every "
                          "carriage up to its endstop");
    }
    return spec.home_switch->position - tower.carriage_offset_mm;
  }
  const Eigen::Vector3d home = fm.machine.home().position_mm;
  const double reach2 =
      tower.rod_mm * tower.rod_mm - (home.head<2>() - tower.column_mm).squaredNorm();
  return home.z() + std::sqrt(std::max(reach2, 0.0));
}

struct DeltaSettings {
  StepperJoints joints{};
  double radius = 0, rod = 0, height = 0;
  std::array<double, 3> angle_trim{}, radius_trim{}, rod_trim{}, endstop_adj{};
};

DeltaSettings delta_settings(const FirmwareMachine& fm) {
  const kinematics::LinearDeltaForm& form = std::get<kinematics::LinearDeltaForm>(fm.form.geometry);
  DeltaSettings s;
  s.joints = nearest_towers(form);
  std::array<double, 3> radius{}, rod{}, column_rise{};
  for (int k = 0; k < 3; ++k) {
    const kinematics::LinearDeltaTower& tower = form.towers[s.joints[k]];
    radius[k] = tower.column_mm.norm();
    rod[k] = tower.rod_mm;
    if (radius[k] < 1e-6 || rod[k] <= radius[k]) {
      throw ExportRefused(fm.machine.source() + ": tower " + kTowerLetters[k] +
                          ": Marlin's DELTA needs each tower's column off the centre (X0 Y0) and "
                          "its rod longer than that distance");
    }
    s.angle_trim[k] = wrapped_deg(angle_deg(tower.column_mm) - kNominalDeg[k]);
    column_rise[k] = std::sqrt(rod[k] * rod[k] - radius[k] * radius[k]);
  }
  s.radius = (radius[0] + radius[1] + radius[2]) / 3.0;
  s.rod = (rod[0] + rod[1] + rod[2]) / 3.0;
  s.height = 1e300;
  for (int k = 0; k < 3; ++k) {
    s.radius_trim[k] = radius[k] - s.radius;
    s.rod_trim[k] = rod[k] - s.rod;
    s.height = std::min(s.height, endstop_position(fm, s.joints[k]) - column_rise[k]);
  }
  for (int k = 0; k < 3; ++k) {
    s.endstop_adj[k] = s.height + column_rise[k] - endstop_position(fm, s.joints[k]);
  }
  return s;
}

std::vector<double> as_list(const std::array<double, 3>& values) {
  return {values[0], values[1], values[2]};
}

std::string delta_geometry_defines(const DeltaSettings& s) {
  std::string text;
  text += define_line("DELTA_DIAGONAL_ROD", marlin_number(s.rod), "mm, rod joint to rod joint");
  text += define_line("DELTA_DIAGONAL_ROD_TRIM_TOWER", marlin_list(as_list(s.rod_trim)),
                      "mm added to the rod of tower A B C");
  text += define_line("DELTA_RADIUS", marlin_number(s.radius),
                      "mm, X0 Y0 to where a tower's rod hangs vertical over the tool");
  text += define_line("DELTA_RADIUS_TRIM_TOWER", marlin_list(as_list(s.radius_trim)),
                      "mm added to DELTA_RADIUS for tower A B C (no G-code sets these)");
  text += define_line("DELTA_TOWER_ANGLE_TRIM", marlin_list(as_list(s.angle_trim)),
                      "deg added to towers A B C at 210, 330, 90 deg");
  text += define_line("DELTA_HEIGHT", marlin_number(s.height),
                      "mm, the tool's Z at X0 Y0 once G28 has homed");
  text += define_line("DELTA_ENDSTOP_ADJ", marlin_list(as_list(s.endstop_adj)),
                      "mm each carriage moves from its endstop after homing (<= 0)");
  return text;
}

std::string delta_limit_defines(const FirmwareMachine& fm, const DeltaSettings& s,
                                std::vector<std::string>& warnings) {
  const WorkBox box = work_box(fm.machine);
  const double printable = std::min({-box.min.x(), box.max.x(), -box.min.y(), box.max.y()});
  if (printable <= 0.0) {
    throw ExportRefused(fm.machine.source() +
                        ": Marlin's DELTA keeps the tool within DELTA_PRINTABLE_RADIUS of X0 Y0; "
                        "this machine's work area does not contain X0 Y0");
  }
  if (box.max.z() > s.height + 1e-6) {
    warnings.push_back("Marlin keeps Z at or below DELTA_HEIGHT " + marlin_number(s.height) +
                       " mm (where G28 leaves the tool); the machine reaches Z " +
                       marlin_number(box.max.z()) + " mm");
  }
  std::string text;
  text += define_line("PRINTABLE_RADIUS", marlin_number(printable),
                      "mm: the largest circle about X0 Y0 inside the machine's work area");
  text += define_line("DELTA_PRINTABLE_RADIUS", marlin_number(printable), "older Marlin's name");
  text += define_line("DELTA_MAX_RADIUS", marlin_number(printable), "mm");
  text += define_line("MANUAL_X_HOME_POS", "0", "");
  text += define_line("MANUAL_Y_HOME_POS", "0", "");
  text += define_line("MANUAL_Z_HOME_POS", marlin_number(s.height), "DELTA_HEIGHT");
  text += define_line("X_BED_SIZE", marlin_number(2.0 * printable), "mm");
  text += define_line("Y_BED_SIZE", marlin_number(2.0 * printable), "mm");
  text += define_line("X_MIN_POS", marlin_number(-printable), "mm");
  text += define_line("Y_MIN_POS", marlin_number(-printable), "mm");
  text += define_line("X_MAX_POS", marlin_number(printable), "mm");
  text += define_line("Y_MAX_POS", marlin_number(printable), "mm");
  text += define_line("Z_MIN_POS", marlin_number(box.min.z()), "mm, the lowest tool Z");
  text += define_line("Z_MAX_POS", marlin_number(s.height), "mm: DELTA_HEIGHT");
  return text;
}

std::string delta_gcode_comments(const DeltaSettings& s) {
  auto pair = [](const char* letter, double value) {
    return std::string(" ") + letter + marlin_number(value);
  };
  std::string text = "// The same geometry on a running Marlin (send, then M500 to keep it):\n";
  text += "//   M665" + pair("L", s.rod) + pair("R", s.radius) + pair("H", s.height) +
          pair("X", s.angle_trim[0]) + pair("Y", s.angle_trim[1]) + pair("Z", s.angle_trim[2]) +
          pair("A", s.rod_trim[0]) + pair("B", s.rod_trim[1]) + pair("C", s.rod_trim[2]) + "\n";
  text += "//   M666" + pair("X", s.endstop_adj[0]) + pair("Y", s.endstop_adj[1]) +
          pair("Z", s.endstop_adj[2]) + "\n";
  if (s.radius_trim[0] != 0.0 || s.radius_trim[1] != 0.0 || s.radius_trim[2] != 0.0) {
    text += "//   DELTA_RADIUS_TRIM_TOWER has no G-code: compile it in.\n";
  }
  return text;
}

// Marlin's homeaxis moves a carriage by its DELTA_ENDSTOP_ADJ only when that is more than
// MIN_STEPS_PER_SEGMENT (6 by default) steps: a smaller one is not moved at all.
void warn_small_adjustments(const FirmwareMachine& fm, const DeltaSettings& s,
                            std::vector<std::string>& warnings) {
  for (int k = 0; k < 3; ++k) {
    const machine::JointSpec& joint = fm.machine.joints()[s.joints[k]];
    const double steps = joint.steps_per_unit.value_or(kMarlinStockSteps[0]);
    const double smallest = 6.0 / steps;
    if (s.endstop_adj[k] != 0.0 && std::abs(s.endstop_adj[k]) <= smallest) {
      warnings.push_back(std::string("DELTA_ENDSTOP_ADJ of tower ") + kTowerLetters[k] + " is " +
                         marlin_number(s.endstop_adj[k]) + " mm, within Marlin's 6 steps (" +
                         marlin_number(smallest) +
                         " mm), which it does not move: G28 leaves "
                         "that carriage that far off");
    }
  }
}

}  // namespace

ExportedFile write_marlin_delta(const FirmwareMachine& fm, const ExportContext& context) {
  if (fm.form.passthrough.count() > 0) {
    throw ExportRefused(fm.machine.source() +
                        ": Marlin's DELTA drives the three towers only; this machine has "
                        "pass-through joints");
  }
  const DeltaSettings settings = delta_settings(fm);
  ExportedFile file;
  file.text = marlin_preamble(fm, context, "DELTA");
  file.text += delta_geometry_defines(settings);
  file.text += delta_limit_defines(fm, settings, file.warnings);
  warn_small_adjustments(fm, settings, file.warnings);
  file.text += marlin_motion_defines(fm, settings.joints);
  file.text += delta_gcode_comments(settings);
  return file;
}

namespace {

// What a Configuration.h says of a delta, in Marlin's terms (absent trims are 0).
struct DeltaFile {
  double rod = 0, radius = 0, height = 0, printable = 0, z_min = 0;
  std::array<double, 3> angle_trim{}, radius_trim{}, rod_trim{}, adj{};
  Eigen::Vector2d home_xy = Eigen::Vector2d::Zero();
};

std::array<double, 3> optional_triple(const MarlinDefines& defines, const char* name) {
  const std::optional<std::vector<double>> values = defines.optional_list(name, 3);
  return values ? std::array{(*values)[0], (*values)[1], (*values)[2]} : std::array{0.0, 0.0, 0.0};
}

// X_HOME_POS as Marlin's Conditionals_post.h sets it for a delta: MANUAL_X_HOME_POS, else 0
// with BED_CENTER_AT_0_0, else the bed's middle.
double delta_home(const MarlinDefines& defines, const char axis) {
  const std::string letter(1, axis);
  if (const auto manual = defines.optional_number("MANUAL_" + letter + "_HOME_POS")) return *manual;
  if (defines.enabled("BED_CENTER_AT_0_0")) return 0.0;
  const auto min = defines.optional_number(letter + "_MIN_POS");
  const auto size = defines.optional_number(letter + "_BED_SIZE");
  return min && size ? *min + 0.5 * *size : 0.0;
}

DeltaFile read_delta_file(const MarlinDefines& defines) {
  for (const char* name : {"DELTA_DIAGONAL_ROD", "DELTA_RADIUS", "DELTA_HEIGHT"}) {
    if (!defines.enabled(name)) defines.missing(name, "DELTA", "the delta's geometry needs it");
  }
  DeltaFile file;
  file.rod = defines.number("DELTA_DIAGONAL_ROD");
  file.radius = defines.number("DELTA_RADIUS");
  file.height = defines.number("DELTA_HEIGHT");
  file.angle_trim = optional_triple(defines, "DELTA_TOWER_ANGLE_TRIM");
  file.radius_trim = optional_triple(defines, "DELTA_RADIUS_TRIM_TOWER");
  file.rod_trim = optional_triple(defines, "DELTA_DIAGONAL_ROD_TRIM_TOWER");
  file.adj = optional_triple(defines, "DELTA_ENDSTOP_ADJ");
  for (int k = 0; k < 3; ++k) {
    // Each tower's rod with its trim: a rod of 0 or less has no carriage height.
    const double rod = file.rod + file.rod_trim[k], radius = file.radius + file.radius_trim[k];
    if (!(rod > 0.0) || !std::isfinite(rod) || !std::isfinite(radius)) {
      const char* name =
          file.rod_trim[k] != 0.0 ? "DELTA_DIAGONAL_ROD_TRIM_TOWER" : "DELTA_DIAGONAL_ROD";
      throw FirmwareFileError(defines.source() + ":" + std::to_string(defines.line(name)) + ": " +
                              name + ": tower " + "ABC"[k] + "'s rod is " + marlin_number(rod) +
                              " mm (with its trim), radius " + marlin_number(radius) +
                              " mm: a rod must be longer than 0 mm");
    }
  }
  file.home_xy = Eigen::Vector2d(delta_home(defines, 'X'), delta_home(defines, 'Y'));
  // PRINTABLE_RADIUS is newer Marlin's name of DELTA_PRINTABLE_RADIUS.
  file.printable =
      defines.optional_number("PRINTABLE_RADIUS")
          .value_or(
              defines.optional_number("DELTA_PRINTABLE_RADIUS")
                  .value_or(defines.optional_number("DELTA_MAX_RADIUS").value_or(file.radius)));
  file.z_min = defines.optional_number("Z_MIN_POS").value_or(0.0);
  return file;
}

const std::vector<std::string> kDeltaDefinesRead = {"DELTA",
                                                    "DELTA_DIAGONAL_ROD",
                                                    "DELTA_RADIUS",
                                                    "DELTA_HEIGHT",
                                                    "DELTA_TOWER_ANGLE_TRIM",
                                                    "DELTA_RADIUS_TRIM_TOWER",
                                                    "DELTA_DIAGONAL_ROD_TRIM_TOWER",
                                                    "DELTA_ENDSTOP_ADJ",
                                                    "MANUAL_X_HOME_POS",
                                                    "MANUAL_Y_HOME_POS",
                                                    "MANUAL_Z_HOME_POS",
                                                    "BED_CENTER_AT_0_0",
                                                    "PRINTABLE_RADIUS",
                                                    "DELTA_PRINTABLE_RADIUS",
                                                    "DELTA_MAX_RADIUS",
                                                    "X_BED_SIZE",
                                                    "Y_BED_SIZE",
                                                    "X_MIN_POS",
                                                    "Y_MIN_POS",
                                                    "X_MAX_POS",
                                                    "Y_MAX_POS",
                                                    "Z_MIN_POS",
                                                    "Z_MAX_POS"};

// Tower k (Marlin's A B C) as the machine's joint `joint` of `form` and `imported`.
void add_tower(const DeltaFile& file, const StepperRates& rates, const std::string& name, int k,
               int joint, kinematics::LinearDeltaForm& form, machine::ImportedMachine& imported) {
  const double angle = geometry::degrees_to_radians(kNominalDeg[k] + file.angle_trim[k]);
  const double r = file.radius + file.radius_trim[k], rod = file.rod + file.rod_trim[k];
  kinematics::LinearDeltaTower& tower = form.towers[joint];
  tower.column_mm = Eigen::Vector2d(r * std::cos(angle), r * std::sin(angle));
  tower.rod_mm = rod;
  const double rise =
      std::sqrt(std::max(rod * rod - (file.home_xy - tower.column_mm).squaredNorm(), 0.0));
  machine::ImportedJoint& spec = imported.joints[joint];
  spec.name = name;
  spec.min = 0.0;
  spec.max = file.height + rise - file.adj[k];  // the endstop
  spec.max_velocity = rates.feed_mm_per_s[k];
  spec.max_acceleration = rates.acceleration_mm_per_s2[k];
  spec.home = file.height + rise;
  if (rates.steps_per_mm) spec.steps_per_unit = (*rates.steps_per_mm)[k];
}

}  // namespace

machine::ImportedMachine read_marlin_delta(const MarlinDefines& defines) {
  const DeltaFile file = read_delta_file(defines);
  const MarlinJointNames names = read_joint_names(defines, {"x", "y", "z"});
  const StepperRates rates = read_stepper_rates(defines, names, "DELTA");
  machine::ImportedMachine imported = imported_base(defines, kDeltaDefinesRead);
  kinematics::LinearDeltaForm form;
  imported.joints.resize(3);
  for (int k = 0; k < 3; ++k) {
    if (names.order[k] < 0) {
      joint_names_fail(defines, names,
                       std::string("stepper ") + "XYZ"[k] +
                           " = none: a delta's steppers drive "
                           "joints 1 to 3");
    }
    add_tower(file, rates, names.names[k], k, names.order[k], form, imported);
  }
  imported.kinematics_section =
      machine::kinematics_toml(*kinematics::make_form_kinematics(form), machine::LengthUnit::mm);
  imported.home = std::vector<double>{file.home_xy.x(), file.home_xy.y(), file.height};
  imported.envelope_min = std::vector<double>{-file.printable, -file.printable, file.z_min};
  imported.envelope_max = std::vector<double>{file.printable, file.printable, file.height};
  const auto& feed = rates.feed_mm_per_s;
  const auto& acceleration = rates.acceleration_mm_per_s2;
  imported.max_feed_per_min = 60.0 * *std::min_element(feed.begin(), feed.end());
  imported.max_acceleration =
      defines.optional_number("DEFAULT_ACCELERATION")
          .value_or(*std::min_element(acceleration.begin(), acceleration.end()));
  imported.notes.push_back(
      "carriage readings are Marlin's: z + sqrt(rod^2 - horizontal distance^2); each joint's max "
      "is where its endstop trips (DELTA_HEIGHT, DELTA_ENDSTOP_ADJ), min 0: Marlin has no "
      "carriage limit below");
  if (file.adj != std::array{0.0, 0.0, 0.0}) {
    imported.notes.push_back("DELTA_ENDSTOP_ADJ " + marlin_list(as_list(file.adj)) +
                             " mm: in the joints' max; the machine file has no home switches "
                             "from it");
  }
  imported.notes.push_back("max_feed: Marlin has no tool feed limit; the slowest stepper's");
  return imported;
}

}  // namespace pkm::firmware
