// FluidNC's config.yaml for a two-cable wall plotter or a rotary delta, and Maslow 4's maslow.yaml
// (its FluidNC fork's MaslowKinematics) for a cable robot on swivel arms
// (docs/firmware-fluidnc.md). FluidNC's WallPlotter (bdring/FluidNC,
// FluidNC/src/Kinematics/WallPlotter.cpp): the cords' lengths are their distances from the anchors;
// a motor position is the cord's length less its length at the frame's origin (the pen's place at
// power-on), the left motor's sign reversed.
#include "pkm/firmware/fluidnc.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <variant>

namespace pkm::firmware {
namespace {

// FluidNC's `name:`, double-quoted: the machine's name with its quotes and backslashes made
// plain, so that FluidNC's reader and pkm's both take it whole.
std::string name_line(const machine::Machine& machine) {
  std::string name = machine.name();
  for (char& c : name) {
    if (c == '"' || c == '\\') c = '\'';
    if (static_cast<unsigned char>(c) < 0x20) c = ' ';
  }
  return "name: \"" + name + "\"\n";
}

// How far FluidNC's forward kinematics (lengths_to_xy) may miss the pose its inverse
// (xy_to_lengths) was given: 1 um, the round trips' bound.
constexpr double kForwardToleranceMm = 1e-3;
// How far a cord may leave its straight-line length mid-segment (segment_length below).
constexpr double kSegmentCordErrorMm = 0.001;

std::string fixed(double value, int decimals = 6) {
  char text[64];
  std::snprintf(text, sizeof text, "%.*f", decimals, value);
  std::string result = text;
  // A value that rounds to zero is written "0.000", never "-0.000".
  if (result.find_first_not_of("-0.") == std::string::npos && result[0] == '-') result.erase(0, 1);
  return result;
}

std::string refusal_start(const FirmwareMachine& machine) {
  return machine.machine.source() + ": fluidnc's WallPlotter cannot hold this machine: ";
}

struct AxisText {
  char letter;
  std::string what;  // comment lines, each without its "# "
  const machine::JointSpec* joint;
  double cord_offset_mm;  // reading less the cord length (0 for z)
  std::string source;     // the machine file, for refusals
  // Maslow's belts: its own motor code drives them (null_motor), and it checks no travel.
  bool maslow_belt = false;
};

// FluidNC's ranges for an axis's settings (Machine/Axis.cpp, handler.item): a value outside is
// not what FluidNC would run.
void check_axis_ranges(const AxisText& axis, const char* unit) {
  const machine::JointSpec& joint = *axis.joint;
  struct Range {
    const char* key;
    double value, low, high;
  };
  const Range ranges[] = {{"steps_per_mm", joint.steps_per_unit.value_or(80.0), 0.001, 100000.0},
                          {"max_rate_mm_per_min", joint.max_velocity * 60.0, 0.001, 250000.0},
                          {"acceleration_mm_per_sec2", joint.max_acceleration, 0.001, 100000.0},
                          {"max_travel_mm", joint.max - joint.min, 0.1, 1e7}};
  for (const Range& range : ranges) {
    if (range.value < range.low || range.value > range.high) {
      throw ExportRefused(axis.source + ": fluidnc: axis " + axis.letter + " " + range.key + " " +
                          fixed(range.value, 3) + " (" + unit + ") is outside FluidNC's " +
                          fixed(range.low, 3) + ".." + fixed(range.high, 0));
    }
  }
}

std::string axis_section(const AxisText& axis, const char* unit = "mm") {
  check_axis_ranges(axis, unit);
  const machine::JointSpec& joint = *axis.joint;
  std::string text = std::string("  ") + axis.letter + ":\n";
  text += axis.what;
  if (joint.steps_per_unit) {
    text += "    steps_per_mm: " + fixed(*joint.steps_per_unit) + "\n";
  } else {
    text +=
        "    # steps_per_mm: not in the machine file; FluidNC's default 80 applies: set your "
        "motor's\n";
  }
  text += "    max_rate_mm_per_min: " + fixed(joint.max_velocity * 60.0, 3) + "\n";
  text += "    acceleration_mm_per_sec2: " + fixed(joint.max_acceleration, 3) + "\n";
  text += std::string(unit) == "deg"
              ? "    # FluidNC checks only up_degrees - 1; the machine file's limits (deg):\n"
              : "    # FluidNC's " +
                    std::string(axis.maslow_belt ? "MaslowKinematics" : "WallPlotter") +
                    " checks no travel; the machine file's limits (mm, a cord's length for a "
                    "cord):\n";
  text += "    # pkmkit limits: " + fixed(joint.min - axis.cord_offset_mm) + " .. " +
          fixed(joint.max - axis.cord_offset_mm) + " " + unit + "\n";
  text += "    max_travel_mm: " + fixed(joint.max - joint.min, 3) + "\n";
  text += "    soft_limits: false\n";
  if (axis.maslow_belt) return text + "    motor0:\n      null_motor:\n";
  text += "    motor0:\n";
  text += "      # FILL IN your board's pins (gpio.N): NO_PIN drives nothing\n";
  text += "      standard_stepper:\n";
  text += "        step_pin: NO_PIN\n";
  text += "        direction_pin: NO_PIN\n";
  text += "        disable_pin: NO_PIN\n";
  return text;
}

// FluidNC's ParallelDelta (FluidNC/src/Kinematics/ParallelDelta.cpp) takes pkmkit's
// RotaryDeltaForm conventions as they are: arm 0 on the -y side, arms 1 and 2 at +120 and +240
// deg, angle 0 horizontal, positive down, z = 0 at the pivots. Its triangles are sides of
// equilateral triangles whose inradius is the form's radius (side = 2 sqrt(3) r).
struct DeltaSetting {
  const char* key;
  double value_mm;
  double low_mm;  // FluidNC's handler.item range (ParallelDelta::group), up to 500 mm
};

std::array<DeltaSetting, 4> delta_settings(const kinematics::RotaryDeltaForm& form) {
  const double to_side = 2.0 * std::sqrt(3.0);
  return {{{"crank_mm", form.arm_length_mm, 50.0},
           {"base_triangle_mm", to_side * form.base_radius_mm, 20.0},
           {"linkage_mm", form.forearm_length_mm, 20.0},
           {"end_effector_triangle_mm", to_side * form.platform_radius_mm, 20.0}}};
}

std::string delta_refusal(const FirmwareMachine& machine) {
  return machine.machine.source() + ": fluidnc's parallel_delta cannot hold this machine: ";
}

// What FluidNC's ParallelDelta fixes that the machine must already be: its settings' ranges,
// one step count for the three arms (init() gives y and z x's), no pass-through axes, and the
// arms horizontal a pose of the machine (where FluidNC starts, unhomed).
void check_rotary_delta(const FirmwareMachine& machine, const kinematics::RotaryDeltaForm& form) {
  std::string out_of_range;
  for (const DeltaSetting& setting : delta_settings(form)) {
    if (setting.value_mm < setting.low_mm || setting.value_mm > 500.0) {
      out_of_range += std::string(out_of_range.empty() ? "" : ", ") + setting.key + " " +
                      fixed(setting.value_mm, 3) + " (FluidNC takes " + fixed(setting.low_mm, 0) +
                      "..500 mm)";
    }
  }
  if (!out_of_range.empty()) throw ExportRefused(delta_refusal(machine) + out_of_range);
  if (machine.form.passthrough.count() > 0) {
    throw ExportRefused(delta_refusal(machine) + "pkmkit writes no pass-through axes for it");
  }
  const std::vector<machine::JointSpec>& joints = machine.machine.joints();
  for (int arm = 0; arm < 3; ++arm) {
    if (joints[arm].steps_per_unit != joints[0].steps_per_unit) {
      throw ExportRefused(delta_refusal(machine) +
                          "its arms' steps_per_unit differ; FluidNC gives every arm x's");
    }
    if (joints[arm].min > 0.0 || joints[arm].max < 0.0) {
      throw ExportRefused(delta_refusal(machine) + "arm " + std::to_string(arm) +
                          " cannot be horizontal (its limits exclude 0 deg), where FluidNC's "
                          "unhomed ParallelDelta starts");
    }
  }
}

ExportedFile write_rotary_delta(const FirmwareMachine& machine, const ExportContext& context,
                                const kinematics::RotaryDeltaForm& form) {
  check_rotary_delta(machine, form);
  const std::vector<machine::JointSpec>& joints = machine.machine.joints();
  double min_deg = -90.0, velocity = INFINITY, acceleration = INFINITY;
  for (int arm = 0; arm < 3; ++arm) {
    min_deg = std::max(min_deg, geometry::radians_to_degrees(joints[arm].min));
    velocity = std::min(velocity, joints[arm].max_velocity);
    acceleration = std::min(acceleration, joints[arm].max_acceleration);
  }
  ExportedFile file;
  file.text += header_comment(machine, context, "# ");
  file.text +=
      "# pkmkit writes name:, kinematics: and axes: below; the rest of config.yaml (board, "
      "stepping, spindle, pins) is yours.\n"
      "# Unhomed, FluidNC's parallel_delta takes the arms to be horizontal at power-on: park "
      "them there.\n";
  file.text += name_line(machine.machine);
  file.text += "kinematics:\n  parallel_delta:\n";
  file.text +=
      "    # mm; the triangles' sides: 2 sqrt(3) x the centre-to-pivot and tool-to-joint "
      "radii\n";
  for (const DeltaSetting& setting : delta_settings(form)) {
    file.text += "    " + std::string(setting.key) + ": " + fixed(setting.value_mm) + "\n";
  }
  file.text +=
      "    # FluidNC refuses arm angles below up_degrees - 1 (deg, 0 horizontal, + down)\n";
  file.text += "    up_degrees: " + fixed(std::min(min_deg, 0.0), 3) + "\n";
  file.text += "    kinematic_segment_len_mm: 1.000\n    use_servos: false\n";
  file.text += "axes:\n";
  for (int arm = 0; arm < 3; ++arm) {
    machine::JointSpec joint = joints[arm];
    // FluidNC's units for a delta arm are degrees where the names say mm; FluidNC takes x's
    // steps, rate and acceleration for all three (ParallelDelta::init): the least of them.
    joint.min = geometry::radians_to_degrees(joint.min);
    joint.max = geometry::radians_to_degrees(joint.max);
    joint.max_velocity = geometry::radians_to_degrees(velocity);
    joint.max_acceleration = geometry::radians_to_degrees(acceleration);
    const std::string what = "    # arm " + std::to_string(arm) + ", pkmkit joint '" +
                             machine.machine.joint_names()[arm] +
                             "': its reading (deg) = FluidNC's motor position (deg; rates in "
                             "deg/min, deg/s^2)\n";
    file.text += axis_section({"xyz"[arm], what, &joint, 0.0, machine.machine.source()}, "deg");
  }
  file.warnings.push_back(
      "fill in the motors' pins (NO_PIN) in axes:, and park the arms horizontal "
      "before power-on");
  return file;
}

// Where FluidNC's forward kinematics (WallPlotter::lengths_to_xy) put the pen for the cords to
// `point` (FluidNC's frame, mm): it takes the anchors' separation along x only and the lower of
// the circles' meeting points, so it is right for level anchors with the pen below them.
Eigen::Vector2d fluidnc_forward(const Eigen::Vector2d& left, const Eigen::Vector2d& right,
                                const Eigen::Vector2d& point) {
  const double left_cord = (left - point).norm(), right_cord = (right - point).norm();
  const double separation = right.x() - left.x();
  const double along = (left_cord * left_cord - right_cord * right_cord + separation * separation) /
                       (2.0 * separation);
  const double below = std::sqrt(std::max(left_cord * left_cord - along * along, 0.0));
  return {left.x() + along, left.y() - below};
}

// What FluidNC's WallPlotter fixes that the machine must already be: a pass-through Z only, and
// forward kinematics that give the pen back (the position FluidNC reports and resumes from after
// a stop) within kForwardToleranceMm over the workspace: level anchors, the pen below them.
void check_wall_plotter(const FirmwareMachine& machine, const kinematics::WallPlotterForm& form) {
  for (const int axis : machine.form.passthrough.axes()) {
    if (axis != 2) {
      throw ExportRefused(refusal_start(machine) +
                          "pkmkit writes only a pass-through Z as FluidNC's third axis");
    }
  }
  const Eigen::Vector2d home = machine.machine.home().position_mm.head<2>();
  const Eigen::Vector2d left = form.anchors_mm[0] - home, right = form.anchors_mm[1] - home;
  double worst = 0.0;
  Eigen::Vector2d worst_at = Eigen::Vector2d::Zero();
  for (const geometry::Pose& pose : workspace_samples(machine.machine)) {
    const Eigen::Vector2d point = pose.position_mm.head<2>() - home;
    const double error = (fluidnc_forward(left, right, point) - point).norm();
    if (!(error <= worst)) {
      worst = error;
      worst_at = pose.position_mm.head<2>();
    }
  }
  if (!(worst <= kForwardToleranceMm)) {
    throw ExportRefused(
        refusal_start(machine) + "FluidNC's forward kinematics (WallPlotter::lengths_to_xy: " +
        "anchors level, the pen below them; the position it reports and resumes from after a " +
        "stop) would be off by up to " + fixed(worst, 4) + " mm, at x " + fixed(worst_at.x(), 3) +
        " y " + fixed(worst_at.y(), 3) + " mm (anchors' y " + fixed(form.anchors_mm[0].y(), 4) +
        " and " + fixed(form.anchors_mm[1].y(), 4) + " mm)");
  }
}

// The longest segment (from 10 mm down) over which each cord stays within kSegmentCordErrorMm of
// its length on the straight line: mid-segment the error is at most s^2 / (8 L) for a cord of
// length L (its length's second derivative along a line is at most 1 / L).
double segment_length_mm(double shortest_cord_mm) {
  for (const double s : {10.0, 5.0, 2.0, 1.0, 0.5, 0.2, 0.1}) {
    if (s * s / (8.0 * shortest_cord_mm) <= kSegmentCordErrorMm) return s;
  }
  return 0.05;
}

std::string kinematics_section(const kinematics::WallPlotterForm& form, const Eigen::Vector2d& home,
                               double segment_mm, double shortest_cord_mm) {
  const Eigen::Vector2d left = form.anchors_mm[0] - home;
  const Eigen::Vector2d right = form.anchors_mm[1] - home;
  std::string text = "kinematics:\n  WallPlotter:\n";
  text += "    # anchors (mm) in FluidNC's frame: the machine file's less its home (x " +
          fixed(home.x(), 3) + " y " + fixed(home.y(), 3) +
          "), where the pen must be at power-on\n";
  text += "    # FluidNC's WallPlotter drives axes 0 (x) and 1 (y) whatever left_axis says\n";
  text += "    left_axis: 0\n";
  text += "    left_anchor_x: " + fixed(left.x()) + "\n";
  text += "    left_anchor_y: " + fixed(left.y()) + "\n";
  text += "    right_axis: 1\n";
  text += "    right_anchor_x: " + fixed(right.x()) + "\n";
  text += "    right_anchor_y: " + fixed(right.y()) + "\n";
  text +=
      "    # a move is cut into pieces of this length (mm): mid-piece a cord is off its "
      "straight-line length by at most " +
      fixed(segment_mm * segment_mm / (8.0 * shortest_cord_mm), 4) + " mm (at its shortest, " +
      fixed(shortest_cord_mm, 3) + " mm)\n";
  text += "    segment_length: " + fixed(segment_mm, 3) + "\n";
  return text;
}

// Maslow 4's fork of FluidNC (MaslowCNC/Maslow_4, FluidNC/src/Kinematics/MaslowKinematics.cpp)
// computes belt = sqrt((|corner - router| in plan - (beltEndExtension + armLength))^2 +
// (z + cornerZ)^2), the corners tl, tr, bl, br its axes a b c d, and counts x y from the frame's
// centre (the diagonals' crossing); z passes through to axis z.
void check_maslow(const FirmwareMachine& machine, const kinematics::CableRobotForm& form) {
  const std::string start =
      machine.machine.source() + ": fluidnc's MaslowKinematics cannot hold this machine: ";
  if (form.anchors_mm.size() != 4 || !form.planar || !form.cables_follow_z) {
    throw ExportRefused(start +
                        "it takes four belts in a plane, tl tr bl br, their tie points riding on "
                        "the router's z (planar = true, cables_follow_z = true)");
  }
  for (std::size_t k = 0; k < 4; ++k) {
    if (form.swivel_arms_mm[k] != form.swivel_arms_mm[0]) {
      throw ExportRefused(start + "one armLength for all four belts; cable " + std::to_string(k) +
                          "'s swivel_arm is " + fixed(form.swivel_arms_mm[k], 3) +
                          " mm, cable 0's " + fixed(form.swivel_arms_mm[0], 3) + " mm");
    }
    if (form.cable_offsets_mm[k] != 0.0) {
      throw ExportRefused(start + "its axis position is the belt's length; cable " +
                          std::to_string(k) + " has offset " + fixed(form.cable_offsets_mm[k], 3) +
                          " mm");
    }
  }
  const Eigen::Vector2d centre = maslow_centre(form.anchors_mm);
  if (!std::isfinite(centre.x()) || !std::isfinite(centre.y())) {
    throw ExportRefused(start +
                        "its origin is where the diagonals tl-br and tr-bl cross; these "
                        "do not cross");
  }
  if (machine.form.passthrough.axes() != std::vector<int>{2}) {
    throw ExportRefused(start + "it passes z alone through (passthrough = [\"z\"])");
  }
}

// Maslow's beltEndExtension, its default: the rest of the swivel arm is written as armLength
// (Maslow subtracts only their sum).
constexpr double kMaslowBeltEndExtensionMm = 30.0;

ExportedFile write_maslow(const FirmwareMachine& machine, const ExportContext& context,
                          const kinematics::CableRobotForm& form) {
  check_maslow(machine, form);
  const machine::Machine& m = machine.machine;
  ExportedFile file;
  file.text += header_comment(machine, context, "# ");
  file.text +=
      "# Maslow 4's FluidNC (MaslowCNC/Maslow_4) reads this from maslow.yaml. pkmkit writes "
      "name:, kinematics: and axes: below; the rest (board, Maslow_ settings, z motors) is "
      "yours.\n";
  file.text += name_line(m);
  const Eigen::Vector2d centre = maslow_centre(form.anchors_mm);
  file.text += "# Maslow's x y count from the diagonals' crossing, the machine file's x " +
               fixed(centre.x(), 3) + " y " + fixed(centre.y(), 3) +
               " mm; its z is the machine file's.\n";
  file.text += "kinematics:\n  MaslowKinematics:\n";
  const char* corners[] = {"tl", "tr", "bl", "br"};
  for (int k = 0; k < 4; ++k) {
    const Eigen::Vector3d& corner = form.anchors_mm[k];
    // The router's z less the folded anchor's is the tie point's height above its corner.
    file.text += std::string("    ") + corners[k] + "X: " + fixed(corner.x()) + "\n";
    file.text += std::string("    ") + corners[k] + "Y: " + fixed(corner.y()) + "\n";
    file.text += std::string("    ") + corners[k] + "Z: " + fixed(-corner.z()) + "\n";
  }
  file.text += "    beltEndExtension: " + fixed(kMaslowBeltEndExtensionMm) + "\n";
  file.text += "    armLength: " + fixed(form.swivel_arms_mm[0] - kMaslowBeltEndExtensionMm) + "\n";
  file.text += "axes:\n";
  const char letters[] = {'a', 'b', 'c', 'd'};
  for (int k = 0; k < 4; ++k) {
    const std::string what = std::string("    # the ") + corners[k] + " belt, pkmkit joint '" +
                             m.joint_names()[k] + "': its reading = Maslow's " + letters[k] +
                             " position (mm)\n";
    file.text += axis_section({letters[k], what, &m.joints()[k], 0.0, m.source(), true});
  }
  const std::string what = "    # the router's z, pkmkit joint '" + m.joint_names()[4] + "' (mm)\n";
  file.text += axis_section({'z', what, &m.joints()[4], 0.0, m.source()});
  for (const std::string& unchecked : machine.form.unchecked) {
    file.warnings.push_back("Maslow's firmware does not check: " + unchecked);
  }
  file.warnings.push_back(
      "merge these sections into your maslow.yaml; the z motors' section is yours");
  return file;
}

}  // namespace

Eigen::Vector2d maslow_centre(const std::vector<Eigen::Vector3d>& corners_mm) {
  // bl + s (tr - bl) = tl + t (br - tl), solved for s.
  const Eigen::Vector2d bl = corners_mm[2].head<2>(), tr = corners_mm[1].head<2>();
  const Eigen::Vector2d tl = corners_mm[0].head<2>(), br = corners_mm[3].head<2>();
  const Eigen::Vector2d u = tr - bl, v = br - tl, w = tl - bl;
  const double cross = u.x() * v.y() - u.y() * v.x();
  const double s = (w.x() * v.y() - w.y() * v.x()) / cross;
  return bl + s * u;
}

std::string fluidnc_startup_line(double home_x_mm, double home_y_mm, const double* home_z_mm) {
  // G10 L2 P1 puts G54's origin at the given machine position: work = machine - origin, so the
  // origin -home makes work coordinates the machine file's.
  std::string line = "G10 L2 P1 X" + fixed(-home_x_mm) + " Y" + fixed(-home_y_mm);
  if (home_z_mm) line += " Z" + fixed(-*home_z_mm);
  return line;
}

ExportedFile write_fluidnc(const FirmwareMachine& machine, const ExportContext& context) {
  if (const auto* belts = std::get_if<kinematics::CableRobotForm>(&machine.form.geometry)) {
    return write_maslow(machine, context, *belts);
  }
  if (const auto* delta = std::get_if<kinematics::RotaryDeltaForm>(&machine.form.geometry)) {
    return write_rotary_delta(machine, context, *delta);
  }
  const auto* form = std::get_if<kinematics::WallPlotterForm>(&machine.form.geometry);
  if (!form) {
    throw ExportRefused(machine.machine.source() +
                        ": fluidnc has kinematics for a two-cable wall plotter, a rotary delta or "
                        "Maslow 4's belts");
  }
  check_wall_plotter(machine, *form);
  const machine::Machine& m = machine.machine;
  const bool has_z = machine.form.passthrough.count() == 1;
  const Eigen::Vector3d home = m.home().position_mm;
  const Eigen::Vector2d home_xy = home.head<2>();

  std::array<double, 2> home_cord{};
  double shortest_cord = INFINITY;
  for (int k = 0; k < 2; ++k) {
    home_cord[k] = (form->anchors_mm[k] - home_xy).norm();
    shortest_cord = std::min(shortest_cord, m.joints()[k].min - form->cable_offsets_mm[k]);
  }
  shortest_cord = std::max(shortest_cord, 1.0);

  ExportedFile file;
  file.text += header_comment(machine, context, "# ");
  file.text +=
      "# pkmkit writes name:, kinematics:, axes: and macros: startup_line0 below; the rest of "
      "config.yaml (board, stepping, spindle, pins) is yours.\n";
  file.text += name_line(machine.machine);
  file.text += "# FluidNC's WallPlotter cannot home: park the pen at the machine's home (x " +
               fixed(home.x(), 3) + " y " + fixed(home.y(), 3) +
               (has_z ? " z " + fixed(home.z(), 3) : std::string()) +
               " mm) before power-on; there FluidNC's machine position is 0.\n";
  file.text += kinematics_section(*form, home_xy, segment_length_mm(shortest_cord), shortest_cord);
  file.text += "axes:\n";
  const std::array<const char*, 2> names = {"left", "right"};
  for (int k = 0; k < 2; ++k) {
    const double reading_at_home = home_cord[k] + form->cable_offsets_mm[k];
    std::string what = "    # the " + std::string(names[k]) + " cord, pkmkit joint '" +
                       m.joint_names()[k] + "': its reading = " + fixed(reading_at_home) +
                       (k == 0 ? " - " : " + ") + "FluidNC's " + (k == 0 ? "x" : "y") +
                       " motor position (mm)\n";
    file.text += axis_section(
        {k == 0 ? 'x' : 'y', what, &m.joints()[k], form->cable_offsets_mm[k], m.source()});
  }
  if (has_z) {
    const std::string what = "    # the pass-through Z, pkmkit joint '" + m.joint_names()[2] +
                             "': its reading = " + fixed(home.z()) +
                             " + FluidNC's z motor position (mm)\n";
    file.text += axis_section({'z', what, &m.joints()[2], 0.0, m.source()});
  }
  file.text +=
      "macros:\n  # G54 work coordinates = the machine file's frame (FluidNC's machine position "
      "+ home)\n";
  const double home_z = home.z();
  file.text +=
      "  startup_line0: " + fluidnc_startup_line(home.x(), home.y(), has_z ? &home_z : nullptr) +
      "\n";
  if (!machine.form.unchecked.empty()) {
    file.warnings.push_back("FluidNC does not check: " + machine.form.unchecked.front());
  }
  file.warnings.push_back(
      "fill in the motors' pins (NO_PIN) in axes:, and park the pen at home before power-on");
  return file;
}

Target fluidnc_target() {
  return Target{"fluidnc",
                "config.yaml",
                {FormKind::wall_plotter, FormKind::rotary_delta, FormKind::swivel_arm_cable_robot},
                write_fluidnc,
                read_fluidnc};
}

}  // namespace pkm::firmware
