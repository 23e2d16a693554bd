// grblHAL's delta robot (grblHAL/core kinematics/delta.c, docs/firmware-grblhal.md): a rotary
// delta in the Trossen form. Its `$643` base and `$644` effector are triangle sides: the pivot
// axes lie f / (2 sqrt 3) from the centre, the effector's joints e / (2 sqrt 3) from the tool. Arm
// A (X) swings in the y z plane at -y, B and C at +120 and +240 deg counter-clockwise; an angle is
// 0 with the arm horizontal and outward, positive down, in radians; z = 0 is the pivots' plane, z
// up. pkmkit's RotaryDeltaForm has the same conventions: the frame and the joints map as they are.
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "pkm/firmware/grblhal_settings.hpp"
#include "pkm/machine/machine_writer.hpp"

namespace pkm::firmware::grblhal {
namespace {

// Side of the equilateral triangle whose inscribed circle has `radius`: delta.c's f and e.
constexpr double kSidePerRadius = 2.0 * 1.7320508075688772;
constexpr double kDegPerRad = 180.0 / M_PI;

std::string degrees(double value_deg) {
  char text[48];
  std::snprintf(text, sizeof text, "%.6g deg", value_deg);
  return text;
}

// The arms' common angle range in deg: grblHAL has one home and one max angle for all three.
std::pair<double, double> angle_range_deg(const FirmwareMachine& firmware) {
  double low = -1e9, high = 1e9;
  for (int arm = 0; arm < 3; ++arm) {
    const machine::JointSpec& joint = firmware.machine.joints()[static_cast<std::size_t>(arm)];
    low = std::max(low, joint.to_interface(joint.min));
    high = std::min(high, joint.to_interface(joint.max));
  }
  const auto refuse = [&](const char* what, double value, double lowest, double highest) {
    if (value >= lowest && value <= highest) return;
    throw ExportRefused(firmware.machine.source() + ": grblHAL's delta " + what + " must be " +
                        degrees(lowest) + " to " + degrees(highest) + " (delta.c); the arms' is " +
                        degrees(value));
  };
  refuse("home position $646 [the arms' min]", low, -90.0, 90.0);
  refuse("max angle $648 [the arms' max]", high, -90.0, 135.0);
  return {low, high};
}

void write_header(Lines& out, const FirmwareMachine& firmware, const ExportContext& context) {
  for (const std::string& line : header_lines(firmware, context)) out.comment(line);
  out.comment(
      "grblHAL built with DELTA_ROBOT On [config.h, or -DDELTA_ROBOT=1]: $I reports "
      "[KINEMATICS:Delta v0.05], $DELTA shows its envelope");
  out.comment(
      "Frame: the machine's own: z = 0 the pivots' plane, z up, arm A [X] at -y, B [Y] and C [Z] "
      "at +120 and +240 deg, an angle is 0 with the arm horizontal outward, positive down");
  const std::vector<std::string>& names = firmware.machine.joint_names();
  out.comment("motor A = joint '" + names[0] + "', B = '" + names[1] + "', C = '" + names[2] +
              "': the arm's angle, rad in grblHAL, deg in the machine file");
  out.comment(
      "Not written: $640 segment length, $645 base to floor, $647 flags [keep grblHAL's or "
      "yours], the work envelope [$130-$132 and the cuboid]");
}

void write_motors(Lines& out, const FirmwareMachine& firmware, std::vector<std::string>& warnings) {
  const std::vector<machine::JointSpec>& joints = firmware.machine.joints();
  const char motor[] = {'A', 'B', 'C'};
  const auto what = [&](int arm, const char* unit) {
    return std::string("motor ") + motor[arm] + ": " + unit;
  };
  for (int arm = 0; arm < 3; ++arm) {
    const machine::JointSpec& joint = joints[static_cast<std::size_t>(arm)];
    if (joint.steps_per_unit) {
      out.setting(100 + arm, *joint.steps_per_unit * kDegPerRad, what(arm, "steps/rad"));
    } else {
      warnings.push_back("joint '" + joint.name + "' has no steps_per_unit: set $" +
                         std::to_string(100 + arm) + " [steps/rad] yourself");
    }
  }
  for (int arm = 0; arm < 3; ++arm) {
    out.setting(110 + arm, joints[static_cast<std::size_t>(arm)].max_velocity * 60.0,
                what(arm, "max rate, rad/min"));
  }
  for (int arm = 0; arm < 3; ++arm) {
    out.setting(120 + arm, joints[static_cast<std::size_t>(arm)].max_acceleration,
                what(arm, "acceleration, rad/s^2"));
  }
  const auto alike = [&](auto value) {
    return value(joints[0]) == value(joints[1]) && value(joints[0]) == value(joints[2]);
  };
  if (!alike([](const machine::JointSpec& j) { return j.steps_per_unit; }) ||
      !alike([](const machine::JointSpec& j) { return j.max_velocity; }) ||
      !alike([](const machine::JointSpec& j) { return j.max_acceleration; })) {
    warnings.push_back(
        "the arms' steps, rates or accelerations differ: grblHAL's delta wants them alike "
        "($DELTA says \"Review settings\")");
  }
}

}  // namespace

ExportedFile write_rotary_delta(const FirmwareMachine& firmware, const ExportContext& context,
                                const kinematics::RotaryDeltaForm& form) {
  if (firmware.form.passthrough.count() > 0) {
    throw ExportRefused(firmware.machine.source() +
                        ": grblHAL's delta moves its three arms only (delta.c computes no axis "
                        "past C): this machine's pass-through joints have no place there");
  }
  const auto [low_deg, high_deg] = angle_range_deg(firmware);
  ExportedFile file;
  Lines out;
  write_header(out, firmware, context);
  write_motors(out, firmware, file.warnings);
  out.setting(641, form.forearm_length_mm, "forearm length re, mm: elbow to effector joint");
  out.setting(642, form.arm_length_mm, "bicep length rf, mm: pivot to elbow");
  out.setting(643, form.base_radius_mm * kSidePerRadius,
              "base f, mm: triangle side, 2 sqrt3 x the pivots' radius");
  out.setting(644, form.platform_radius_mm * kSidePerRadius,
              "end effector e, mm: triangle side, 2 sqrt3 x the joints' radius");
  out.setting(646, low_deg, "home position, deg: the arms' min, where homing stops");
  out.setting(648, high_deg, "max angle, deg: the arms' max");
  file.text = out.text;
  return file;
}

bool is_delta_file(const SettingsFile& file) {
  const auto first = file.settings.lower_bound(640);
  return first != file.settings.end() && first->first <= 648;
}

namespace {

machine::ImportedJoint arm(const SettingsFile& file, int index, double min_deg, double max_deg) {
  machine::ImportedJoint joint;
  joint.name = std::string("arm_") + static_cast<char>('a' + index);
  joint.angular = true;
  joint.min = min_deg;
  joint.max = max_deg;
  joint.max_velocity = required(file, 110 + index, "max rate, rad/min") / 60.0 * kDegPerRad;
  joint.max_acceleration = required(file, 120 + index, "acceleration, rad/s^2") * kDegPerRad;
  if (file.settings.count(100 + index)) {
    joint.steps_per_unit = required(file, 100 + index, "steps/rad") / kDegPerRad;
  }
  return joint;
}

}  // namespace

machine::ImportedMachine read_rotary_delta(const SettingsFile& file) {
  kinematics::RotaryDeltaForm form;
  form.forearm_length_mm = required(file, 641, "forearm length re, mm");
  form.arm_length_mm = required(file, 642, "bicep length rf, mm");
  form.base_radius_mm = required(file, 643, "base f, mm") / kSidePerRadius;
  form.platform_radius_mm = required(file, 644, "end effector e, mm") / kSidePerRadius;
  const double min_deg = optional_number(file, 646).value_or(0.0);
  const double max_deg = optional_number(file, 648).value_or(0.0);
  machine::ImportedMachine imported;
  imported.source = file.source;
  imported.origin = "Imported by `pkm import grblhal` from " + file.source + " (Delta)";
  imported.name = "grblHAL delta";
  imported.kinematics_section =
      machine::kinematics_toml(*kinematics::make_form_kinematics(form), machine::LengthUnit::mm);
  imported.joints = {arm(file, 0, min_deg, max_deg == 0.0 ? 90.0 : max_deg),
                     arm(file, 1, min_deg, max_deg == 0.0 ? 90.0 : max_deg),
                     arm(file, 2, min_deg, max_deg == 0.0 ? 90.0 : max_deg)};
  double slowest = 1e300, weakest = 1e300;
  for (const machine::ImportedJoint& joint : imported.joints) {
    slowest = std::min(slowest, joint.max_velocity / kDegPerRad);
    weakest = std::min(weakest, joint.max_acceleration / kDegPerRad);
  }
  imported.max_feed_per_min = form.arm_length_mm * slowest * 60.0;
  imported.max_acceleration = form.arm_length_mm * weakest;
  // The tool on the axis with every arm at its home position (the arms' min).
  const double h = min_deg / kDegPerRad;
  const double reach =
      form.base_radius_mm - form.platform_radius_mm + form.arm_length_mm * std::cos(h);
  const double drop = form.forearm_length_mm * form.forearm_length_mm - reach * reach;
  if (!(drop > 0.0)) {
    throw FirmwareFileError(file.source + ":" + std::to_string(file.settings.at(641).line) +
                            ": $641: the forearms (" + value_text(form.forearm_length_mm) +
                            " mm) do not reach the axis with the arms at $646");
  }
  imported.home =
      std::vector<double>{0.0, 0.0, -form.arm_length_mm * std::sin(h) - std::sqrt(drop)};
  imported.notes.push_back(
      "the frame and the arms' angles are grblHAL's: z = 0 the pivots' plane, arm A at -y");
  imported.notes.push_back(
      "the arms' limits: min = $646 (the home position), max = $648 (90 deg where $648 is 0 or "
      "absent: grblHAL computes its own); home is the tool with every arm at $646");
  imported.notes.push_back(
      "max_feed and max_acceleration are ours: the bicep's length times the slowest arm's rate");
  note_unused(file, {100, 101, 102, 110, 111, 112, 120, 121, 122, 641, 642, 643, 644, 646, 648},
              imported.notes);
  return imported;
}

}  // namespace pkm::firmware::grblhal
