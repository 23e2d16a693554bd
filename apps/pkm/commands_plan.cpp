// pkm plan: G-code to joint samples at the servo period, or (without -o) the estimate of a job:
// its duration, samples, joint ranges and the moves whose feed the joints lower (or whose feed
// and acceleration a hanging effector's cable tensions lower).
#include <algorithm>
#include <cstdio>
#include <memory>
#include <nlohmann/json.hpp>

#include <filesystem>

#include "app.hpp"
#include "embedded_machine.hpp"
#include "pkm/files/atomic_file.hpp"
#include "pkm/gcode/gcode_error.hpp"
#include "pkm/io/json_reports.hpp"
#include "pkm/io/sample_files.hpp"
#include "pkm/motion/job_reach.hpp"
#include "pkm/motion/planner.hpp"
#include "pkm/view/html_page.hpp"
#include "progress.hpp"

namespace pkm::app {

namespace {

struct PlanCommandOptions {
  std::string machine;
  std::string program;
  std::string output;
  std::string report;
  ToolTableOptions tool_table;
  std::vector<std::filesystem::path> subroutine_path;
  double period_s = 0.001;
  std::vector<double> start;
  std::vector<double> origin;
  std::string attitude = "linear";
  double jerk = 0.0;
  bool estimate = false;
  bool sample_without_output = false;  // pkm demo: make the samples even without -o
  long max_samples = motion::kDefaultMaxSamples;
  std::string display_name;  // how to name the job in the summary (default: its path)
  std::string html;          // the page of the plan (--html), empty for none
};

// Samples nobody keeps: `pkm demo` without -o, and the estimate (which makes none).
struct DiscardSamples final : io::SampleFile {
  void write(const motion::Sample&) override {}
  void commit() override {}
};

// What one run of the planner needs beyond the machine: the job's interpreter options (tool
// table) and the plan options from the command line.
struct PlanSetup {
  gcode::InterpreterOptions interpreter;
  motion::PlanOptions plan;
};

PlanSetup plan_setup(const machine::Machine& machine, const PlanCommandOptions& options) {
  PlanSetup setup;
  setup.plan.period_s = options.period_s;
  setup.interpreter.subroutine_path = options.subroutine_path;
  if (!options.start.empty()) setup.plan.start = pose_from_arguments(machine, options.start);
  setup.plan.origin = pose_vector_over(machine, setup.plan.origin, options.origin);
  setup.plan.great_circle_attitude = options.attitude == "great-circle";
  setup.plan.jerk_mm_per_s3 = mm_from_machine_units(machine, options.jerk);
  try {
    setup.interpreter.tool_table = read_tool_table(machine, options.tool_table);
  } catch (const gcode::GcodeError& error) {
    throw CommandError(error.what());
  }
  return setup;
}

// One run of the planner over the job, its errors turned into the command's.
motion::PlanReport run_planner(const machine::Machine& machine, const PlanCommandOptions& options,
                               const PlanSetup& setup, motion::SampleSink& sink) {
  try {
    return motion::plan_program(machine, options.program, setup.interpreter, setup.plan, sink);
  } catch (const gcode::GcodeError& error) {
    throw CommandError(error.what());
  } catch (const motion::PlanError& error) {
    throw CommandError(error.what() + motion::job_reach_hint(machine, options.program,
                                                             setup.interpreter, setup.plan.origin));
  } catch (const std::invalid_argument& error) {
    throw CommandError(error.what());
  }
}

// Bytes of a sample file: NPY exactly (header and 8 bytes a column), CSV roughly (a real number
// takes some 14 characters).
double npy_bytes(const machine::Machine& machine, double samples) {
  return 128.0 + samples * 8.0 * static_cast<double>(io::sample_columns(machine).size());
}
double csv_bytes(const machine::Machine& machine, double samples) {
  return samples * (14.0 * static_cast<double>(io::sample_columns(machine).size() - 2) + 16.0);
}

void print_estimate_head(const machine::Machine& machine, const motion::PlanReport& report,
                         const std::string& name) {
  // Seconds to the millisecond; an absurd job's (1e152 s) in powers of ten.
  std::printf(report.duration_s < 1e9
                  ? "%s on %s (estimate, no samples made): %.3f s, path %.3f %s\n"
                  : "%s on %s (estimate, no samples made): %.4g s, path %.3f %s\n",
              name.c_str(), machine.name().c_str(), report.duration_s,
              report.path_length_mm / machine.mm_per_unit(), machine.length_unit());
  const double samples = static_cast<double>(report.samples);
  std::printf("  %s%ld samples at the period: NPY %s, CSV about %s\n",
              report.samples >= motion::kSampleCountCap ? "more than " : "", report.samples,
              size_text(npy_bytes(machine, samples)).c_str(),
              size_text(csv_bytes(machine, samples)).c_str());
}

// "the left cable" (a cable is named as its joint); -1 where the effector would have no
// balance at all (the tensions' bound was where one ends).
std::string cable_text(const machine::Machine& machine, int cable) {
  if (cable < 0) return "the cables' balance";
  return "the " + machine.joints()[static_cast<std::size_t>(cable)].name + " cable";
}

// "joint left", or "the left cable's tension".
std::string limiting(const machine::Machine& machine, int joint, motion::LimitCause cause) {
  if (cause == motion::LimitCause::tension) {
    return joint < 0 ? cable_text(machine, joint) : cable_text(machine, joint) + "'s tension";
  }
  return "joint " + machine.joints()[static_cast<std::size_t>(joint)].name;
}

// The kinds of feed limits the summary counts apart: what a user does about each differs (a
// faster joint, gentler corners, lighter acceleration on a hanging effector).
enum class FeedLimitKind { joint_velocity, joint_acceleration, tension };

FeedLimitKind kind_of(const motion::FeedLimit& limit) {
  if (limit.cause == motion::LimitCause::tension) return FeedLimitKind::tension;
  return limit.bound == motion::JointBound::velocity ? FeedLimitKind::joint_velocity
                                                     : FeedLimitKind::joint_acceleration;
}

const char* kind_text(FeedLimitKind kind) {
  switch (kind) {
    case FeedLimitKind::joint_velocity:
      return "joint velocity";
    case FeedLimitKind::joint_acceleration:
      return "joint acceleration";
    case FeedLimitKind::tension:
      break;
  }
  return "cable tensions";
}

// "feed lowered by joint acceleration on 98 moves, 96 of them G64 corner blends (first at line
// 44, joint right)": one line per kind of limit.
void print_feed_limit_counts(const machine::Machine& machine, const motion::PlanReport& report) {
  for (const FeedLimitKind kind :
       {FeedLimitKind::joint_velocity, FeedLimitKind::joint_acceleration, FeedLimitKind::tension}) {
    const auto of_kind = [&](const motion::FeedLimit& limit) { return kind_of(limit) == kind; };
    const auto first = std::find_if(report.feed_limits.begin(), report.feed_limits.end(), of_kind);
    if (first == report.feed_limits.end()) continue;
    const auto blends = std::count_if(first, report.feed_limits.end(), [&](const auto& limit) {
      return of_kind(limit) && limit.curve == motion::CurveKind::blend;
    });
    std::string corners;
    if (blends > 0) {
      corners = ", " + std::to_string(blends) +
                " of them G64 corner blends: G64 P with a larger tolerance rounds them wider and "
                "faster";
    }
    std::printf("  feed lowered by %s on %td moves%s (first at line %d, %s)\n", kind_text(kind),
                std::count_if(first, report.feed_limits.end(), of_kind), corners.c_str(),
                first->line, limiting(machine, first->joint, first->cause).c_str());
  }
}

// The first `count` moves whose feed a joint (or a cable's tension) lowered, and whose
// acceleration a cable's tension lowered: what to look at before running the job.
void print_feed_limits(const machine::Machine& machine, const motion::PlanReport& report,
                       std::size_t count) {
  for (std::size_t i = 0; i < report.feed_limits.size() && i < count; ++i) {
    const motion::FeedLimit& limit = report.feed_limits[i];
    std::printf("    line %d: %s\n", limit.line, io::feed_limit_text(machine, limit).c_str());
  }
  if (report.feed_limits.size() > count) {
    std::printf("    and %zu more (--report lists them all)\n", report.feed_limits.size() - count);
  }
  for (std::size_t i = 0; i < report.tension_limits.size() && i < count; ++i) {
    const motion::TensionLimitedMove& move = report.tension_limits[i];
    std::printf("    line %d: acceleration %.1f lowered to %.1f %s/s^2: %s %s\n", move.line,
                move.machine_mm_per_s2 / machine.mm_per_unit(),
                move.allowed_mm_per_s2 / machine.mm_per_unit(), machine.length_unit(),
                cable_text(machine, move.cable).c_str(),
                move.cable < 0 ? "would fail"
                : move.slack   ? "would go slack"
                               : "would pass its maximum tension");
  }
  if (report.tension_limits.size() > count) {
    std::printf("    and %zu more (--report lists them all)\n",
                report.tension_limits.size() - count);
  }
}

void print_summary(const machine::Machine& machine, const motion::PlanReport& report,
                   const std::string& name, bool estimate) {
  if (estimate) {
    print_estimate_head(machine, report, name);
  } else {
    std::printf("%s: %ld samples, %.3f s of machine motion, path %.3f %s on %s\n", name.c_str(),
                report.samples, report.duration_s, report.path_length_mm / machine.mm_per_unit(),
                machine.length_unit(), machine.name().c_str());
  }
  // Joints as check prints them: in the machine file's units.
  for (std::size_t i = 0; i < machine.joints().size(); ++i) {
    const int j = static_cast<int>(i);
    const machine::JointSpec& joint = machine.joints()[i];
    const motion::JointStatistics& s = report.joints[i];
    const char* unit = machine.joint_file_unit(j);
    std::printf("  %-10s %10.3f .. %10.3f %s, peak %8.2f of %.1f %s/s", joint.name.c_str(),
                machine.joint_to_file(j, s.min), machine.joint_to_file(j, s.max), unit,
                machine.joint_to_file(j, s.peak_velocity),
                machine.joint_to_file(j, joint.max_velocity), unit);
    if (!estimate) {
      std::printf(", %9.1f of %.1f %s/s^2", machine.joint_to_file(j, s.peak_acceleration),
                  machine.joint_to_file(j, joint.max_acceleration), unit);
    }
    std::printf("\n");
  }
  if (machine.tool().z == machine::ToolZ::pen) {
    std::printf("  pen down or up %d times, %.3f s of pen delay\n", report.pen_changes,
                report.pen_changes * machine.tool().delay_s);
  }
  print_feed_limit_counts(machine, report);
  if (!report.tension_limits.empty()) {
    const motion::TensionLimitedMove& first = report.tension_limits.front();
    std::printf("  acceleration lowered by cable tensions on %zu moves (first at line %d, %s)\n",
                report.tension_limits.size(), first.line, cable_text(machine, first.cable).c_str());
  }
  if (estimate) print_feed_limits(machine, report, 5);
}

void print_warnings(const PlanCommandOptions& options, const motion::PlanReport& report) {
  for (const gcode::Warning& warning : report.warnings) {
    std::fprintf(stderr, "pkm: warning: %s:%d: %s\n", options.program.c_str(), warning.line,
                 warning.message.c_str());
  }
}

// The estimate refuses a job that would write more samples than the bound, before anything is
// written: a wrong period or machine file would otherwise fill the disk.
void refuse_beyond_bound(const machine::Machine& machine, const PlanCommandOptions& options,
                         const motion::PlanReport& estimate) {
  if (estimate.samples <= options.max_samples) return;
  char text[512];
  std::snprintf(text, sizeof text,
                "%s would take %.6g s of machine time: %s%ld samples at %g s (NPY %s), more than "
                "--max-samples %ld. Check the period and the machine's feeds and accelerations, "
                "or raise --max-samples",
                options.program.c_str(), estimate.duration_s,
                estimate.samples >= motion::kSampleCountCap ? "more than " : "", estimate.samples,
                options.period_s,
                size_text(npy_bytes(machine, static_cast<double>(estimate.samples))).c_str(),
                options.max_samples);
  throw CommandError(text);
}

void run_plan(const PlanCommandOptions& options) {
  check_outputs({{"-o", options.output}, {"--report", options.report}, {"--html", options.html}});
  refuse_overwriting_input(options.output, {{"the job", options.program},
                                            {"the machine file", options.machine},
                                            {"the tool table", options.tool_table.path}});
  for (const std::string& written : {options.report, options.html}) {
    refuse_overwriting_input(written, {{"the job", options.program},
                                       {"the machine file", options.machine},
                                       {"the tool table", options.tool_table.path}});
  }
  const machine::Machine machine = load_machine_or_default(options.machine);
  PlanSetup setup = plan_setup(machine, options);
  const std::string name = !options.output.empty()         ? options.output
                           : !options.display_name.empty() ? options.display_name
                                                           : options.program;
  // The estimate first: without -o it is the answer; with -o it keeps the run within the bound.
  // The page draws the samples: --html makes them even without -o.
  const bool estimate_only =
      options.estimate ||
      (options.output.empty() && !options.sample_without_output && options.html.empty());
  if (estimate_only || options.max_samples > 0) {
    setup.plan.estimate_only = true;
    DiscardSamples none;
    const motion::PlanReport estimate = run_planner(machine, options, setup, none);
    if (estimate_only) {
      if (!options.report.empty()) {
        files::write_file_atomically(
            options.report,
            io::plan_report_json(machine, estimate, options.program, options.period_s, true)
                    .dump(2) +
                "\n");
      }
      print_warnings(options, estimate);
      print_summary(machine, estimate, name, true);
      return;
    }
    refuse_beyond_bound(machine, options, estimate);
    setup.plan.estimate_only = false;
    setup.plan.max_samples = options.max_samples;
  }
  ProgressBar progress(
      "plan " + std::filesystem::path(options.display_name.empty() ? options.program
                                                                   : options.display_name)
                    .filename()
                    .string(),
      options.program);
  setup.plan.on_line = progress.on_line();
  std::unique_ptr<io::SampleFile> output;
  try {
    output = options.output.empty() ? std::make_unique<DiscardSamples>()
                                    : io::SampleFile::open(options.output, machine);
  } catch (const std::invalid_argument& error) {
    throw CommandError(error.what());
  }
  view::PlanRecorder recorder(machine, output.get());
  motion::SampleSink& sink =
      options.html.empty() ? static_cast<motion::SampleSink&>(*output) : recorder;
  const motion::PlanReport report = run_planner(machine, options, setup, sink);
  progress.clear();
  output->commit();
  const nlohmann::json json =
      io::plan_report_json(machine, report, options.program, options.period_s, false);
  if (!options.report.empty()) files::write_file_atomically(options.report, json.dump(2) + "\n");
  if (!options.html.empty()) {
    recorder.finish();
    const std::string job =
        std::filesystem::path(options.display_name.empty() ? options.program : options.display_name)
            .filename()
            .string();
    view::write_page(options.html,
                     view::plan_page(json, recorder, "pkm plan: " + job + " on " + machine.name()));
  }
  print_warnings(options, report);
  print_summary(machine, report, name, false);
  if (!options.report.empty()) std::printf("wrote the report %s\n", options.report.c_str());
  if (!options.html.empty()) {
    std::printf("wrote the page %s: open it in a browser\n", options.html.c_str());
  }
}

// The embedded job on the embedded machine: the paper's sphere on the paper's hexapod. The job
// is read from a temporary file that is never committed: it goes with the run, however the run
// ends (a signal included), and one left by a killed run is removed by the next.
void run_demo(PlanCommandOptions options) {
  files::AtomicFileWriter job(std::filesystem::temp_directory_path() / "pkm-demo-sphere.ngc");
  job.write(kEmbeddedJob);
  if (std::fflush(job.stream()) != 0) {
    throw CommandError(job.temporary_path() + ": cannot write the demo's job");
  }
  options.program = job.temporary_path();
  options.display_name = "sphere.ngc";
  options.sample_without_output = true;
  std::printf(
      "pkm demo: the sphere test part of the interpolation paper (examples/jobs/sphere.ngc)\n"
      "on its Stewart platform (examples/machines/hexapod-bit.toml)\n");
  run_plan(options);
}

}  // namespace

void register_plan_commands(CLI::App& app) {
  auto demo = std::make_shared<PlanCommandOptions>();
  CLI::App* demo_command = app.add_subcommand(
      "demo", "The embedded default: the paper's sphere planned on the paper's hexapod");
  demo_command
      ->add_option("-o,--output", demo->output, "Also write the samples: OUT.csv or OUT.npy")
      ->check(file_name());
  demo_command->add_option("--report", demo->report, "Write the plan report as JSON")
      ->check(file_name());
  demo_command
      ->add_option("--html", demo->html, "Write the plan's page: one HTML file that opens offline")
      ->check(file_name());
  demo_command->add_option("--period", demo->period_s, "Interpolation period, s (default 0.001)")
      ->check(number_in(motion::kMinPeriodS, motion::kMaxPeriodS));
  demo_command->callback([demo] { run_demo(*demo); });

  auto options = std::make_shared<PlanCommandOptions>();
  CLI::App* command = app.add_subcommand(
      "plan",
      "Joint positions at every servo period for a G-code job (time-division interpolation); "
      "without -o, the job's estimate");
  command->add_option("-m,--machine", options->machine, "Machine file (default: embedded hexapod)");
  command->add_option("program", options->program, "The G-code job")->required();
  CLI::Option* output = command
                            ->add_option("-o,--output", options->output,
                                         "Samples: OUT.csv or OUT.npy (without it: the estimate)")
                            ->check(file_name());
  command
      ->add_flag("--estimate", options->estimate,
                 "Print the duration, samples, joint ranges and feed-limited moves; write no "
                 "samples")
      ->excludes(output);
  command
      ->add_option("--max-samples", options->max_samples,
                   "Refuse a job that needs more samples than this (default 50000000)")
      ->check(number_in(1, static_cast<double>(motion::kMaxSamplesBound)));
  command->add_option("--period", options->period_s, "Interpolation period, s (default 0.001)")
      ->check(number_in(motion::kMinPeriodS, motion::kMaxPeriodS));
  command->add_option("--report", options->report, "Write the plan report as JSON")
      ->check(file_name());
  command
      ->add_option("--html", options->html,
                   "Write the plan's page: one HTML file that opens offline (makes the samples)")
      ->check(file_name())
      ->excludes("--estimate");
  add_tool_table_options(*command, options->tool_table);
  add_subroutine_path_option(*command, options->subroutine_path);
  add_pose_option(*command, "--start", options->start,
                  "Start pose, in the machine file's units (mm or inch) and deg (default: home)");
  add_pose_option(*command, "--origin", options->origin,
                  "Where the program's X0 Y0 Z0 sits in machine coordinates, in the machine "
                  "file's units (mm or inch) and deg (default 0)");
  command
      ->add_option("--attitude", options->attitude,
                   "Tool attitude within a move: linear (A B C, as LinuxCNC) or great-circle "
                   "(the tool axis along a great circle)")
      ->check(CLI::IsMember({"linear", "great-circle"}));
  command
      ->add_option("--jerk", options->jerk,
                   "Tool-tip jerk limit, the machine file's length unit per s^3: S-curve speed "
                   "changes (default: none; a machine file with a joint's max_jerk plans "
                   "S-curves anyway, at the least jerk its joints allow)")
      ->check(number_in(0.0, motion::kMaxJerkPerS3));
  command->callback([options] { run_plan(*options); });
}

}  // namespace pkm::app
