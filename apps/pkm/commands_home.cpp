// pkm home: the homing program of a machine with switches, or the set-position block for joint
// readings measured by hand, or for home's joints where the effector was put at home by hand
// (a Hangprinter's or a Maslow's, without switches) (docs/homing.md).
#include <algorithm>
#include <cstdio>
#include <memory>

#include "app.hpp"
#include "pkm/files/atomic_file.hpp"
#include "pkm/post/homing_program.hpp"

namespace pkm::app {

namespace {

struct HomeOptions {
  std::string machine;
  std::string output;
  std::string dialect = "linuxcnc";
  std::vector<double> measured;
  bool at_home = false;
};

// "left 160.000 mm, right 160.000 mm"
std::string readings_text(const machine::Machine& machine, const std::vector<int>& joints,
                          const kinematics::JointVector& values) {
  std::string text;
  for (const int joint : joints) {
    char value[48];
    std::snprintf(value, sizeof value, " %.3f %s", machine.joint_to_file(joint, values[joint]),
                  machine.joint_file_unit(joint));
    text +=
        (text.empty() ? "" : ", ") + machine.joints()[static_cast<std::size_t>(joint)].name + value;
  }
  return text;
}

// What the homing program does, for the terminal: the joints in order, how far a probe may stop
// past its switch where the controller sets the joint there (LinuxCNC sets it at the trip
// point), where it ends.
std::string homing_summary(const machine::Machine& machine, post::Dialect dialect) {
  std::string names;
  std::string overshoot;
  for (const machine::HomingMove& move : machine::homing_moves(machine)) {
    if (move.kind != machine::HomingMoveKind::probe) continue;
    const machine::JointSpec& joint = machine.joints()[static_cast<std::size_t>(move.homed_joint)];
    char text[96];
    std::snprintf(text, sizeof text, "%s %.4f %s", joint.name.c_str(),
                  machine.joint_to_file(move.homed_joint, move.stop_distance),
                  machine.joint_file_unit(move.homed_joint));
    names += (names.empty() ? "" : ", ") + joint.name;
    overshoot += (overshoot.empty() ? "" : ", ") + std::string(text);
  }
  const std::string where = dialect == post::Dialect::linuxcnc
                                ? "each set at its probe's trip point"
                                : "each set where it stopped, past its switch by up to " +
                                      overshoot + " at max_acceleration";
  return "homes " + names + " on their switches (" + where + "), then moves to home " +
         machine.format_pose(machine.home());
}

void run_home(const HomeOptions& options) {
  refuse_overwriting_input(options.output, {{"the machine file", options.machine}});
  const machine::Machine machine = machine::load_machine(options.machine);
  const post::Dialect dialect = post::dialect_named(options.dialect);
  std::string program;
  std::string summary;
  try {
    if (options.at_home) {
      const post::MeasuredJoints at_home = post::joints_at_home(machine);
      program = post::set_position_program(machine, dialect, at_home);
      summary = "sets " +
                readings_text(machine, post::measured_joint_indices(machine), at_home.joints) +
                ", the joints at home " + machine.format_pose(at_home.pose);
    } else if (options.measured.empty()) {
      if (!machine.homing()) {
        throw CommandError(machine.source() +
                           ": the machine file has no [homing] table (docs/homing.md): without "
                           "switches, put the effector at home and use --at-home, or measure "
                           "the joints (--measured)");
      }
      program = post::homing_program(machine, dialect);
      summary = homing_summary(machine, dialect);
    } else {
      const post::MeasuredJoints measured = post::measured_joints(machine, options.measured);
      program = post::set_position_program(machine, dialect, measured);
      summary = "sets " +
                readings_text(machine, post::measured_joint_indices(machine), measured.joints) +
                ": pose " + machine.format_pose(measured.pose);
    }
  } catch (const std::invalid_argument& error) {
    throw CommandError(error.what());
  }
  files::write_file_atomically(options.output, program);
  std::printf("%s: %s\n", options.output.c_str(), summary.c_str());
}

}  // namespace

void register_home_commands(CLI::App& app) {
  auto options = std::make_shared<HomeOptions>();
  CLI::App* command = app.add_subcommand(
      "home",
      "Joint-space G-code that homes a machine on its switches ([homing]), or sets "
      "joint readings measured by hand (--measured)");
  command->add_option("-m,--machine", options->machine, "Machine file")->required();
  command->add_option("-o,--output", options->output, "The program to write")->required();
  command->add_option("--dialect", options->dialect, "linuxcnc (default), mach3, grbl or grblhal")
      ->check(CLI::IsMember({"linuxcnc", "mach3", "grbl", "grblhal"}));
  command
      ->add_option("--measured", options->measured,
                   "Joint readings measured by hand at rest, one per joint of the mechanism "
                   "(not pass-through joints such as a pen's Z), in the machine file's units")
      ->check(number_in(-kMaxCoordinate, kMaxCoordinate))
      ->excludes(command->add_flag(
          "--at-home", options->at_home,
          "The effector stands at home (put there by hand: a machine without switches, such as "
          "a Hangprinter or a Maslow): set each joint to its value there"));
  command->callback([options] { run_home(*options); });
}

}  // namespace pkm::app
