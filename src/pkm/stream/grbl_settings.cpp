#include "pkm/stream/grbl_settings.hpp"

#include <cstdio>

#include "pkm/post/joint_program.hpp"
#include "pkm/stream/grbl_position.hpp"

namespace pkm::stream {

namespace {

std::string setting_line(int number, double value) {
  char text[64];
  std::snprintf(text, sizeof text, "$%d=%.3f", number, value);
  return text;
}

}  // namespace

std::vector<GrblSetting> grbl_settings(const Machine& machine) {
  std::vector<GrblSetting> settings;
  for (const JointSpec& joint : machine.joints()) {
    const int axis = grbl_axis(joint);
    const std::string unit = joint.interface_unit();
    if (joint.steps_per_unit) {
      settings.push_back(
          {setting_line(100 + axis, *joint.steps_per_unit), joint.name + ": steps per " + unit});
    }
    // Velocity and acceleration are mm or rad per second inside; grbl's rate is per minute.
    settings.push_back({setting_line(110 + axis, joint.to_interface(joint.max_velocity) * 60.0),
                        joint.name + ": max rate, " + unit + "/min"});
    settings.push_back({setting_line(120 + axis, joint.to_interface(joint.max_acceleration)),
                        joint.name + ": acceleration, " + unit + "/s^2"});
  }
  if (machine.controller()) {
    settings.push_back(
        {setting_line(11, machine.controller()->junction_deviation), "junction deviation, mm"});
  }
  return settings;
}

std::string grbl_zero_line(const Machine& machine, const JointVector& joints) {
  std::string line = "G10 L20 P1";
  const post::DialectRules rules = post::rules_of(post::Dialect::grbl);
  for (std::size_t i = 0; i < machine.joints().size(); ++i) {
    line += post::joint_word(machine.joints()[i], joints[static_cast<Eigen::Index>(i)], rules);
  }
  return line;
}

}  // namespace pkm::stream
