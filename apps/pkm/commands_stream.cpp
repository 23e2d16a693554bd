// pkm stream: a job sent to a grbl-class controller (or grbl-sim) line by line with grbl's
// character counting, posted on the fly or read as a joint program, stopped cleanly at a refusal
// or Ctrl-C.
#include <algorithm>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <optional>
#include <string>

#include "app.hpp"
#include "pkm/controller/grbl_planner.hpp"
#include "pkm/gcode/gcode_error.hpp"
#include "pkm/post/grbl_settings.hpp"
#include "pkm/post/homing_program.hpp"
#include "pkm/post/joint_program.hpp"
#include "pkm/stream/grbl_position.hpp"
#include "pkm/stream/grbl_sender.hpp"
#include "pkm/stream/port.hpp"
#include "progress.hpp"

#ifndef PKM_GRBL_SIM
#define PKM_GRBL_SIM ""
#endif

namespace pkm::app {

namespace {

struct StreamCommandOptions {
  std::string machine;
  std::string job;
  std::string port;
  int baud = 0;  // 0: the [controller] table's, else 115200
  bool dry_run = false;
  bool joint_program = false;
  std::string record_steps;
  double step_interval_s = 0.01;
  double sim_clock = 0.5;
  std::string grbl_sim;
  double tolerance = 0.0;
  std::vector<double> origin;
};

volatile std::sig_atomic_t interrupted = 0;
extern "C" void on_interrupt(int signal_number) {
  interrupted = signal_number;
}

// Ctrl-C (and a kill's SIGTERM) raises the flag the sender looks at between lines; without
// SA_RESTART, so that a wait in poll() ends at once. The previous handlers come back at the end.
class InterruptFlag {
 public:
  InterruptFlag() {
    interrupted = 0;
    struct sigaction action {};
    action.sa_handler = on_interrupt;
    sigemptyset(&action.sa_mask);
    sigaction(SIGINT, &action, &previous_);
    sigaction(SIGTERM, &action, &previous_term_);
  }
  ~InterruptFlag() {
    sigaction(SIGINT, &previous_, nullptr);
    sigaction(SIGTERM, &previous_term_, nullptr);
  }
  InterruptFlag(const InterruptFlag&) = delete;
  InterruptFlag& operator=(const InterruptFlag&) = delete;

 private:
  struct sigaction previous_ {};
  struct sigaction previous_term_ {};
};

std::filesystem::path grbl_sim_executable(const StreamCommandOptions& options) {
  if (!options.grbl_sim.empty()) return options.grbl_sim;
  if (const char* from_environment = std::getenv("PKM_GRBL_SIM")) return from_environment;
  if (std::string(PKM_GRBL_SIM).empty()) {
    throw CommandError(
        "--dry-run: no grbl-sim known: give --grbl-sim PATH (build it with "
        "../shared/controllers/grbl-1.1h/build-sim DEST)");
  }
  return PKM_GRBL_SIM;
}

std::string step_file_partial(const std::string& path) {
  return path + ".partial";
}

stream::Port open_port(const machine::Machine& machine, const StreamCommandOptions& options) {
  if (options.dry_run) {
    stream::Port::SimulatorOptions simulator;
    simulator.executable = grbl_sim_executable(options);
    if (!options.record_steps.empty())
      simulator.step_file = step_file_partial(options.record_steps);
    simulator.step_interval_s = options.step_interval_s;
    simulator.clock_factor = options.sim_clock;
    return stream::Port::start_simulator(simulator);
  }
  const int baud = options.baud > 0       ? options.baud
                   : machine.controller() ? machine.controller()->baud
                                          : 115200;
  return stream::Port::open_serial(options.port, baud);
}

// Sends the machine's $ settings to grbl-sim, the lines `pkm export grbl` writes: a real
// controller keeps its own (the user checks and sends them).
void send_settings(const machine::Machine& machine, stream::GrblSender& sender) {
  if (!machine.controller()) {
    throw CommandError(machine.source() +
                       ": --dry-run needs the machine's [controller] table and each joint's "
                       "steps_per_unit, for the $ settings grbl-sim runs with (docs/grbl.md)");
  }
  post::ControllerSettingsFile settings;
  try {
    settings = post::controller_settings(machine, machine.controller()->kind);
  } catch (const std::invalid_argument& error) {
    throw CommandError(error.what());
  }
  for (const post::ControllerSetting& setting : settings.settings) {
    sender.send("$" + std::to_string(setting.number) + "=" + setting.value, 0, 0);
  }
  // grbl-sim starts at step 0: there it stands at the machine's home, as a user zeroes a plotter
  // (docs/grbl.md).
  kinematics::JointVector home_joints;
  if (machine.inverse(machine.home(), home_joints).code != kinematics::StatusCode::ok) {
    throw CommandError(
        machine.source() + ": the home pose has no joint values: " +
        machine.explain(machine.home(), machine.inverse(machine.home(), home_joints)));
  }
  sender.send(post::set_position_line(machine, post::Dialect::grbl, home_joints), 0, 0);
  for (const std::string& warning : settings.warnings) {
    std::fprintf(stderr, "pkm: warning: %s\n", warning.c_str());
  }
}

// The joint program's lines as they are, numbered as in the file; blank lines are not sent.
void stream_joint_program(const std::string& path, stream::GrblSender& sender) {
  std::ifstream file(path);
  if (!file) throw CommandError(path + ": cannot open");
  std::string line;
  long number = 0;
  while (std::getline(file, line)) {
    ++number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.find_first_not_of(" \t") == std::string::npos) continue;
    sender.send(line, number, 0);
  }
  if (file.bad()) throw CommandError(path + ": read error after line " + std::to_string(number));
}

// How the Cartesian job is posted as it is sent: post's, in the controller's dialect.
post::PostOptions stream_post_options(const machine::Machine& machine,
                                      const StreamCommandOptions& options) {
  post::PostOptions post_options;
  post_options.dialect =
      machine.controller() && machine.controller()->kind == machine::ControllerKind::grblhal
          ? post::Dialect::grblhal
          : post::Dialect::grbl;
  post_options.tolerance_mm = options.tolerance > 0.0
                                  ? mm_from_machine_units(machine, options.tolerance)
                                  : kDefaultTolerance_mm;
  post_options.origin = pose_vector_over(machine, post_options.origin, options.origin);
  post_options.max_blocks = post::kDefaultMaxBlocks;
  return post_options;
}

// How long the controller takes to run the program, in simulated (or real) seconds: post's model
// of grbl's planner (docs/grbl.md, "The planner model") over the joint program, or over the
// Cartesian job posted once beforehand. For the time left on the progress line only: nothing
// without a [controller] table, nor where the program cannot be read (the stream itself then
// stops at that line, saying why).
std::optional<double> predicted_program_s(const machine::Machine& machine,
                                          const StreamCommandOptions& options) {
  if (!machine.controller()) return std::nullopt;
  try {
    if (!options.joint_program) {
      const post::PostReport report =
          post::post_program(machine, options.job, gcode::InterpreterOptions{},
                             stream_post_options(machine, options), [](const std::string&) {});
      if (report.controller) return report.controller->time_s;
      return std::nullopt;
    }
    controller::GrblTimeModel model(controller::grbl_setup_of(machine));
    std::ifstream file(options.job);
    for (std::string line; std::getline(file, line);) {
      if (!line.empty() && line.back() == '\r') line.pop_back();
      if (line.find_first_not_of(" \t") != std::string::npos) model.add_line(line);
    }
    if (file.bad()) return std::nullopt;
    return model.finish().time_s;
  } catch (const std::exception&) {
    return std::nullopt;
  }
}

// The Cartesian job posted block by block into the sender: nothing held but the lines grbl has
// not answered yet.
void stream_posted_job(const machine::Machine& machine, const StreamCommandOptions& options,
                       stream::GrblSender& sender) {
  post::PostOptions post_options = stream_post_options(machine, options);
  int job_line = 0;
  post_options.on_line = [&job_line](int line) { job_line = line; };
  long program_line = 0;
  try {
    post::check_axis_letters(machine, post_options.dialect);
    post::post_program(
        machine, options.job, gcode::InterpreterOptions{}, post_options,
        [&](const std::string& line) { sender.send(line, ++program_line, job_line); });
  } catch (const gcode::GcodeError& error) {
    throw CommandError(error.what());
  } catch (const post::PostError& error) {
    throw CommandError(error.what());
  } catch (const std::invalid_argument& error) {
    throw CommandError(machine.source() + ": " + error.what());
  }
}

std::string position_text(const machine::Machine& machine, const stream::StatusReport& status,
                          geometry::Pose& last_pose) {
  if (!status.has_position) return status.state;
  if (auto pose = stream::tool_pose(machine, status.work_position, last_pose)) {
    last_pose = *pose;
    return status.state + "  " + machine.format_pose(*pose);
  }
  return status.state + "  joints outside the machine's reach";
}

void run_stream(const StreamCommandOptions& options) {
  if (!options.dry_run && options.port.empty()) {
    throw CommandError("give --port DEVICE, or --dry-run to stream into grbl-sim");
  }
  const machine::Machine machine = load_machine_or_default(options.machine);
  InterruptFlag interrupt_flag;
  stream::Port port = open_port(machine, options);
  const int rx_buffer = machine.controller() ? machine.controller()->rx_buffer_bytes : 128;
  stream::StreamTimeouts timeouts;
  if (options.dry_run) {
    // grbl-sim says its banner after a simulated second, 1 / --sim-clock s of ours; its answers
    // come as much slower.
    timeouts.banner_s = 2.0 + 1.5 / options.sim_clock;
    timeouts.silence_s = std::max(timeouts.silence_s, 2.0 / options.sim_clock);
    timeouts.idle_stall_s = std::max(timeouts.idle_stall_s, 2.0 / options.sim_clock);
  }
  stream::GrblSender sender(port.fd(), options.dry_run ? "grbl-sim" : options.port, rx_buffer,
                            timeouts);
  sender.set_interrupt_flag(&interrupted);
  StreamProgress progress("stream " + std::filesystem::path(options.job).filename().string());
  geometry::Pose last_pose = machine.home();
  std::string shown_state;
  sender.on_status = [&](const stream::StatusReport& status) {
    shown_state = position_text(machine, status, last_pose);
    progress.update(sender.lines_sent(), sender.lines_acknowledged(), shown_state);
  };
  sender.on_message = [&progress](const std::string& message) {
    progress.clear();
    std::fprintf(stderr, "grbl: %s\n", message.c_str());
  };
  long before_program = 0;  // lines sent before the program's first: settings, zeroing
  try {
    sender.await_banner();
    if (options.dry_run) send_settings(machine, sender);
    before_program = sender.lines_sent();
    if (progress.active()) {
      // grbl-sim's clock runs --sim-clock simulated seconds per second of ours.
      if (const auto predicted_s = predicted_program_s(machine, options)) {
        progress.start_program(*predicted_s / (options.dry_run ? options.sim_clock : 1.0));
      }
    }
    if (options.joint_program) {
      stream_joint_program(options.job, sender);
    } else {
      stream_posted_job(machine, options, sender);
    }
    sender.drain();
  } catch (const stream::GrblRefusal& refusal) {
    progress.clear();
    throw CommandError(std::string(refusal.what()) + "; " + sender.hold_and_reset());
  } catch (const stream::StreamInterrupted&) {
    progress.clear();
    throw CommandError(
        std::string(interrupted == SIGTERM ? "stopped by SIGTERM" : "stopped by Ctrl-C") +
        " after " + std::to_string(sender.lines_sent()) + " lines sent whole, " +
        std::to_string(sender.lines_acknowledged()) + " done: " + sender.hold_and_reset());
  } catch (const stream::StreamError& error) {
    progress.clear();
    std::string message = error.what();
    if (options.dry_run && message.find("stepping has stopped") != std::string::npos) {
      message +=
          " (grbl-sim's simulated clock stalls so at times on a busy computer: run it "
          "again, or with a lower --sim-clock)";
    }
    throw CommandError(message);
  }
  progress.clear();
  std::string where;
  if (sender.last_status())
    where = ", at " + position_text(machine, *sender.last_status(), last_pose);
  // The program's lines: not the settings before it nor the G4 P0 that waits for its end.
  std::printf("%s: %ld lines sent, every one answered ok%s\n", options.job.c_str(),
              sender.lines_sent() - before_program - 1, where.c_str());
}

}  // namespace

void register_stream_commands(CLI::App& app) {
  auto options = std::make_shared<StreamCommandOptions>();
  CLI::App* command = app.add_subcommand(
      "stream", "Send a job to a grbl controller (or grbl-sim) with grbl's character counting");
  command->add_option("-m,--machine", options->machine, "Machine file (default: embedded hexapod)");
  command
      ->add_option("job", options->job,
                   "The Cartesian G-code job (or, with --joint-program, "
                   "a joint program pkm post wrote)")
      ->required();
  CLI::Option* port =
      command->add_option("--port", options->port, "The controller's serial port (/dev/ttyUSB0)");
  command
      ->add_option("--baud", options->baud,
                   "Serial line speed, bit/s (default: the [controller] table's, else 115200)")
      ->check(CLI::Range(1, 4000000));
  CLI::Option* dry_run = command->add_flag("--dry-run", options->dry_run,
                                           "Stream into grbl-sim (grbl 1.1h compiled for Linux) "
                                           "instead, the machine's $ settings first");
  dry_run->excludes(port);
  command->add_flag("--joint-program", options->joint_program,
                    "JOB is already a joint program: send it as it is");
  command
      ->add_option("--record-steps", options->record_steps,
                   "With --dry-run: grbl-sim writes the step position of X Y Z here (its -s)")
      ->needs(dry_run)
      ->check(file_name());
  command
      ->add_option("--step-interval", options->step_interval_s,
                   "With --record-steps: simulated seconds between two rows (default 0.01)")
      ->check(number_in(1e-4, 10.0));
  command
      ->add_option("--sim-clock", options->sim_clock,
                   "With --dry-run: grbl-sim's simulated seconds per second (default 0.5: it "
                   "cannot keep up with real time on a busy computer)")
      ->check(number_in(0.01, 1.0));
  command->add_option("--grbl-sim", options->grbl_sim,
                      "grbl_sim.exe for --dry-run (default: $PKM_GRBL_SIM, else the build's)");
  command
      ->add_option("--tolerance", options->tolerance,
                   "As pkm post's: largest tool-tip deviation, in the machine file's units")
      ->check(number_in(kMinTolerance, kMaxTolerance));
  add_pose_option(*command, "--origin", options->origin,
                  "Where the job's X0 Y0 Z0 sits in machine coordinates (as pkm post's)");
  command->callback([options] {
    try {
      run_stream(*options);
    } catch (...) {
      // The record is what grbl-sim did, interrupted or not: it is kept under its name.
      if (!options->record_steps.empty()) {
        std::error_code ignored;
        std::filesystem::rename(step_file_partial(options->record_steps), options->record_steps,
                                ignored);
      }
      throw;
    }
    if (!options->record_steps.empty()) {
      std::filesystem::rename(step_file_partial(options->record_steps), options->record_steps);
    }
  });
}

}  // namespace pkm::app
