// pkm verify: any joint-space program against the Cartesian job it should follow.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>

#include "app.hpp"
#include "pkm/files/atomic_file.hpp"
#include "pkm/gcode/gcode_error.hpp"
#include "pkm/io/json_reports.hpp"
#include "pkm/verify/joint_path.hpp"
#include "pkm/view/html_page.hpp"
#include "progress.hpp"

namespace pkm::app {

namespace {

struct VerifyCommandOptions {
  std::string machine;
  std::string joints;
  std::string job;
  std::string report;
  std::string html;        // --html: the page of the verification
  double tolerance = 0.0;  // the machine file's units; 0: the one in the joint program's header
  std::vector<double> origin;
  ToolTableOptions tool_table;
  std::vector<std::filesystem::path> subroutine_path;
};

// The tolerance given (in the machine file's units), or the one post wrote in the joint
// program's header (mm, as the program): mm.
double tolerance_mm_of(const machine::Machine& machine, const VerifyCommandOptions& options) {
  if (options.tolerance != 0.0) return mm_from_machine_units(machine, options.tolerance);
  const std::optional<double> header = verify::tolerance_in_header(options.joints);
  if (!header) {
    throw CommandError(options.joints + ": no tolerance to verify against: give --tolerance " +
                       (machine.units() == machine::LengthUnit::inch ? "IN" : "MM") +
                       " (the joint program's header, where pkm post writes one, has none)");
  }
  return *header;
}

// A finding's value (mm, mm/s, deg or deg/s) in the machine file's units.
double in_machine_units(const machine::Machine& machine, const verify::Violation& v, double value) {
  const bool rotary = v.joint >= 0 && machine.joints()[static_cast<std::size_t>(v.joint)].kind ==
                                          kinematics::JointKind::rotary;
  return rotary ? value : value / machine.mm_per_unit();
}

// 7 decimals: a deviation just above a tolerance of 0.01 shows as 0.0100145, not 0.010000.
std::string fixed(double value, int decimals = 7) {
  char text[64];
  std::snprintf(text, sizeof text, "%.*f", decimals, value);
  return text;
}

std::string joint_name(const machine::Machine& machine, int joint) {
  return joint >= 0 ? machine.joints()[static_cast<std::size_t>(joint)].name : "";
}

// One line per kind of finding: how many, the worst, the lines of the first few. Values in the
// units of the machine file: a joint's, or its length unit, followed by `per` ("" or "/s").
void print_summary(const machine::Machine& machine, const char* what, const std::string& per,
                   const verify::ViolationSummary& summary) {
  if (summary.count == 0) return;
  const verify::Violation& w = summary.worst;
  const std::string units =
      std::string(w.joint >= 0 ? machine.joint_file_unit(w.joint) : machine.length_unit()) + per;
  std::string worst = joint_name(machine, w.joint) + (w.joint >= 0 ? " " : "") +
                      fixed(in_machine_units(machine, w, w.value)) + " " + units;
  worst += w.detail.empty()
               ? ", limit " + fixed(in_machine_units(machine, w, w.limit)) + " " + units
               : " with the " + w.detail;
  // A joint past its travel reads as ik, plan and post say it (Machine::explain_joint).
  if (w.joint >= 0 && !w.detail.empty()) worst = w.detail;
  std::string first;
  for (const verify::Violation& v : summary.first) first += " " + std::to_string(v.line);
  if (summary.count > static_cast<long>(summary.first.size())) first += " ...";
  std::printf("  %s: %ld; worst at line %d (job line %d): %s; first at lines%s\n", what,
              summary.count, w.line, w.job_line, worst.c_str(), first.c_str());
}

void print_report(const machine::Machine& machine, const VerifyCommandOptions& options,
                  const verify::VerifyReport& report) {
  const double per_unit = machine.mm_per_unit();
  const char* unit = machine.length_unit();
  std::printf(
      "%s against %s: %ld blocks, job traced %.3f of %.3f %s, deviation max %.7f %s (line %d of "
      "the joint program, line %d of the job), RMS %.7f %s, tolerance %.7f %s\n",
      options.joints.c_str(), options.job.c_str(), report.blocks, report.traced_mm / per_unit,
      report.job_length_mm / per_unit, unit, report.max_deviation_mm / per_unit, unit,
      report.max_deviation_joint_line, report.max_deviation_job_line,
      report.rms_deviation_mm / per_unit, unit, report.tolerance_mm / per_unit, unit);
  print_summary(machine, "blocks beyond the tolerance", "", report.deviation);
  print_summary(machine, "block ends beyond a joint's travel", "", report.position);
  print_summary(machine, "feed blocks beyond a joint's max_velocity", "/s", report.velocity);
  print_summary(machine, "pen stretches against the job", "", report.pen);
  if (report.pen_downs != report.job_pen_downs) {
    std::printf("  pen: down %ld times, where the job puts it down %ld times (first at line %d)\n",
                report.pen_downs, report.job_pen_downs, report.first_job_pen_down_line);
  }
}

void fail_unless_passed(const machine::Machine& machine, const VerifyCommandOptions& options,
                        const verify::VerifyReport& report) {
  const double per_unit = machine.mm_per_unit();
  const std::string unit = machine.length_unit();
  if (!report.covered) {
    const std::string where = report.blocks == 0
                                  ? options.joints + " has no blocks"
                                  : options.joints + " ends at line " +
                                        std::to_string(report.coverage_stopped_joint_line);
    throw CommandError(where + ": the job " + options.job + " is traced only to line " +
                       std::to_string(report.coverage_stopped_job_line) + " (" +
                       fixed(report.traced_mm / per_unit, 3) + " of " +
                       fixed(report.job_length_mm / per_unit, 3) + " " + unit + ")");
  }
  if (report.deviation.count > 0) {
    throw CommandError("deviation " + fixed(report.max_deviation_mm / per_unit) + " " + unit +
                       " exceeds the tolerance " + fixed(report.tolerance_mm / per_unit) + " " +
                       unit + " at line " + std::to_string(report.max_deviation_joint_line) +
                       " of " + options.joints + " (line " +
                       std::to_string(report.max_deviation_job_line) + " of " + options.job + ")");
  }
  if (!report.commands_mismatch.empty()) {
    throw CommandError(options.joints + " against " + options.job + ": " +
                       report.commands_mismatch);
  }
  const long others = report.position.count + report.velocity.count + report.pen.count;
  if (others > 0 || report.pen_downs != report.job_pen_downs) {
    throw CommandError(std::to_string(report.position.count + report.velocity.count) +
                       " joint limit violations, " + std::to_string(report.pen.count) +
                       " pen stretches against the job (above)" +
                       (report.pen_downs != report.job_pen_downs ? ", pen downs differ" : ""));
  }
}

// The verification's page: the blocks as verify traced them, over the job's outline. Written
// before the verdict, so a failed verification has its page too.
void write_verify_html(const machine::Machine& machine, const VerifyCommandOptions& options,
                       const verify::VerifyOptions& verify_options, const nlohmann::json& json,
                       view::BlockRecorder& recorder) {
  recorder.finish();
  std::vector<view::PathPoint> outline;
  try {
    outline =
        view::job_outline(machine, options.job, verify_options.job_options, verify_options.origin);
  } catch (const gcode::GcodeError& error) {
    throw CommandError(error.what());
  }
  const std::string name = std::filesystem::path(options.joints).filename().string();
  view::write_page(options.html,
                   view::blocks_page("verify", json, recorder, verify_options.tolerance_mm, outline,
                                     "pkm verify: " + name + " on " + machine.name()));
}

void run_verify(const VerifyCommandOptions& options) {
  check_outputs({{"--report", options.report}, {"--html", options.html}});
  for (const std::string& written : {options.report, options.html}) {
    refuse_overwriting_input(written, {{"the joint program", options.joints},
                                       {"the job", options.job},
                                       {"the machine file", options.machine},
                                       {"the tool table", options.tool_table.path}});
  }
  const machine::Machine machine = load_machine_or_default(options.machine);
  verify::VerifyOptions verify_options;
  verify_options.origin = pose_vector_over(machine, verify_options.origin, options.origin);
  verify::VerifyReport report;
  ProgressBar progress("verify " + std::filesystem::path(options.joints).filename().string(),
                       options.joints);
  verify_options.on_line = progress.on_line();
  view::BlockRecorder recorder(machine);
  if (!options.html.empty()) {
    verify_options.on_block = [&recorder](const verify::VerifiedBlock& block) {
      recorder.add(block);
    };
  }
  try {
    verify_options.tolerance_mm = tolerance_mm_of(machine, options);
    verify_options.job_options.tool_table = read_tool_table(machine, options.tool_table);
    verify_options.job_options.subroutine_path = options.subroutine_path;
    report = verify::verify_joint_program(machine, options.joints, options.job, verify_options);
  } catch (const gcode::GcodeError& error) {
    throw CommandError(error.what());
  } catch (const verify::VerifyError& error) {
    throw CommandError(error.what());
  }
  progress.clear();
  const nlohmann::json json = io::verify_report_json(machine, options.joints, options.job, report);
  if (!options.report.empty()) files::write_file_atomically(options.report, json.dump(2) + "\n");
  if (!options.html.empty()) write_verify_html(machine, options, verify_options, json, recorder);
  print_report(machine, options, report);
  if (!options.report.empty()) std::printf("wrote the report %s\n", options.report.c_str());
  if (!options.html.empty()) {
    std::printf("wrote the page %s: open it in a browser\n", options.html.c_str());
  }
  fail_unless_passed(machine, options, report);
}

}  // namespace

void register_verify_commands(CLI::App& app) {
  auto options = std::make_shared<VerifyCommandOptions>();
  CLI::App* command = app.add_subcommand(
      "verify", "Check a joint-space program against its Cartesian job by forward kinematics");
  command->add_option("-m,--machine", options->machine, "Machine file (default: embedded hexapod)");
  command->add_option("joints", options->joints, "The joint-space program")->required();
  command->add_option("--against", options->job, "The Cartesian job it should follow")->required();
  command
      ->add_option("--tolerance", options->tolerance,
                   "Exit non-zero when the deviation exceeds this, in the machine file's units "
                   "(default: the tolerance in the joint program's header)")
      ->check(number_in(kMinTolerance, kMaxTolerance));
  command->add_option("--report", options->report, "Write the report as JSON")->check(file_name());
  command
      ->add_option("--html", options->html,
                   "Write the verification's page: one HTML file that opens offline")
      ->check(file_name());
  add_pose_option(*command, "--origin", options->origin,
                  "Where the job's X0 Y0 Z0 sits in machine coordinates, in the machine file's "
                  "units (mm or inch) and deg");
  add_tool_table_options(*command, options->tool_table);
  add_subroutine_path_option(*command, options->subroutine_path);
  command->callback([options] { run_verify(*options); });
}

}  // namespace pkm::app
