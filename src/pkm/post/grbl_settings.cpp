#include "pkm/post/grbl_settings.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>

namespace pkm::post {

namespace {

// grbl's longest line (LINE_BUFFER_SIZE 80); comments do not count there, but a line that fits it
// whole also fits any sender's buffer.
constexpr std::size_t kMaxLine = 80;
// grbl 1.1 on a 16 MHz AVR steps at about 30 kHz at most (its config.h, MAX_STEP_RATE_HZ).
constexpr double kAvrMaxStepRate_Hz = 30000.0;

// A value as grbl reads it: its read_float keeps 8 significant digits (MAX_INT_DIGITS); at least
// the 3 decimals grbl's own $$ report shows, more where the digits allow (78.740157 steps/mm).
std::string setting_value(double value) {
  const int integer_digits = value >= 1.0 ? static_cast<int>(std::floor(std::log10(value))) + 1 : 1;
  const int decimals = std::clamp(8 - integer_digits, 3, 6);
  char text[64];
  std::snprintf(text, sizeof text, "%.*f", decimals, value);
  std::string written = text;
  const std::size_t point = written.find('.');
  while (written.size() > point + 4 && written.back() == '0') written.pop_back();
  return written;
}

// "(X = joint left: steps/mm)", the joint's name shortened where the line would pass 80.
std::string axis_comment(char letter, const std::string& joint_name, const std::string& what,
                         std::size_t room) {
  const std::string head = std::string(1, letter) + " = joint ";
  const std::string tail = ": " + what;
  std::string name = grbl_comment_text(joint_name);
  if (head.size() + name.size() + tail.size() > room) {
    const std::size_t keep =
        room > head.size() + tail.size() + 3 ? room - head.size() - tail.size() - 3 : 0;
    name = name.substr(0, keep) + "...";
  }
  return head + name + tail;
}

void check_controller(const machine::Machine& machine, machine::ControllerKind kind) {
  const std::string wanted = machine::controller_kind_name(kind);
  if (!machine.controller()) {
    throw std::invalid_argument(machine.source() + ": has no [controller] table; pkm export " +
                                wanted + " needs one (kind = \"" + wanted +
                                "\") and each joint's steps_per_unit (docs/machine-file.md)");
  }
  if (machine.controller()->kind != kind) {
    const std::string has = machine::controller_kind_name(machine.controller()->kind);
    throw std::invalid_argument(machine.source() + ": its [controller] kind is \"" + has +
                                "\": use pkm export " + has +
                                ", or change kind in the machine file");
  }
}

struct AxisJoint {
  int axis;   // index in the controller's order: $100 + axis
  int joint;  // index in the machine
};

// The joints in the controller's axis order, each with its steps; refused where a joint's range in
// steps passes grbl's 32-bit step counter.
std::vector<AxisJoint> axis_order(const machine::Machine& machine) {
  const machine::ControllerSettings& controller = *machine.controller();
  const std::string_view letters =
      machine::controller_axis_letters(controller.kind, controller.axes);
  std::vector<AxisJoint> order;
  for (int j = 0; j < static_cast<int>(machine.joints().size()); ++j) {
    const machine::JointSpec& joint = machine.joints()[static_cast<std::size_t>(j)];
    const std::size_t axis = letters.find(joint.axis_letter);
    if (axis == std::string_view::npos || !joint.steps_per_unit) {
      throw std::invalid_argument(machine.source() + ": joint '" + joint.name + "' (axis " +
                                  joint.axis_letter + ") has no axis or no steps_per_unit on " +
                                  machine::controller_kind_name(controller.kind));
    }
    const double range_steps =
        (joint.to_interface(joint.max) - joint.to_interface(joint.min)) * *joint.steps_per_unit;
    if (!(range_steps < static_cast<double>(std::numeric_limits<std::int32_t>::max()))) {
      char text[160];
      std::snprintf(text, sizeof text, "%.0f steps (its range times steps_per_unit)", range_steps);
      throw std::invalid_argument(machine.source() + ": joint '" + joint.name + "' spans " + text +
                                  ", beyond grbl's step counter (2147483647)");
    }
    order.push_back({static_cast<int>(axis), j});
  }
  std::sort(order.begin(), order.end(),
            [](const AxisJoint& a, const AxisJoint& b) { return a.axis < b.axis; });
  return order;
}

std::string step_rate_warning(const machine::Machine& machine, const machine::JointSpec& joint) {
  const double rate_Hz = joint.to_interface(joint.max_velocity) * *joint.steps_per_unit;
  if (machine.controller()->kind != machine::ControllerKind::grbl ||
      rate_Hz <= kAvrMaxStepRate_Hz) {
    return "";
  }
  char text[240];
  std::snprintf(text, sizeof text,
                "joint '%s' at its max_velocity %.3f %s/s steps at %.0f Hz; grbl 1.1 on a 16 MHz "
                "AVR steps at about %.0f Hz at most: lower max_velocity to %.3f %s/s",
                joint.name.c_str(), joint.to_interface(joint.max_velocity), joint.interface_unit(),
                rate_Hz, kAvrMaxStepRate_Hz, kAvrMaxStepRate_Hz / *joint.steps_per_unit,
                joint.interface_unit());
  return text;
}

}  // namespace

std::string grbl_comment_text(std::string_view text) {
  std::string safe;
  for (const char c : text) {
    const auto byte = static_cast<unsigned char>(c);
    if (c == '(') {
      safe += '[';
    } else if (c == ')') {
      safe += ']';
    } else if (byte < 0x20 || byte > 0x7E || c == '?' || c == '!' || c == '~' || c == ';') {
      safe += '_';
    } else {
      safe += c;
    }
  }
  return safe;
}

ControllerSettingsFile controller_settings(const machine::Machine& machine,
                                           machine::ControllerKind kind) {
  check_controller(machine, kind);
  const std::vector<AxisJoint> order = axis_order(machine);
  ControllerSettingsFile file;
  // grbl cuts the motors' current 25 ms after a move ($1=25): a parallel machine's tool hangs on
  // its joints, and a cord or arm let go slips, losing the zero. 255 keeps them enabled.
  file.settings.push_back({1, "255", "keep the motors enabled at rest: the tool hangs on them"});
  file.settings.push_back({13, "0", "report positions in mm: joint programs are in mm"});
  file.settings.push_back(
      {11, setting_value(machine.controller()->junction_deviation), "junction deviation, mm"});
  struct Column {
    int base;
    std::string what;
  };
  const Column columns[] = {
      {100, "steps/"}, {110, "max rate, "}, {120, "acceleration, "}, {130, "max travel, "}};
  for (const Column& column : columns) {
    for (const auto& [axis, j] : order) {
      const machine::JointSpec& joint = machine.joints()[static_cast<std::size_t>(j)];
      const std::string unit = joint.interface_unit();
      double value = 0.0;
      std::string what = column.what + unit;
      if (column.base == 100) {
        value = *joint.steps_per_unit;
      } else if (column.base == 110) {
        value = joint.to_interface(joint.max_velocity) * 60.0;
        what += "/min";
      } else if (column.base == 120) {
        value = joint.to_interface(joint.max_acceleration);
        what += "/s^2";
      } else {
        value = joint.to_interface(joint.max) - joint.to_interface(joint.min);
        what += ": its max - min";
      }
      ControllerSetting setting{column.base + axis, setting_value(value), ""};
      const std::size_t prefix = 1 + std::to_string(setting.number).size() + 1 +
                                 setting.value.size() + 2 + 1;  // "$N=V (" and ")"
      setting.comment = axis_comment(machine.joints()[static_cast<std::size_t>(j)].axis_letter,
                                     joint.name, what, kMaxLine - prefix);
      file.settings.push_back(setting);
    }
  }
  for (const auto& [axis, j] : order) {
    const std::string warning =
        step_rate_warning(machine, machine.joints()[static_cast<std::size_t>(j)]);
    if (!warning.empty()) file.warnings.push_back(warning);
  }
  return file;
}

std::string ControllerSettingsFile::text() const {
  std::string text;
  for (const ControllerSetting& setting : settings) {
    text += "$" + std::to_string(setting.number) + "=" + setting.value + " (" +
            grbl_comment_text(setting.comment) + ")\n";
  }
  return text;
}

}  // namespace pkm::post
