// pkm ik, pkm fk, pkm check.
#include <cstdio>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>

#include "app.hpp"

namespace pkm::app {

namespace {

struct IkOptions {
  std::string machine;
  bool json = false;
  std::vector<double> pose;
};

struct FkOptions {
  std::string machine;
  bool json = false;
  std::vector<double> seed;
  std::vector<double> joints;
};

struct CheckOptions {
  std::string machine;
  bool json = false;
};

nlohmann::json pose_json(const Pose& pose) {
  return {{"x", pose.position_mm.x()},
          {"y", pose.position_mm.y()},
          {"z", pose.position_mm.z()},
          {"a", radians_to_degrees(pose.orientation_rad.x())},
          {"b", radians_to_degrees(pose.orientation_rad.y())},
          {"c", radians_to_degrees(pose.orientation_rad.z())}};
}

void print_pose(const Machine& machine, const Pose& pose) {
  const Vector6d values = pose.as_vector();
  for (int axis = 0; axis < kPoseSize; ++axis) {
    if (!machine.kinematics().dof().controls(axis)) continue;
    const bool angle = axis >= 3;
    std::printf("%s = %.6f %s\n", std::string(kAxisNames[axis]).c_str(),
                angle ? radians_to_degrees(values[axis]) : values[axis], angle ? "deg" : "mm");
  }
}

void run_ik(const IkOptions& options) {
  const Machine machine = load_machine_or_default(options.machine);
  const Pose pose = pose_from_arguments(machine, options.pose);
  JointVector joints;
  const Status status = machine.inverse(pose, joints);
  if (!status.ok()) {
    throw CommandError("pose is not reachable on " + machine.name() + ": " +
                       machine.describe(status));
  }
  if (options.json) {
    nlohmann::json values = nlohmann::json::array();
    for (int i = 0; i < joints.size(); ++i) {
      values.push_back(machine.joints()[i].to_interface(joints[i]));
    }
    std::cout << nlohmann::json{{"joints", values}, {"names", machine.joint_names()}}.dump()
              << "\n";
    return;
  }
  for (int i = 0; i < joints.size(); ++i) {
    const JointSpec& joint = machine.joints()[i];
    std::printf("%s = %.6f %s\n", joint.name.c_str(), joint.to_interface(joints[i]),
                joint.interface_unit());
  }
}

void run_fk(const FkOptions& options) {
  const Machine machine = load_machine_or_default(options.machine);
  if (options.joints.size() != machine.joints().size()) {
    throw CommandError(machine.name() + " has " + std::to_string(machine.joints().size()) +
                       " joints; got " + std::to_string(options.joints.size()) + " values");
  }
  JointVector joints(static_cast<int>(options.joints.size()));
  for (std::size_t i = 0; i < options.joints.size(); ++i) {
    joints[static_cast<int>(i)] = machine.joints()[i].from_interface(options.joints[i]);
  }
  Pose pose = options.seed.empty() ? machine.home() : pose_from_arguments(machine, options.seed);
  const Status status = machine.forward(joints, pose);
  if (!status.ok()) {
    throw CommandError("no pose for these joints on " + machine.name() + ": " +
                       machine.describe(status));
  }
  if (options.json) {
    std::cout << nlohmann::json{{"pose", pose_json(pose)}}.dump() << "\n";
    return;
  }
  print_pose(machine, pose);
}

void run_check(const CheckOptions& options) {
  const Machine machine = load_machine_or_default(options.machine);
  const Kinematics& kinematics = machine.kinematics();
  JointVector home_joints;
  machine.inverse(machine.home(), home_joints);  // checked when the file was loaded
  const std::vector<AxisExtent> extents = reachable_extent(machine);
  if (options.json) {
    nlohmann::json joints = nlohmann::json::array();
    for (std::size_t i = 0; i < machine.joints().size(); ++i) {
      const JointSpec& joint = machine.joints()[i];
      joints.push_back({{"name", joint.name},
                        {"axis", std::string(1, joint.axis_letter)},
                        {"unit", joint.interface_unit()},
                        {"min", joint.to_interface(joint.min)},
                        {"max", joint.to_interface(joint.max)},
                        {"max_velocity", joint.to_interface(joint.max_velocity)},
                        {"max_acceleration", joint.to_interface(joint.max_acceleration)},
                        {"home", joint.to_interface(home_joints[static_cast<int>(i)])}});
    }
    nlohmann::json extent = nlohmann::json::object();
    for (const AxisExtent& e : extents) {
      const bool angle = e.axis >= 3;
      extent[std::string(kAxisNames[e.axis])] = {angle ? radians_to_degrees(e.min) : e.min,
                                                 angle ? radians_to_degrees(e.max) : e.max};
    }
    nlohmann::json parameters = nlohmann::json::array();
    for (const Parameter& p : kinematics.parameters()) {
      parameters.push_back({{"name", p.name}, {"value", p.value}, {"unit", p.unit}});
    }
    std::cout << nlohmann::json{{"name", machine.name()},
                                {"source", machine.source()},
                                {"type", std::string(kinematics.type())},
                                {"valid", true},
                                {"joints", joints},
                                {"home", pose_json(machine.home())},
                                {"extent", extent},
                                {"parameters", parameters}}
                     .dump(2)
              << "\n";
    return;
  }
  std::printf("%s\n  file: %s\n  kinematics: %s, %d joints, controls", machine.name().c_str(),
              machine.source().c_str(), std::string(kinematics.type()).c_str(),
              kinematics.joint_count());
  for (int axis = 0; axis < kPoseSize; ++axis) {
    if (kinematics.dof().controls(axis)) std::printf(" %s", std::string(kAxisNames[axis]).c_str());
  }
  std::printf("\n  joints (position at home, limits, max velocity and acceleration):\n");
  for (std::size_t i = 0; i < machine.joints().size(); ++i) {
    const JointSpec& joint = machine.joints()[i];
    const char* unit = joint.interface_unit();
    std::printf("    %-10s %c  %12.4f %s  in [%.4f, %.4f]  %.1f %s/s  %.1f %s/s^2\n",
                joint.name.c_str(), joint.axis_letter,
                joint.to_interface(home_joints[static_cast<int>(i)]), unit,
                joint.to_interface(joint.min), joint.to_interface(joint.max),
                joint.to_interface(joint.max_velocity), unit,
                joint.to_interface(joint.max_acceleration), unit);
  }
  std::printf("  cartesian: max feed %.1f mm/min, max acceleration %.1f mm/s^2\n",
              machine.cartesian().max_feed_mm_per_min,
              machine.cartesian().max_acceleration_mm_per_s2);
  std::printf("  home:\n");
  print_pose(machine, machine.home());
  std::printf("  reachable extent along lines through home (IK and joint limits):\n");
  for (const AxisExtent& e : extents) {
    const bool angle = e.axis >= 3;
    std::printf("    %s  %12.4f .. %12.4f %s\n", std::string(kAxisNames[e.axis]).c_str(),
                angle ? radians_to_degrees(e.min) : e.min,
                angle ? radians_to_degrees(e.max) : e.max, angle ? "deg" : "mm");
  }
  std::printf("  ok: machine file is valid\n");
}

}  // namespace

void register_kinematics_commands(CLI::App& app) {
  auto ik = std::make_shared<IkOptions>();
  CLI::App* ik_command =
      app.add_subcommand("ik", "Joint values for a tool pose (inverse kinematics)");
  ik_command->add_option("-m,--machine", ik->machine, "Machine file (default: embedded hexapod)");
  ik_command->add_flag("--json", ik->json, "Print {\"joints\": [..], \"names\": [..]}");
  ik_command->add_option("pose", ik->pose, "x y z [a b c] in mm and deg")
      ->required()
      ->check(number_in(-kMaxCoordinate, kMaxCoordinate));
  ik_command->callback([ik] { run_ik(*ik); });

  auto fk = std::make_shared<FkOptions>();
  CLI::App* fk_command =
      app.add_subcommand("fk", "Tool pose for joint values (forward kinematics)");
  fk_command->add_option("-m,--machine", fk->machine, "Machine file (default: embedded hexapod)");
  fk_command->add_flag("--json", fk->json, "Print {\"pose\": {\"x\": .., ..}}");
  fk_command->add_option("--seed", fk->seed, "Pose to start from, x y z [a b c] (default: home)")
      ->expected(2, 6)
      ->check(number_in(-kMaxCoordinate, kMaxCoordinate));
  fk_command->add_option("joints", fk->joints, "Joint values in mm (deg for rotary joints)")
      ->required()
      ->check(number_in(-kMaxCoordinate, kMaxCoordinate));
  fk_command->callback([fk] { run_fk(*fk); });

  auto check = std::make_shared<CheckOptions>();
  CLI::App* check_command = app.add_subcommand(
      "check", "Validate a machine file; print joints, limits and reachable extent");
  check_command->add_option("-m,--machine", check->machine,
                            "Machine file (default: embedded hexapod)");
  check_command->add_flag("--json", check->json, "Print the summary as JSON");
  check_command->callback([check] { run_check(*check); });
}

}  // namespace pkm::app
