// grblHAL's WallPlotter (grblHAL/core kinematics/wall_plotter.c, docs/firmware-grblhal.md):
//   motor A (X) = |g|, motor B (Y) = |g - (W, 0)|, Z and further axes straight through,
// W = $130 (X max travel), g grblHAL's machine coordinates, y >= 0 (its forward kinematics takes
// the positive root). A pkmkit wall plotter has the pen below its anchors, left anchor first:
// grblHAL's g is then a1 - m (m the machine's x y, a1 its right anchor), motor A its right cord and
// motor B its left one; the G54 offset a1 makes G54's x y the machine's -x -y.
#include "pkm/firmware/grblhal.hpp"

#include "pkm/firmware/grblhal_settings.hpp"
#include "pkm/post/grbl_settings.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <variant>

namespace pkm::firmware {
namespace grblhal {

// grblHAL reads a setting with read_float (any number of decimals) and stores a float; six
// decimals carry a length to well under the float's own rounding.
std::string value_text(double value) {
  char text[64];
  std::snprintf(text, sizeof text, "%.6f", value);
  std::string written = text;
  const std::size_t point = written.find('.');
  while (written.size() > point + 4 && written.back() == '0') written.pop_back();
  if (written == "-0.000") written = "0.000";
  return written;
}

namespace {}  // namespace

// grblHAL reads 256 characters a line (protocol.h LINE_BUFFER_SIZE) and reports an overflow past
// them: a longer comment goes on as many lines as it takes.
void Lines::comment(std::string_view line) {
  constexpr std::size_t kRoom = 250;
  const std::string safe = post::grbl_comment_text(line);
  for (std::size_t at = 0; at == 0 || at < safe.size(); at += kRoom) {
    text += "(" + safe.substr(at, kRoom) + ")\n";
  }
}

void Lines::setting(int number, double value, std::string_view what) {
  text += "$" + std::to_string(number) + "=" + value_text(value) + " (" +
          post::grbl_comment_text(what) + ")\n";
}

}  // namespace grblhal

namespace {

using grblhal::Lines;
using grblhal::value_text;

// The machine's joints in grblHAL's axis order: X = motor A (joint 1, the right cord), Y = motor
// B (joint 0, the left cord), Z = the pass-through z.
struct AxisJoint {
  char letter;
  int joint;
  std::string role;  // "motor A, cord from the right anchor"
};

std::vector<AxisJoint> axis_joints(const FirmwareMachine& firmware) {
  const kinematics::PassThroughAxes& passthrough = firmware.form.passthrough;
  std::vector<AxisJoint> axes = {{'X', 1, "motor A: the right cord"},
                                 {'Y', 0, "motor B: the left cord"}};
  for (int k = 0; k < passthrough.count(); ++k) {
    if (passthrough.axes()[static_cast<std::size_t>(k)] != 2) {
      throw ExportRefused(firmware.machine.source() +
                          ": grblhal writes a wall plotter's z pass-through axis only; this "
                          "machine passes an a, b or c axis through, which pkmkit does not map "
                          "to grblHAL's axes yet");
    }
    axes.push_back({'Z', 2 + k, "z, straight through"});
  }
  return axes;
}

void check_level(const FirmwareMachine& firmware, const kinematics::WallPlotterForm& form) {
  const double rise = form.anchors_mm[1].y() - form.anchors_mm[0].y();
  // A fit's rounding (1e-7 mm) is no turn: the writer puts both motors at the right anchor's
  // height, moving the left cord's by at most this.
  if (std::abs(rise) <= 1e-6) return;
  const double span = form.anchors_mm[1].x() - form.anchors_mm[0].x();
  char text[400];
  std::snprintf(text, sizeof text,
                ": grblhal's WallPlotter puts both motors on its x axis; this machine's right "
                "anchor is %.6f mm %s the left one, so grblHAL's frame would turn by %.6f deg "
                "against the machine's, and no grblHAL setting turns it back",
                std::abs(rise), rise > 0.0 ? "above" : "below",
                std::atan2(rise, span) * 180.0 / M_PI);
  throw ExportRefused(firmware.machine.source() + text);
}

std::string turned_frame_refusal(const FirmwareMachine& firmware) {
  return firmware.machine.source() +
         ": grblhal's WallPlotter (grblHAL/core kinematics/wall_plotter.c) has its origin at "
         "motor A, motor B on +x and the pen on +y (its forward kinematics takes y = "
         "+sqrt(...)): with this machine's pen below its motors that frame is the machine's "
         "turned 180 deg about z (motor A the right motor; G-code X and Y move the pen the "
         "other way). No grblHAL setting turns it back (G10 L2 R needs ROTATION_ENABLE and "
         "leaves incremental moves and jogs unturned), so grblhal refuses it; run the machine "
         "on joint-space G-code instead (pkmkit's joint settings for grblHAL: docs/grbl.md)";
}

void write_header(Lines& out, const FirmwareMachine& firmware, const ExportContext& context,
                  const kinematics::WallPlotterForm& form) {
  for (const std::string& line : header_lines(firmware, context)) out.comment(line);
  out.comment(
      "grblHAL built with WALL_PLOTTER On [config.h, or -DWALL_PLOTTER=1]: $I reports "
      "[KINEMATICS:WallPlotter v2.01]");
  out.comment(
      "FRAME TURNED: grblHAL's x y are this machine's turned 180 deg about z. With the G54 "
      "offset below, G54 X Y = the machine's -x -y: turn your drawing by 180 deg");
  const std::vector<std::string> names = firmware.machine.joint_names();
  char text[300];
  for (int joint = 1; joint >= 0; --joint) {
    std::snprintf(text, sizeof text,
                  "motor %c = joint '%s': the cord's length from its anchor, mm = the joint's "
                  "reading less its cable_offset %s mm",
                  joint == 1 ? 'A' : 'B', names[static_cast<std::size_t>(joint)].c_str(),
                  value_text(form.cable_offsets_mm[static_cast<std::size_t>(joint)]).c_str());
    out.comment(text);
  }
  out.comment(
      "No homing in WallPlotter: at power-up and after a setting change it takes the pen to be "
      "at motor A [cords 0 and $130]. Leave soft limits $20 and homing $22 off");
  out.comment("The cords' joint limits have no grblHAL setting: grblHAL does not check them");
}

double longest_cord_mm(const FirmwareMachine& firmware, const kinematics::WallPlotterForm& form) {
  double longest = 0.0;
  for (int joint = 0; joint < 2; ++joint) {
    longest = std::max(longest, firmware.machine.joints()[static_cast<std::size_t>(joint)].max -
                                    form.cable_offsets_mm[static_cast<std::size_t>(joint)]);
  }
  return longest;
}

void write_axes(Lines& out, const FirmwareMachine& firmware, const std::vector<AxisJoint>& axes,
                const kinematics::WallPlotterForm& form, std::vector<std::string>& warnings) {
  const std::vector<machine::JointSpec>& joints = firmware.machine.joints();
  const auto spec = [&](const AxisJoint& axis) -> const machine::JointSpec& {
    return joints[static_cast<std::size_t>(axis.joint)];
  };
  const auto label = [&](const AxisJoint& axis, const std::string& what) {
    return std::string(1, axis.letter) + " = " + axis.role + " '" + spec(axis).name + "': " + what;
  };
  for (std::size_t k = 0; k < axes.size(); ++k) {
    if (spec(axes[k]).steps_per_unit) {
      out.setting(100 + static_cast<int>(k), *spec(axes[k]).steps_per_unit,
                  label(axes[k], "steps/mm"));
    } else {
      warnings.push_back("joint '" + spec(axes[k]).name + "' has no steps_per_unit: set $" +
                         std::to_string(100 + k) + " [steps/mm] yourself");
    }
  }
  for (std::size_t k = 0; k < axes.size(); ++k) {
    out.setting(110 + static_cast<int>(k), spec(axes[k]).max_velocity * 60.0,
                label(axes[k], "max rate, mm/min"));
  }
  for (std::size_t k = 0; k < axes.size(); ++k) {
    out.setting(120 + static_cast<int>(k), spec(axes[k]).max_acceleration,
                label(axes[k], "acceleration, mm/s^2"));
  }
  const double width = form.anchors_mm[1].x() - form.anchors_mm[0].x();
  out.setting(130, width, "X max travel = WallPlotter's width: motor A to motor B, mm");
  out.setting(131, longest_cord_mm(firmware, form),
              "Y max travel: unused by WallPlotter, pkmkit's longest cord, mm");
  for (std::size_t k = 2; k < axes.size(); ++k) {
    out.setting(130 + static_cast<int>(k), spec(axes[k]).max - spec(axes[k]).min,
                label(axes[k], "max travel, mm: its max - min"));
  }
}

ExportedFile write_wall_plotter(const FirmwareMachine& firmware, const ExportContext& context,
                                const kinematics::WallPlotterForm& form, GrblhalFrameTurn turn) {
  check_level(firmware, form);
  if (turn == GrblhalFrameTurn::refuse) throw ExportRefused(turned_frame_refusal(firmware));
  const std::vector<AxisJoint> axes = axis_joints(firmware);
  ExportedFile file;
  Lines out;
  write_header(out, firmware, context, form);
  write_axes(out, firmware, axes, form, file.warnings);
  const Eigen::Vector2d& right = form.anchors_mm[1];
  std::string offset = "G10 L2 P1 X" + value_text(right.x()) + " Y" + value_text(right.y());
  if (axes.size() > 2) offset += " Z0";
  out.text += offset + " (G54 offset: G54 X Y = the machine's -x -y)\n";
  file.text = out.text;
  file.warnings.insert(file.warnings.begin(),
                       "grblHAL's frame is this machine's turned 180 deg about z: G54 X Y are "
                       "the machine's -x -y (turn drawings by 180 deg)");
  file.warnings.push_back(
      "grblHAL's WallPlotter does not home: it starts with the pen taken to be at motor A");
  return file;
}

}  // namespace

ExportedFile grblhal_write(const FirmwareMachine& machine, const ExportContext& context,
                           GrblhalFrameTurn turn) {
  if (const auto* delta = std::get_if<kinematics::RotaryDeltaForm>(&machine.form.geometry)) {
    return grblhal::write_rotary_delta(machine, context, *delta);
  }
  const auto* wall_plotter = std::get_if<kinematics::WallPlotterForm>(&machine.form.geometry);
  if (wall_plotter == nullptr) {
    throw ExportRefused(machine.machine.source() +
                        ": grblhal writes a two-cable wall plotter or a rotary delta; this "
                        "machine is a " +
                        std::string(kinematics::form_name(machine.form.geometry)));
  }
  return write_wall_plotter(machine, context, *wall_plotter, turn);
}

Target grblhal_target() {
  return Target{
      "grblhal",
      "$ settings",
      {FormKind::wall_plotter, FormKind::rotary_delta},
      [](const FirmwareMachine& machine, const ExportContext& context) {
        return grblhal_write(machine, context, GrblhalFrameTurn::refuse);
      },
      [](std::string_view text, const std::string& source) { return grblhal_read(text, source); }};
}

}  // namespace pkm::firmware
