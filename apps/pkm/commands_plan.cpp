// pkm plan: G-code to joint samples at the servo period.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <memory>
#include <nlohmann/json.hpp>

#include <unistd.h>
#include <filesystem>

#include "app.hpp"
#include "embedded_machine.hpp"
#include "pkm/gcode/gcode_error.hpp"
#include "pkm/io/sample_files.hpp"

namespace pkm::app {

namespace {

struct PlanCommandOptions {
  std::string machine;
  std::string program;
  std::string output;
  std::string report;
  std::string tool_table;
  double period_s = 0.001;
  std::vector<double> start;
  std::vector<double> origin;
  std::string attitude = "linear";
  double jerk = 0.0;
  std::string display_name;  // how to name the job in the summary (default: its path)
};

nlohmann::json report_json(const Machine& machine, const motion::PlanReport& report,
                           const PlanCommandOptions& options) {
  nlohmann::json joints = nlohmann::json::array();
  for (std::size_t i = 0; i < machine.joints().size(); ++i) {
    const JointSpec& joint = machine.joints()[i];
    const motion::JointStatistics& s = report.joints[i];
    joints.push_back({{"name", joint.name},
                      {"unit", joint.interface_unit()},
                      {"min", joint.to_interface(s.min)},
                      {"max", joint.to_interface(s.max)},
                      {"limit_min", joint.to_interface(joint.min)},
                      {"limit_max", joint.to_interface(joint.max)},
                      {"peak_velocity", joint.to_interface(s.peak_velocity)},
                      {"max_velocity", joint.to_interface(joint.max_velocity)},
                      {"peak_acceleration", joint.to_interface(s.peak_acceleration)},
                      {"max_acceleration", joint.to_interface(joint.max_acceleration)}});
  }
  nlohmann::json limits = nlohmann::json::array();
  for (const motion::FeedLimit& limit : report.feed_limits) {
    limits.push_back({{"line", limit.line},
                      {"joint", machine.joints()[static_cast<std::size_t>(limit.joint)].name},
                      {"programmed_mm_per_min", limit.programmed_mm_per_s * 60.0},
                      {"allowed_mm_per_min", limit.allowed_mm_per_s * 60.0}});
  }
  return {{"machine", machine.name()},
          {"program", options.program},
          {"period_s", options.period_s},
          {"duration_s", report.duration_s},
          {"samples", report.samples},
          {"path_length_mm", report.path_length_mm},
          {"joints", joints},
          {"feed_limited_by_joints", limits}};
}

// A progress bar on stderr when it is a terminal: the fraction of the program's lines planned.
class ProgressBar {
 public:
  explicit ProgressBar(const std::string& program) {
    if (::isatty(STDERR_FILENO) == 0) return;
    std::FILE* file = std::fopen(program.c_str(), "rb");
    if (file == nullptr) return;
    char buffer[1 << 16];
    std::size_t n = 0;
    while ((n = std::fread(buffer, 1, sizeof buffer, file)) > 0) {
      lines_ += std::count(buffer, buffer + n, '\n');
    }
    std::fclose(file);
    active_ = lines_ > 10000;  // short jobs finish before a bar helps
  }
  ~ProgressBar() { clear(); }
  void clear() {
    if (shown_) std::fprintf(stderr, "\r%60s\r", "");
    shown_ = false;
    active_ = false;
  }
  void update(int line) {
    if (!active_) return;
    const auto now = std::chrono::steady_clock::now();
    if (shown_ && now - last_ < std::chrono::milliseconds(100)) return;
    last_ = now;
    shown_ = true;
    const double fraction = std::min(1.0, static_cast<double>(line) / static_cast<double>(lines_));
    const int filled = static_cast<int>(fraction * 30);
    std::fprintf(stderr, "\r[%.*s%*s] %3.0f%%  line %d of %ld", filled,
                 "==============================", 30 - filled, "", 100.0 * fraction, line, lines_);
    std::fflush(stderr);
  }

 private:
  long lines_ = 0;
  bool active_ = false, shown_ = false;
  std::chrono::steady_clock::time_point last_;
};

// Samples nobody keeps: `pkm demo` without -o.
struct DiscardSamples final : SampleFile {
  void write(const motion::Sample&) override {}
  void commit() override {}
};

void run_plan(const PlanCommandOptions& options) {
  const Machine machine = load_machine_or_default(options.machine);
  motion::PlanOptions plan_options;
  plan_options.period_s = options.period_s;
  if (!options.start.empty()) plan_options.start = pose_from_arguments(machine, options.start);
  plan_options.origin = pose_vector_over(plan_options.origin, options.origin);
  plan_options.great_circle_attitude = options.attitude == "great-circle";
  plan_options.jerk_mm_per_s3 = options.jerk;
  ProgressBar progress(options.program);
  plan_options.on_line = [&progress](int line) { progress.update(line); };
  gcode::InterpreterOptions interpreter_options;
  std::unique_ptr<SampleFile> output;
  motion::PlanReport report;
  try {
    if (!options.tool_table.empty()) {
      interpreter_options.tool_table = gcode::read_tool_table(options.tool_table);
    }
    output = options.output.empty() ? std::make_unique<DiscardSamples>()
                                    : SampleFile::open(options.output, machine);
    report =
        motion::plan_program(machine, options.program, interpreter_options, plan_options, *output);
  } catch (const gcode::GcodeError& error) {
    throw CommandError(error.what());
  } catch (const motion::PlanError& error) {
    throw CommandError(error.what() + job_reach_hint(machine, options.program, interpreter_options,
                                                     plan_options.origin));
  } catch (const std::invalid_argument& error) {
    throw CommandError(error.what());
  }
  progress.clear();
  output->commit();
  const nlohmann::json json = report_json(machine, report, options);
  if (!options.report.empty()) write_file_atomically(options.report, json.dump(2) + "\n");
  for (const gcode::Warning& warning : report.warnings) {
    std::fprintf(stderr, "pkm: warning: %s:%d: %s\n", options.program.c_str(), warning.line,
                 warning.message.c_str());
  }
  std::printf("%s: %ld samples, %.3f s, path %.3f mm on %s\n",
              !options.output.empty()         ? options.output.c_str()
              : !options.display_name.empty() ? options.display_name.c_str()
                                              : options.program.c_str(),
              report.samples, report.duration_s, report.path_length_mm, machine.name().c_str());
  for (std::size_t i = 0; i < machine.joints().size(); ++i) {
    const JointSpec& joint = machine.joints()[i];
    const motion::JointStatistics& s = report.joints[i];
    std::printf("  %-10s %10.3f .. %10.3f %s, peak %8.2f of %.1f %s/s, %9.1f of %.1f %s/s^2\n",
                joint.name.c_str(), joint.to_interface(s.min), joint.to_interface(s.max),
                joint.interface_unit(), joint.to_interface(s.peak_velocity),
                joint.to_interface(joint.max_velocity), joint.interface_unit(),
                joint.to_interface(s.peak_acceleration), joint.to_interface(joint.max_acceleration),
                joint.interface_unit());
  }
  if (!report.feed_limits.empty()) {
    std::printf(
        "  feed lowered by joint limits on %zu moves (first at line %d, joint %s)\n",
        report.feed_limits.size(), report.feed_limits.front().line,
        machine.joints()[static_cast<std::size_t>(report.feed_limits.front().joint)].name.c_str());
  }
}

// The embedded job on the embedded machine: the paper's sphere on the paper's hexapod.
void run_demo(PlanCommandOptions options) {
  const std::filesystem::path job = std::filesystem::temp_directory_path() /
                                    ("pkm-demo-sphere-" + std::to_string(::getpid()) + ".ngc");
  write_file_atomically(job, kEmbeddedJob);
  options.program = job.string();
  options.display_name = "sphere.ngc";
  std::printf(
      "pkm demo: the sphere test part of the interpolation paper (examples/jobs/sphere.ngc)\n"
      "on its Stewart platform (examples/machines/hexapod-bit.toml)\n");
  try {
    run_plan(options);
  } catch (...) {
    std::filesystem::remove(job);
    throw;
  }
  std::filesystem::remove(job);
}

}  // namespace

void register_plan_commands(CLI::App& app) {
  auto demo = std::make_shared<PlanCommandOptions>();
  CLI::App* demo_command = app.add_subcommand(
      "demo", "The embedded default: the paper's sphere planned on the paper's hexapod");
  demo_command->add_option("-o,--output", demo->output,
                           "Also write the samples: OUT.csv or OUT.npy");
  demo_command->add_option("--report", demo->report, "Write the plan report as JSON");
  demo_command->add_option("--period", demo->period_s, "Interpolation period, s (default 0.001)")
      ->check(CLI::PositiveNumber);
  demo_command->callback([demo] { run_demo(*demo); });

  auto options = std::make_shared<PlanCommandOptions>();
  CLI::App* command = app.add_subcommand(
      "plan",
      "Joint positions at every servo period for a G-code job (time-division interpolation)");
  command->add_option("-m,--machine", options->machine, "Machine file (default: embedded hexapod)");
  command->add_option("program", options->program, "The G-code job")->required();
  command->add_option("-o,--output", options->output, "Samples: OUT.csv or OUT.npy")->required();
  command->add_option("--period", options->period_s, "Interpolation period, s (default 0.001)")
      ->check(CLI::PositiveNumber);
  command->add_option("--report", options->report, "Write the plan report as JSON");
  command->add_option("--tool-table", options->tool_table, "LinuxCNC tool table (.tbl, mm)");
  command->add_option("--start", options->start, "Start pose x y z [a b c] (default: home)")
      ->expected(2, 6);
  command
      ->add_option("--origin", options->origin,
                   "Where the program's X0 Y0 Z0 sits in machine coordinates, x y [z [a b c]] "
                   "(mm, deg; default 0)")
      ->expected(2, 6);
  command
      ->add_option("--attitude", options->attitude,
                   "Tool attitude within a move: linear (A B C, as LinuxCNC) or great-circle "
                   "(the tool axis along a great circle)")
      ->check(CLI::IsMember({"linear", "great-circle"}));
  command
      ->add_option("--jerk", options->jerk,
                   "Tool-tip jerk limit, mm/s^3: S-curve speed changes (default: none)")
      ->check(CLI::NonNegativeNumber);
  command->callback([options] { run_plan(*options); });
}

}  // namespace pkm::app
