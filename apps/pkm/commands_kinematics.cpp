// pkm ik, pkm fk, pkm check. They speak the machine file's units: lengths in its `units` (mm or
// inch), angles in degrees, for poses and joints alike.
#include <cstdio>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>

#include "app.hpp"
#include "pkm/kinematics/cable_plotter.hpp"

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

nlohmann::json pose_json(const Machine& machine, const Pose& pose) {
  const Vector6d values = pose.as_vector();
  nlohmann::json json = nlohmann::json::object();
  for (int axis = 0; axis < kPoseSize; ++axis) {
    json[std::string(kAxisNames[axis])] = machine.axis_to_file(axis, values[axis]);
  }
  return json;
}

void print_pose(const Machine& machine, const Pose& pose) {
  const Vector6d values = pose.as_vector();
  for (int axis = 0; axis < kPoseSize; ++axis) {
    if (!machine.kinematics().dof().controls(axis)) continue;
    std::printf("%s = %.6f %s\n", std::string(kAxisNames[axis]).c_str(),
                machine.axis_to_file(axis, values[axis]) + 0.0, machine.axis_file_unit(axis));
  }
}

// A pose typed in the machine file's units, to mm and rad (angles default to home's).
Pose pose_in_file_units(const Machine& machine, std::vector<double> values) {
  for (std::size_t i = 0; i < values.size() && i < 3; ++i) values[i] *= machine.mm_per_unit();
  return pose_from_arguments(machine, values);
}

// A hanging machine with a weight: how hard each cable pulls at rest, how far the effector tilts.
void print_cable_statics(const Machine& machine, const Pose& pose) {
  const auto* plotter = dynamic_cast<const CablePlotterKinematics*>(&machine.kinematics());
  if (plotter == nullptr || !(plotter->geometry().effector_mass_kg > 0.0)) return;
  CableStatics statics;
  if (!plotter->statics(pose, Eigen::Vector2d::Zero(), statics).ok()) return;
  for (int cable = 0; cable < 2; ++cable) {
    std::printf("tension %s = %.3f N (%.3f .. %.3f along it)\n",
                machine.joints()[static_cast<std::size_t>(cable)].name.c_str(),
                statics.tension_N[cable], statics.lowest_N[cable], statics.highest_N[cable]);
  }
  if (plotter->geometry().tilts()) {
    std::printf("tilt = %.4f deg\n", radians_to_degrees(statics.tilt_rad));
  }
}

void run_ik(const IkOptions& options) {
  const Machine machine = load_machine_or_default(options.machine);
  const Pose pose = pose_in_file_units(machine, options.pose);
  JointVector joints;
  const Status status = machine.inverse(pose, joints);
  if (!status.ok()) {
    throw CommandError("pose is not reachable on " + machine.name() + ": " +
                       machine.explain(pose, status));
  }
  if (options.json) {
    nlohmann::json values = nlohmann::json::array();
    for (int i = 0; i < joints.size(); ++i) values.push_back(machine.joint_to_file(i, joints[i]));
    std::cout << nlohmann::json{{"joints", values},
                                {"names", machine.joint_names()},
                                {"units", machine.length_unit()}}
                     .dump()
              << "\n";
    return;
  }
  for (int i = 0; i < joints.size(); ++i) {
    std::printf("%s = %.6f %s\n", machine.joints()[i].name.c_str(),
                machine.joint_to_file(i, joints[i]), machine.joint_file_unit(i));
  }
  print_cable_statics(machine, pose);
}

void run_fk(FkOptions options) {
  const Machine machine = load_machine_or_default(options.machine);
  const std::size_t joint_count = machine.joints().size();
  if (!options.seed.empty() && options.joints.size() < joint_count) {
    // `--seed x y z a b c j1 .. j6`: the option takes every number; the last ones are the joints.
    options.seed.insert(options.seed.end(), options.joints.begin(), options.joints.end());
    const std::size_t split = options.seed.size() - std::min(options.seed.size(), joint_count);
    options.joints.assign(options.seed.begin() + static_cast<std::ptrdiff_t>(split),
                          options.seed.end());
    options.seed.resize(split);
  }
  if (options.joints.size() != joint_count) {
    throw CommandError(machine.name() + " has " + std::to_string(joint_count) + " joints; got " +
                       std::to_string(options.joints.size()) + " values");
  }
  JointVector joints(static_cast<int>(joint_count));
  for (std::size_t i = 0; i < joint_count; ++i) {
    joints[static_cast<int>(i)] = machine.joint_from_file(static_cast<int>(i), options.joints[i]);
  }
  Pose pose = machine.home();
  if (!options.seed.empty()) {
    try {
      pose = pose_in_file_units(machine, options.seed);
    } catch (const CommandError& error) {
      throw CommandError(std::string(error.what()) + " for --seed, before the " +
                         std::to_string(joint_count) + " joint values");
    }
  }
  const Status status = machine.forward(joints, pose);
  if (!status.ok()) {
    const bool limit = status.code == StatusCode::joint_limit && status.joint >= 0;
    throw CommandError("no pose for these joints on " + machine.name() + ": " +
                       (limit ? machine.explain_joint(status.joint, joints[status.joint])
                              : machine.describe(status)));
  }
  if (options.json) {
    std::cout << nlohmann::json{{"pose", pose_json(machine, pose)},
                                {"units", machine.length_unit()}}
                     .dump()
              << "\n";
    return;
  }
  print_pose(machine, pose);
}

struct CheckSummary {
  JointVector home_joints;
  std::vector<AxisExtent> extents;
  double conditioning = 0.0;  // relative_conditioning_at_home
};

nlohmann::json check_json(const Machine& machine, const CheckSummary& summary) {
  nlohmann::json joints = nlohmann::json::array();
  for (int i = 0; i < static_cast<int>(machine.joints().size()); ++i) {
    const JointSpec& joint = machine.joints()[static_cast<std::size_t>(i)];
    joints.push_back({{"name", joint.name},
                      {"axis", std::string(1, joint.axis_letter)},
                      {"unit", machine.joint_file_unit(i)},
                      {"min", machine.joint_to_file(i, joint.min)},
                      {"max", machine.joint_to_file(i, joint.max)},
                      {"max_velocity", machine.joint_to_file(i, joint.max_velocity)},
                      {"max_acceleration", machine.joint_to_file(i, joint.max_acceleration)},
                      {"home", machine.joint_to_file(i, summary.home_joints[i])}});
  }
  nlohmann::json extent = nlohmann::json::object();
  for (const AxisExtent& e : summary.extents) {
    extent[std::string(kAxisNames[e.axis])] = {machine.axis_to_file(e.axis, e.min),
                                               machine.axis_to_file(e.axis, e.max)};
  }
  nlohmann::json envelope = nullptr;
  if (machine.cartesian().has_envelope()) {
    envelope = nlohmann::json::object();
    for (int axis = 0; axis < kPoseSize; ++axis) {
      if (!machine.kinematics().dof().controls(axis)) continue;
      envelope[std::string(kAxisNames[axis])] = {
          machine.axis_to_file(axis, machine.cartesian().envelope_min[axis]),
          machine.axis_to_file(axis, machine.cartesian().envelope_max[axis])};
    }
  }
  nlohmann::json parameters = nlohmann::json::array();
  for (const Parameter& p : machine.kinematics().parameters()) {
    parameters.push_back({{"name", p.name}, {"value", p.value}, {"unit", p.unit}});
  }
  return {{"name", machine.name()},
          {"source", machine.source()},
          {"type", std::string(machine.kinematics().type())},
          {"units", machine.length_unit()},
          {"valid", true},
          {"singular_at_home", summary.conditioning < kSingularAtHome},
          {"conditioning_at_home", summary.conditioning},
          {"joints", joints},
          {"home", pose_json(machine, machine.home())},
          {"envelope", envelope},
          {"extent", extent},
          {"parameters", parameters}};
}

void print_check_joints(const Machine& machine, const CheckSummary& summary) {
  std::printf("  joints (position at home, limits, max velocity and acceleration):\n");
  for (int i = 0; i < static_cast<int>(machine.joints().size()); ++i) {
    const JointSpec& joint = machine.joints()[static_cast<std::size_t>(i)];
    const char* unit = machine.joint_file_unit(i);
    std::printf("    %-10s %c  %12.4f %s  range [%.4f, %.4f]  %.1f %s/s  %.1f %s/s^2\n",
                joint.name.c_str(), joint.axis_letter,
                machine.joint_to_file(i, summary.home_joints[i]), unit,
                machine.joint_to_file(i, joint.min), machine.joint_to_file(i, joint.max),
                machine.joint_to_file(i, joint.max_velocity), unit,
                machine.joint_to_file(i, joint.max_acceleration), unit);
  }
}

void print_check(const Machine& machine, const CheckSummary& summary) {
  const Kinematics& kinematics = machine.kinematics();
  std::printf("%s\n  file: %s\n  units: %s and deg\n  kinematics: %s, %d joints, controls",
              machine.name().c_str(), machine.source().c_str(),
              machine.units() == LengthUnit::inch ? "inch" : "mm",
              std::string(kinematics.type()).c_str(), kinematics.joint_count());
  for (int axis = 0; axis < kPoseSize; ++axis) {
    if (kinematics.dof().controls(axis)) std::printf(" %s", std::string(kAxisNames[axis]).c_str());
  }
  std::printf("\n");
  print_check_joints(machine, summary);
  const double per_unit = machine.mm_per_unit();
  std::printf("  cartesian: max feed %.1f %s/min, max acceleration %.1f %s/s^2\n",
              machine.cartesian().max_feed_mm_per_min / per_unit, machine.length_unit(),
              machine.cartesian().max_acceleration_mm_per_s2 / per_unit, machine.length_unit());
  std::printf("  home:\n");
  print_pose(machine, machine.home());
  std::printf("  reachable extent along lines through home (IK, joint limits%s):\n",
              machine.cartesian().has_envelope() ? ", work envelope" : "");
  for (const AxisExtent& e : summary.extents) {
    const bool clipped = machine.cartesian().envelope_min[e.axis] == e.min ||
                         machine.cartesian().envelope_max[e.axis] == e.max;
    std::printf("    %s  %12.4f .. %12.4f %s%s\n", std::string(kAxisNames[e.axis]).c_str(),
                machine.axis_to_file(e.axis, e.min) + 0.0,
                machine.axis_to_file(e.axis, e.max) + 0.0, machine.axis_file_unit(e.axis),
                clipped ? "  (clipped by the envelope)" : "");
  }
  if (summary.conditioning < kSingularAtHome) {
    std::printf(
        "  warning: the machine is singular at home (relative smallest singular value of its "
        "jacobian %.3g): some motion of the tool moves no joint, or the joints fight\n",
        summary.conditioning);
  }
  std::printf("  ok: machine file is valid\n");
}

void run_check(const CheckOptions& options) {
  const Machine machine = load_machine_or_default(options.machine);
  CheckSummary summary;
  machine.inverse(machine.home(), summary.home_joints);  // checked when the file was loaded
  summary.extents = reachable_extent(machine);
  summary.conditioning = relative_conditioning_at_home(machine);
  if (options.json) {
    std::cout << check_json(machine, summary).dump(2) << "\n";
  } else {
    print_check(machine, summary);
  }
}

}  // namespace

void register_kinematics_commands(CLI::App& app) {
  auto ik = std::make_shared<IkOptions>();
  CLI::App* ik_command =
      app.add_subcommand("ik", "Joint values for a tool pose (inverse kinematics)");
  ik_command->add_option("-m,--machine", ik->machine, "Machine file (default: embedded hexapod)");
  ik_command->add_flag("--json", ik->json, "Print {\"joints\": [..], \"names\": [..]}");
  ik_command->add_option("pose", ik->pose, "x y z [a b c] in the machine file's units and deg")
      ->required()
      ->check(number_in(-kMaxCoordinate, kMaxCoordinate));
  ik_command->callback([ik] { run_ik(*ik); });

  auto fk = std::make_shared<FkOptions>();
  CLI::App* fk_command =
      app.add_subcommand("fk", "Tool pose for joint values (forward kinematics)");
  fk_command->add_option("-m,--machine", fk->machine, "Machine file (default: embedded hexapod)");
  fk_command->add_flag("--json", fk->json, "Print {\"pose\": {\"x\": .., ..}}");
  fk_command
      ->add_option("--seed", fk->seed,
                   "Pose to start from, x y z [a b c] (default: home); the joint values may "
                   "follow it directly")
      ->expected(2, -1)
      ->check(number_in(-kMaxCoordinate, kMaxCoordinate));
  fk_command
      ->add_option("joints", fk->joints,
                   "Joint values in the machine file's units (deg for rotary joints)")
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
