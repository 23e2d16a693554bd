#include "pkm/firmware/marlin.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "pkm/firmware/marlin_forms.hpp"

namespace pkm::firmware {
namespace {

ExportedFile write_marlin(const FirmwareMachine& machine, const ExportContext& context) {
  if (form_kind(machine.form.geometry) == FormKind::linear_delta) {
    return write_marlin_delta(machine, context);
  }
  return write_marlin_polargraph(machine, context);
}

machine::ImportedMachine read_marlin(std::string_view text, const std::string& source) {
  const MarlinDefines defines(text, source);
  const bool delta = defines.enabled("DELTA"), polargraph = defines.enabled("POLARGRAPH");
  if (delta && polargraph) {
    throw FirmwareFileError(source + ":" + std::to_string(defines.line("POLARGRAPH")) +
                            ": POLARGRAPH: DELTA is enabled too (line " +
                            std::to_string(defines.line("DELTA")) + "); enable one");
  }
  if (delta) return read_marlin_delta(defines);
  if (polargraph) return read_marlin_polargraph(defines);
  throw FirmwareFileError(source +
                          ":1: DELTA: neither #define DELTA nor #define POLARGRAPH is enabled; "
                          "pkmkit reads Marlin's linear delta and polargraph kinematics");
}

std::string joint_label(const machine::Machine& machine, int joint) {
  if (joint < 0) return "none";
  return "joint " + std::to_string(joint + 1) + " " + machine.joints()[joint].name;
}

}  // namespace

std::string define_line(const std::string& name, const std::string& value,
                        const std::string& comment) {
  std::string line = "#define " + name;
  if (!value.empty()) line += " " + value;
  if (!comment.empty()) line += "  // " + comment;
  return line + "\n";
}

std::string marlin_list(const std::vector<double>& values) {
  std::string text = "{ ";
  for (std::size_t i = 0; i < values.size(); ++i) {
    text += (i > 0 ? ", " : "") + marlin_number(values[i]);
  }
  return text + " }";
}

std::string marlin_preamble(const FirmwareMachine& machine, const ExportContext& context,
                            const char* kinematics_define) {
  std::string text;
  text += header_comment(machine, context, "// ");
  text += "// Paste into Marlin's Configuration.h: each define replaces the one of that name.\n";
  text += define_line(kinematics_define, "", "");
  text += define_line("CUSTOM_MACHINE_NAME", "\"" + machine.machine.name() + "\"", "");
  return text;
}

std::string marlin_motion_defines(const FirmwareMachine& machine, const StepperJoints& joints) {
  const std::vector<machine::JointSpec>& specs = machine.machine.joints();
  std::vector<double> steps, feed, acceleration;
  bool stock_steps = false;
  for (int k = 0; k < 3; ++k) {
    const int j = joints[k];
    const bool has_steps = j >= 0 && specs[j].steps_per_unit.has_value();
    stock_steps = stock_steps || (j >= 0 && !has_steps);
    // A joint without steps gets Marlin's stock X value (its deltas' too); a missing Z, Z's.
    steps.push_back(has_steps ? *specs[j].steps_per_unit : kMarlinStockSteps[j >= 0 ? 0 : k]);
    feed.push_back(j >= 0 ? specs[j].max_velocity : kMarlinStockFeed[k]);
    acceleration.push_back(
        std::floor(j >= 0 ? specs[j].max_acceleration : kMarlinStockAcceleration[k]));
  }
  std::string text = "// pkmkit joints: X = " + joint_label(machine.machine, joints[0]) +
                     ", Y = " + joint_label(machine.machine, joints[1]) +
                     ", Z = " + joint_label(machine.machine, joints[2]);
  text += stock_steps ? " (steps per mm: Marlin's stock values, set yours)\n" : "\n";
  text += define_line("DEFAULT_AXIS_STEPS_PER_UNIT", marlin_list(steps),
                      "steps per mm of the X Y Z steppers");
  text += define_line("DEFAULT_MAX_FEEDRATE", marlin_list(feed), "mm/s of each stepper");
  text += define_line("DEFAULT_MAX_ACCELERATION", marlin_list(acceleration),
                      "mm/s^2 of each stepper (whole numbers: Marlin holds integers)");
  const double tool_acceleration = machine.machine.cartesian().max_acceleration_mm_per_s2;
  text += define_line("DEFAULT_ACCELERATION", marlin_number(tool_acceleration),
                      "mm/s^2 of the tool along a move");
  text += define_line("DEFAULT_TRAVEL_ACCELERATION", marlin_number(tool_acceleration),
                      "mm/s^2 of the tool along a travel move");
  text += define_line("EXTRUDERS", "0", "the machine file has no extruder");
  return text;
}

WorkBox work_box(const machine::Machine& machine) {
  const machine::PoseBox reach = machine::reach_box(machine);
  const machine::CartesianLimits& limits = machine.cartesian();
  WorkBox box;
  for (int axis = 0; axis < 3; ++axis) {
    const bool controlled = reach.axes.controls(axis);
    const double reach_min = controlled ? reach.min[axis] : machine.home().as_vector()[axis];
    const double reach_max = controlled ? reach.max[axis] : machine.home().as_vector()[axis];
    box.min[axis] =
        std::isfinite(limits.envelope_min[axis]) ? limits.envelope_min[axis] : reach_min;
    box.max[axis] =
        std::isfinite(limits.envelope_max[axis]) ? limits.envelope_max[axis] : reach_max;
  }
  return box;
}

MarlinJointNames read_joint_names(const MarlinDefines& defines,
                                  const std::array<std::string, 3>& default_names) {
  MarlinJointNames result;
  result.names = default_names;
  const std::vector<MarlinDefines::Comment> lines = defines.comment_lines("pkmkit joints:");
  if (lines.empty()) return result;
  result.line = lines.front().line;
  // "X = joint 2 tower b, Y = joint 3 tower c, Z = none (steps per mm: ...)": a joint's name may
  // hold spaces, so each stepper's part runs to the next ", Y = " or ", Z = ".
  std::string text = lines.front().text;
  const std::size_t stock = text.find(" (steps per mm: Marlin's stock values");
  result.stock_steps = stock != std::string::npos;
  if (result.stock_steps) text.resize(stock);
  const std::size_t y = text.find(", Y = "), z = text.find(", Z = ");
  if (text.rfind("X = ", 0) != 0 || y == std::string::npos || z == std::string::npos || z < y) {
    joint_names_fail(defines, result, "not 'X = joint N name, Y = ..., Z = ...'");
  }
  const std::array<std::string, 3> parts = {text.substr(4, y - 4), text.substr(y + 6, z - y - 6),
                                            text.substr(z + 6)};
  for (int k = 0; k < 3; ++k) {
    if (parts[k] == "none") {
      result.order[k] = -1;
      continue;
    }
    // Each stepper one joint of the three, none twice: else a tower or cord would have no
    // geometry (the comment is pkmkit's own; Marlin ignores it).
    const char digit = parts[k].size() > 8 ? parts[k][6] : '0';
    const int joint = digit - '1';
    const bool taken = std::find(result.order.begin(), result.order.begin() + k, joint) !=
                       result.order.begin() + k;
    if (parts[k].rfind("joint ", 0) != 0 || joint < 0 || joint > 2 || parts[k][7] != ' ' || taken) {
      joint_names_fail(defines, result,
                       std::string("stepper ") + "XYZ"[k] + " = '" + parts[k] +
                           "' is not 'none' or 'joint N name' of joints 1 to 3");
    }
    result.order[k] = joint;
    result.names[k] = parts[k].substr(8);
  }
  return result;
}

void joint_names_fail(const MarlinDefines& defines, const MarlinJointNames& names,
                      const std::string& why) {
  throw FirmwareFileError(defines.source() + ":" + std::to_string(names.line) +
                          ": // pkmkit joints: " + why +
                          ", each joint once (the comment names the machine joint of each "
                          "stepper; correct it, or delete it for X Y Z = joints 1 2 3)");
}

StepperRates read_stepper_rates(const MarlinDefines& defines, const MarlinJointNames& names,
                                const std::string& kinematics_define) {
  StepperRates rates;
  for (const char* needed : {"DEFAULT_MAX_FEEDRATE", "DEFAULT_MAX_ACCELERATION"}) {
    if (!defines.enabled(needed)) {
      defines.missing(needed, kinematics_define,
                      "the steppers' rates (mm/s, mm/s^2) are the joints' limits");
    }
  }
  const std::vector<double> feed = defines.list("DEFAULT_MAX_FEEDRATE", 3);
  const std::vector<double> acceleration = defines.list("DEFAULT_MAX_ACCELERATION", 3);
  const std::optional<std::vector<double>> steps =
      defines.optional_list("DEFAULT_AXIS_STEPS_PER_UNIT", 3);
  for (int k = 0; k < 3; ++k) {
    rates.feed_mm_per_s[k] = feed[k];
    rates.acceleration_mm_per_s2[k] = acceleration[k];
  }
  if (steps && !names.stock_steps)
    rates.steps_per_mm = std::array{(*steps)[0], (*steps)[1], (*steps)[2]};
  return rates;
}

machine::ImportedMachine imported_base(const MarlinDefines& defines,
                                       const std::vector<std::string>& used) {
  machine::ImportedMachine imported;
  imported.source = defines.source();
  imported.origin = "Imported by `pkm import marlin " + defines.source() + "`";
  imported.name = defines.string_value("CUSTOM_MACHINE_NAME").value_or("Marlin machine");
  std::vector<std::string> all_used = used;
  for (const char* name : {"CUSTOM_MACHINE_NAME", "DEFAULT_MAX_FEEDRATE",
                           "DEFAULT_MAX_ACCELERATION", "DEFAULT_AXIS_STEPS_PER_UNIT",
                           "DEFAULT_ACCELERATION", "DEFAULT_TRAVEL_ACCELERATION", "EXTRUDERS"}) {
    all_used.push_back(name);
  }
  const std::vector<std::string> unused = defines.unused(all_used);
  if (!unused.empty()) {
    std::string list;
    for (std::size_t i = 0; i < unused.size() && i < 40; ++i) list += (i ? ", " : "") + unused[i];
    if (unused.size() > 40) list += ", ... (" + std::to_string(unused.size()) + " in all)";
    imported.notes.push_back("Marlin defines not imported (no kinematics in them): " + list);
  }
  return imported;
}

Target marlin_target() {
  return Target{"marlin",
                "Configuration.h",
                {FormKind::wall_plotter, FormKind::linear_delta},
                write_marlin,
                read_marlin};
}

}  // namespace pkm::firmware
