#include "pkm/verify/joint_words.hpp"

#include <string_view>

namespace pkm::verify {

namespace {
constexpr std::string_view kLetters = "XYZABCUVW";
}  // namespace

JointWords::JointWords(const machine::Machine& machine) : machine_(machine) {
  for (const machine::JointSpec& joint : machine.joints()) {
    index_.push_back(static_cast<int>(kLetters.find(joint.axis_letter)));
  }
}

gcode::InterpreterOptions JointWords::program_options(
    const kinematics::JointVector& start, const gcode::InterpreterOptions& bounds) const {
  gcode::InterpreterOptions options;
  options.max_loop_iterations = bounds.max_loop_iterations;
  options.max_program_iterations = bounds.max_program_iterations;
  for (std::size_t i = 0; i < index_.size(); ++i) {
    options.start_position[static_cast<std::size_t>(index_[i])] =
        machine_.joints()[i].to_interface(start[static_cast<int>(i)]);
  }
  const machine::ToolChannel& tool = machine_.tool();
  if (tool.z == machine::ToolZ::pen) options.event_lines = {tool.down_command, tool.up_command};
  return options;
}

kinematics::JointVector JointWords::read(const gcode::Canon& canon) const {
  const double scale = canon.units == gcode::LengthUnits::inch ? 25.4 : 1.0;
  kinematics::JointVector q(static_cast<int>(index_.size()));
  for (std::size_t i = 0; i < index_.size(); ++i) {
    const machine::JointSpec& joint = machine_.joints()[i];
    const double value = canon.end[static_cast<std::size_t>(index_[i])];
    q[static_cast<int>(i)] = joint.kind == kinematics::JointKind::rotary
                                 ? geometry::degrees_to_radians(value)
                                 : value * scale;
  }
  return q;
}

}  // namespace pkm::verify
