// pkm post: joint-space G-code with the tool tip's deviation bounded.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>

#include "app.hpp"
#include "pkm/files/atomic_file.hpp"
#include "pkm/gcode/gcode_error.hpp"
#include "pkm/io/input_files.hpp"
#include "pkm/io/json_reports.hpp"
#include "pkm/motion/job_reach.hpp"
#include "pkm/motion/planner.hpp"
#include "pkm/post/grbl_settings.hpp"
#include "pkm/post/joint_program.hpp"
#include "pkm/post/mach3_export.hpp"
#include "pkm/post/program_header.hpp"
#include "pkm/verify/joint_path.hpp"
#include "pkm/view/html_page.hpp"
#include "progress.hpp"

namespace pkm::app {

namespace {

struct PostCommandOptions {
  std::string machine;
  std::string program;
  std::string output;
  std::string dialect = "linuxcnc";
  ToolTableOptions tool_table;
  std::vector<std::filesystem::path> subroutine_path;
  double tolerance = 0.0;      // the machine file's units; 0: kDefaultTolerance_mm
  bool no_span_moves = false;  // --no-span-moves: every move covered on its own
  std::string rapids;          // --rapids g0|timed; empty: the dialect's default
  long max_blocks = post::kDefaultMaxBlocks;
  std::vector<double> origin;
  std::string report;  // --report: the summary as JSON
  std::string html;    // --html: the page of the joint program
};

// The page of the written program: its blocks traced by verify's forward kinematics against the
// job, each coloured by its measured deviation.
void write_post_html(const machine::Machine& machine, const PostCommandOptions& options,
                     const post::PostOptions& post_options, const nlohmann::json& report) {
  view::BlockRecorder recorder(machine);
  verify::VerifyOptions verify_options;
  verify_options.tolerance_mm = post_options.tolerance_mm;
  verify_options.origin = post_options.origin;
  verify_options.on_block = [&recorder](const verify::VerifiedBlock& block) {
    recorder.add(block);
  };
  std::vector<view::PathPoint> outline;
  try {
    verify_options.job_options.tool_table = read_tool_table(machine, options.tool_table);
    verify_options.job_options.subroutine_path = options.subroutine_path;
    verify::verify_joint_program(machine, options.output, options.program, verify_options);
    outline = view::job_outline(machine, options.program, verify_options.job_options,
                                verify_options.origin);
  } catch (const std::exception& error) {
    throw CommandError(options.html + ": cannot trace the written program: " + error.what());
  }
  recorder.finish();
  const std::string job = std::filesystem::path(options.program).filename().string();
  view::write_page(options.html,
                   view::blocks_page("post", report, recorder, post_options.tolerance_mm, outline,
                                     "pkm post: " + job + " on " + machine.name()));
}

std::string format_number(const char* pattern, double value) {
  char text[64];
  std::snprintf(text, sizeof text, pattern, value);
  return text;
}

// The controller's time beside plan's: what the joints and the job allow when the machine has
// the kinematics, against what grbl's planner makes of the joint program.
void print_controller_time(const machine::Machine& machine, const PostCommandOptions& options,
                           const post::PostOptions& post_options,
                           const controller::GrblPrediction& prediction) {
  motion::PlanOptions plan_options;
  plan_options.origin = post_options.origin;
  gcode::InterpreterOptions interpreter_options;
  interpreter_options.tool_table = read_tool_table(machine, options.tool_table);
  interpreter_options.subroutine_path = options.subroutine_path;
  plan_options.estimate_only = true;
  struct : motion::SampleSink {
    void write(const motion::Sample&) override {}
  } discard;
  std::string plan_time;
  try {
    const double plan_s =
        motion::plan_program(machine, options.program, interpreter_options, plan_options, discard)
            .duration_s;
    plan_time = format_number("pkm plan: %.3f s", plan_s);
  } catch (const std::exception& error) {
    plan_time = std::string("pkm plan refuses the job: ") + error.what();
  }
  std::printf("%s predicts %.3f s for the program (%s)\n",
              machine::controller_kind_name(machine.controller()->kind), prediction.time_s,
              plan_time.c_str());
}

// The post options the command line asks for, checked against the machine (its axis letters in
// the dialect).
post::PostOptions post_options_for(const machine::Machine& machine,
                                   const PostCommandOptions& options) {
  post::PostOptions post_options;
  post_options.tolerance_mm = options.tolerance > 0.0
                                  ? mm_from_machine_units(machine, options.tolerance)
                                  : kDefaultTolerance_mm;
  post_options.dialect = post::dialect_named(options.dialect);
  post_options.span_moves = !options.no_span_moves;
  post_options.max_blocks = options.max_blocks;
  if (!options.rapids.empty()) post_options.rapids = post::rapids_style_named(options.rapids);
  try {
    post::check_axis_letters(machine, post_options.dialect);
  } catch (const std::invalid_argument& error) {
    throw CommandError(machine.source() + ": " + error.what());
  }
  post_options.origin = pose_vector_over(machine, post_options.origin, options.origin);
  return post_options;
}

// A subroutine file the job called is known only once the job is read: no output may replace
// one (the outputs are still under their temporary names when this is asked).
void refuse_overwriting_subroutines(const PostCommandOptions& options,
                                    const post::PostReport& report) {
  std::vector<io::NamedInput> subroutines;
  for (std::size_t i = 1; i < report.files_read.size(); ++i) {
    subroutines.push_back({"a subroutine file the job calls", report.files_read[i]});
  }
  for (const std::string& written : {options.output, options.report, options.html}) {
    if (const std::string reason = io::overwrites_input(written, subroutines); !reason.empty()) {
      throw CommandError(reason);
    }
  }
}

void print_warnings(const std::string& program, const std::vector<gcode::Warning>& warnings) {
  for (const gcode::Warning& warning : warnings) {
    // Line 0: about the whole program, not one of its lines.
    if (warning.line > 0) {
      std::fprintf(stderr, "pkm: warning: %s:%d: %s\n", program.c_str(), warning.line,
                   warning.message.c_str());
    } else {
      std::fprintf(stderr, "pkm: warning: %s: %s\n", program.c_str(), warning.message.c_str());
    }
  }
}

// The one-line summary, in the machine's length unit, then what else was written.
void print_post_summary(const machine::Machine& machine, const PostCommandOptions& options,
                        const post::PostOptions& post_options, const post::PostReport& report) {
  const double per_unit = machine.mm_per_unit();
  std::printf("%s: %ld blocks for %ld moves, %s %.6f %s (line %d), tolerance %.6f %s\n",
              options.output.c_str(), report.blocks, report.moves,
              report.bounded ? "deviation bounded by" : "largest sampled deviation",
              report.max_deviation_mm / per_unit, machine.length_unit(), report.max_deviation_line,
              post_options.tolerance_mm / per_unit, machine.length_unit());
  if (report.controller) print_controller_time(machine, options, post_options, *report.controller);
  if (!options.report.empty()) std::printf("wrote the report %s\n", options.report.c_str());
  if (!options.html.empty()) {
    std::printf("wrote the page %s: open it in a browser\n", options.html.c_str());
  }
}

void run_post(const PostCommandOptions& options) {
  check_outputs({{"-o", options.output}, {"--report", options.report}, {"--html", options.html}});
  for (const std::string& written : {options.output, options.report, options.html}) {
    refuse_overwriting_input(written, {{"the job", options.program},
                                       {"the machine file", options.machine},
                                       {"the tool table", options.tool_table.path}});
  }
  const machine::Machine machine = load_machine_or_default(options.machine);
  post::PostOptions post_options = post_options_for(machine, options);
  gcode::InterpreterOptions interpreter_options;
  files::AtomicFileWriter file(options.output);
  file.write(post::joint_program_header(machine, options.program, post_options.dialect,
                                        post_options.tolerance_mm, nullptr));
  post::PostReport report;
  ProgressBar progress("post " + std::filesystem::path(options.program).filename().string(),
                       options.program);
  post_options.on_line = progress.on_line();
  try {
    interpreter_options.tool_table = read_tool_table(machine, options.tool_table);
    interpreter_options.subroutine_path = options.subroutine_path;
    report = post::post_program(machine, options.program, interpreter_options, post_options,
                                [&](const std::string& line) { file.write(line + "\n"); });
  } catch (const gcode::GcodeError& error) {
    throw CommandError(error.what());
  } catch (const post::BlockBoundError& error) {
    throw CommandError(std::string(error.what()) +
                       ". Check the job's arcs (their P, the turns) and --tolerance, or raise "
                       "--max-blocks");
  } catch (const post::PostError& error) {
    throw CommandError(error.what() + motion::job_reach_hint(machine, options.program,
                                                             interpreter_options,
                                                             post_options.origin));
  } catch (const std::invalid_argument& error) {
    throw CommandError(error.what());
  }
  progress.clear();
  refuse_overwriting_subroutines(options, report);
  file.write_at(0, post::joint_program_header(machine, options.program, post_options.dialect,
                                              post_options.tolerance_mm, &report));
  file.commit();
  print_warnings(options.program, report.warnings);
  const nlohmann::json json = io::post_report_json(machine, options.program, options.output, report,
                                                   post_options.tolerance_mm);
  if (!options.report.empty()) files::write_file_atomically(options.report, json.dump(2) + "\n");
  if (!options.html.empty()) write_post_html(machine, options, post_options, json);
  print_post_summary(machine, options, post_options, report);
}

// pkm export grbl|grblhal: the controller's $ settings, on standard output or in -o FILE.
void run_export_settings(const std::string& machine_file, const std::string& output,
                         machine::ControllerKind kind) {
  refuse_overwriting_input(output, {{"the machine file", machine_file}});
  const machine::Machine machine = machine::load_machine(machine_file);
  post::ControllerSettingsFile settings;
  try {
    settings = post::controller_settings(machine, kind);
  } catch (const std::invalid_argument& error) {
    throw CommandError(error.what());
  }
  for (const std::string& warning : settings.warnings) {
    std::fprintf(stderr, "pkm: warning: %s\n", warning.c_str());
  }
  if (output.empty()) {
    std::fputs(settings.text().c_str(), stdout);
    return;
  }
  files::write_file_atomically(output, settings.text());
  std::printf("%s: %zu %s settings for %s: send it line by line, waiting for each ok\n",
              output.c_str(), settings.settings.size(), machine::controller_kind_name(kind),
              machine.name().c_str());
}

void register_export_settings(CLI::App& export_command, machine::ControllerKind kind) {
  struct Options {
    std::string machine;
    std::string output;
  };
  auto options = std::make_shared<Options>();
  const std::string name = machine::controller_kind_name(kind);
  CLI::App* command = export_command.add_subcommand(
      name, "The " + name + " $ settings of the joints (steps, rates, accelerations, travel)");
  command->add_option("-m,--machine", options->machine, "Machine file with a [controller] table")
      ->required();
  command
      ->add_option("-o,--output", options->output, "The settings file (default: standard output)")
      ->check(file_name());
  if (kind != machine::ControllerKind::grblhal) {
    command->callback(
        [options, kind] { run_export_settings(options->machine, options->output, kind); });
    return;
  }
  // grblHAL also has kinematics of its own (a wall plotter, a delta): docs/firmware-grblhal.md.
  auto firmware = std::make_shared<FirmwareExportOptions>();
  command->add_flag("--kinematics", firmware->kinematics_wanted,
                    "The settings of grblHAL's own kinematics instead (a wall plotter or delta "
                    "built with them): G-code in machine coordinates, no joint-space post");
  command->add_flag("--approximate", firmware->approximate,
                    "With --kinematics: where grblHAL's kinematics cannot hold the machine "
                    "exactly, the nearest machine they can hold, with the worst tool error");
  command->callback([options, firmware, kind] {
    if (firmware->kinematics_wanted) {
      firmware->machine = options->machine;
      firmware->output = options->output;
      run_firmware_export("grblhal", *firmware);
      return;
    }
    if (firmware->approximate) throw CommandError("--approximate needs --kinematics");
    run_export_settings(options->machine, options->output, kind);
  });
}

}  // namespace

void register_post_commands(CLI::App& app) {
  auto export_machine = std::make_shared<std::string>();
  CLI::App* export_command =
      app.add_subcommand("export", "Export a machine for another controller");
  export_command->require_subcommand(1);
  CLI::App* mach3 = export_command->add_subcommand(
      "mach3", "Mach3 formula-axis equations, for machines whose IK is a closed formula");
  mach3->add_option("-m,--machine", *export_machine, "Machine file (default: embedded hexapod)");
  mach3->callback([export_machine] {
    const machine::Machine machine = load_machine_or_default(*export_machine);
    std::vector<std::pair<char, std::string>> formulas;
    try {
      formulas = post::mach3_formulas(machine);
    } catch (const std::invalid_argument& error) {
      throw CommandError(std::string(error.what()) + " (" + machine.source() + ")");
    }
    std::printf("(Mach3 formula axis correction for %s: enable formulas, then)\n",
                machine.name().c_str());
    for (const auto& [letter, expression] : formulas) {
      std::printf("f(%c) = %s\n", letter, expression.c_str());
    }
  });

  register_export_settings(*export_command, machine::ControllerKind::grbl);
  register_export_settings(*export_command, machine::ControllerKind::grblhal);

  auto options = std::make_shared<PostCommandOptions>();
  CLI::App* command = app.add_subcommand(
      "post", "Joint-space G-code for controllers without kinematics, within a tolerance");
  command->add_option("-m,--machine", options->machine, "Machine file (default: embedded hexapod)");
  command->add_option("program", options->program, "The Cartesian G-code job")->required();
  command->add_option("-o,--output", options->output, "The joint-space program to write")
      ->required()
      ->check(file_name());
  command
      ->add_option("--tolerance", options->tolerance,
                   "Largest tool-tip deviation from the programmed path, in the machine file's "
                   "units (default 0.01 mm: 0.0003937 in on an inch machine)")
      ->check(number_in(kMinTolerance, kMaxTolerance));
  command->add_flag("--no-span-moves", options->no_span_moves,
                    "Cover every programmed move with blocks of its own (by default one block "
                    "may span consecutive feed moves where it keeps within the tolerance)");
  command
      ->add_option("--rapids", options->rapids,
                   "How G0 is written: timed (an inverse-time G1 at the machine's max_feed, the "
                   "tool within its limits; the default for grbl and grblhal) or g0 (the "
                   "controller's rapid, each joint at its own top rate; the default for linuxcnc "
                   "and mach3)")
      ->check(CLI::IsMember({"g0", "timed"}));
  command
      ->add_option("--max-blocks", options->max_blocks,
                   "Refuse a job that needs more motion blocks than this (default 10000000)")
      ->check(number_in(1, 1e15));
  command->add_option("--dialect", options->dialect, "linuxcnc (default), mach3, grbl or grblhal")
      ->check(CLI::IsMember({"linuxcnc", "mach3", "grbl", "grblhal"}));
  add_tool_table_options(*command, options->tool_table);
  add_subroutine_path_option(*command, options->subroutine_path);
  add_pose_option(*command, "--origin", options->origin,
                  "Where the program's X0 Y0 Z0 sits in machine coordinates, in the machine "
                  "file's units (mm or inch) and deg");
  command->add_option("--report", options->report, "Write the summary as JSON")->check(file_name());
  command
      ->add_option("--html", options->html,
                   "Write the program's page: one HTML file that opens offline")
      ->check(file_name());
  command->callback([options] { run_post(*options); });
}

}  // namespace pkm::app
