// pkm view: what a joint program draws, without the job it came from (docs/html-views.md, "A
// joint program alone"): a summary, and with --html its page.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>

#include "app.hpp"
#include "pkm/files/atomic_file.hpp"
#include "pkm/gcode/gcode_error.hpp"
#include "pkm/io/json_reports.hpp"
#include "pkm/post/joint_program.hpp"
#include "pkm/verify/joint_trace.hpp"
#include "pkm/view/html_page.hpp"
#include "progress.hpp"

namespace pkm::app {

namespace {

struct ViewCommandOptions {
  std::string machine;
  std::string joints;
  std::string dialect;  // empty: the machine's [controller], else linuxcnc
  std::string report;
  std::string html;
};

// The dialect the program is read in: the one named, else the machine's controller's, else
// LinuxCNC's (the widest).
verify::JointDialect dialect_of(const machine::Machine& machine, const std::string& name) {
  std::string chosen = name;
  if (chosen.empty()) {
    chosen = machine.controller() ? machine::controller_kind_name(machine.controller()->kind)
                                  : "linuxcnc";
  }
  const post::Dialect dialect = post::dialect_named(chosen);
  const post::DialectRules rules = post::rules_of(dialect);
  verify::JointDialect out;
  out.name = chosen;
  out.axes = rules.axes;
  out.max_line = rules.max_line;
  out.programming = dialect == post::Dialect::linuxcnc || dialect == post::Dialect::mach3;
  return out;
}

std::string length_text(const machine::Machine& machine, double mm) {
  char text[64];
  std::snprintf(text, sizeof text, "%.3f %s", mm / machine.mm_per_unit(), machine.length_unit());
  return text;
}

void print_extent(const machine::Machine& machine, const verify::TraceReport& report) {
  if (!std::isfinite(report.drawn_min.x())) {
    std::printf("  nothing drawn\n");
    return;
  }
  std::printf("  drawing's extent: x %s .. %s, y %s .. %s\n",
              length_text(machine, report.drawn_min.x()).c_str(),
              length_text(machine, report.drawn_max.x()).c_str(),
              length_text(machine, report.drawn_min.y()).c_str(),
              length_text(machine, report.drawn_max.y()).c_str());
}

// "line 12", or where a joint's extreme is the value it starts from (home, line 0): "at the start".
std::string where_text(int line) {
  return line > 0 ? "line " + std::to_string(line) : "at the start";
}

void print_joints(const machine::Machine& machine, const verify::TraceReport& report) {
  for (std::size_t i = 0; i < report.joints.size(); ++i) {
    const machine::JointSpec& joint = machine.joints()[i];
    const verify::JointRange& range = report.joints[i];
    const int index = static_cast<int>(i);
    std::printf(
        "  joint %s: %s (%s) .. %s (%s) of its travel %s .. %s: margin %s below, %s above\n",
        joint.name.c_str(), machine.joint_value_text(index, range.low).c_str(),
        where_text(range.low_line).c_str(), machine.joint_value_text(index, range.high).c_str(),
        where_text(range.high_line).c_str(), machine.joint_value_text(index, joint.min).c_str(),
        machine.joint_value_text(index, joint.max).c_str(),
        machine.joint_value_text(index, range.low - joint.min).c_str(),
        machine.joint_value_text(index, joint.max - range.high).c_str());
  }
}

void print_report(const machine::Machine& machine, const ViewCommandOptions& options,
                  const verify::TraceReport& report) {
  std::printf("%s on %s: %ld blocks", options.joints.c_str(), machine.name().c_str(),
              report.blocks);
  if (report.has_pen) {
    std::printf(", pen down %ld %s", report.pen_downs, report.pen_downs == 1 ? "time" : "times");
  }
  std::printf("\n  drawn %s (%s), travel %s (%s)", length_text(machine, report.drawn_mm).c_str(),
              report.has_pen ? "pen down" : "G1 blocks",
              length_text(machine, report.travel_mm).c_str(),
              report.has_pen ? "pen up" : "G0 blocks");
  // A grbl program's travel is timed G1 blocks (post --rapids timed): no G0 to speak of.
  if (report.rapid_mm > 0.0 || !report.has_pen) {
    std::printf(", of it rapid (G0) %s", length_text(machine, report.rapid_mm).c_str());
  }
  std::printf("\n");
  print_extent(machine, report);
  print_joints(machine, report);
}

// Each block end beyond a joint's travel the report keeps (its worst and first few), located.
void warn_beyond_travel(const ViewCommandOptions& options, const verify::TraceReport& report) {
  const verify::ViolationSummary& beyond = report.position;
  std::vector<verify::Violation> listed = beyond.first;
  if (beyond.count > 0 && std::none_of(listed.begin(), listed.end(), [&](const auto& v) {
        return v.line == beyond.worst.line && v.joint == beyond.worst.joint;
      })) {
    listed.push_back(beyond.worst);
  }
  for (const verify::Violation& v : listed) {
    std::fprintf(stderr, "pkm: warning: %s:%d: %s\n", options.joints.c_str(), v.line,
                 v.detail.c_str());
  }
}

void run_view(const ViewCommandOptions& options) {
  check_outputs({{"--report", options.report}, {"--html", options.html}});
  for (const std::string& written : {options.report, options.html}) {
    refuse_overwriting_input(
        written, {{"the joint program", options.joints}, {"the machine file", options.machine}});
  }
  const machine::Machine machine = load_machine_or_default(options.machine);
  verify::TraceOptions trace_options;
  trace_options.dialect = dialect_of(machine, options.dialect);
  ProgressBar progress("view " + std::filesystem::path(options.joints).filename().string(),
                       options.joints);
  trace_options.on_line = progress.on_line();
  view::TraceRecorder recorder(machine);
  if (!options.html.empty()) {
    trace_options.on_point = [&recorder](const verify::TracePoint& point) { recorder.add(point); };
  }
  verify::TraceReport report;
  try {
    report = verify::trace_joint_program(machine, options.joints, trace_options);
  } catch (const gcode::GcodeError& error) {
    throw CommandError(error.what());
  } catch (const verify::TraceError& error) {
    throw CommandError(error.what());
  }
  progress.clear();
  const nlohmann::json json = io::view_report_json(machine, options.joints, report);
  if (!options.report.empty()) files::write_file_atomically(options.report, json.dump(2) + "\n");
  if (!options.html.empty()) {
    recorder.finish();
    const std::string name = std::filesystem::path(options.joints).filename().string();
    view::write_page(options.html, view::view_page(json, recorder,
                                                   "pkm view: " + name + " on " + machine.name()));
  }
  print_report(machine, options, report);
  warn_beyond_travel(options, report);
  if (!options.report.empty()) std::printf("wrote the report %s\n", options.report.c_str());
  if (!options.html.empty()) {
    std::printf("wrote the page %s: open it in a browser\n", options.html.c_str());
  }
  if (report.position.count > 0) {
    const long count = report.position.count;
    throw CommandError(options.joints + ": " + std::to_string(count) +
                       (count == 1 ? " block end lies" : " block ends lie") +
                       " beyond a joint's travel, the first at line " +
                       std::to_string(report.position.first.front().line) +
                       " (above): the machine cannot run it");
  }
}

}  // namespace

void register_view_commands(CLI::App& app) {
  auto options = std::make_shared<ViewCommandOptions>();
  CLI::App* command = app.add_subcommand(
      "view",
      "Show what a joint-space program draws: forward kinematics of its blocks, the pen, "
      "the joints against their travel");
  command->add_option("-m,--machine", options->machine, "Machine file (default: embedded hexapod)");
  command->add_option("joints", options->joints, "The joint-space program")->required();
  command
      ->add_option("--dialect", options->dialect,
                   "The controller it is written for: linuxcnc, mach3, grbl or grblhal (default: "
                   "the machine's [controller], else linuxcnc)")
      ->check(CLI::IsMember({"linuxcnc", "mach3", "grbl", "grblhal"}));
  command->add_option("--report", options->report, "Write the summary as JSON")->check(file_name());
  command->add_option("--html", options->html, "Write the page: one HTML file that opens offline")
      ->check(file_name());
  command->callback([options] { run_view(*options); });
}

}  // namespace pkm::app
