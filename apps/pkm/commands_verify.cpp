// pkm verify: any joint-space program against the Cartesian job it should follow.
#include <cstdio>
#include <memory>
#include <nlohmann/json.hpp>

#include "app.hpp"
#include "pkm/gcode/gcode_error.hpp"
#include "pkm/io/atomic_file.hpp"
#include "pkm/verify/joint_path.hpp"

namespace pkm::app {

namespace {

struct VerifyCommandOptions {
  std::string machine;
  std::string joints;
  std::string job;
  std::string report;
  double tolerance_mm = 0.0;
  std::vector<double> origin;
};

void run_verify(const VerifyCommandOptions& options) {
  const Machine machine = load_machine_or_default(options.machine);
  verify::VerifyOptions verify_options;
  verify_options.origin = pose_vector_over(verify_options.origin, options.origin);
  verify::VerifyReport report;
  try {
    report = verify::verify_joint_program(machine, options.joints, options.job, verify_options);
  } catch (const gcode::GcodeError& error) {
    throw CommandError(error.what());
  } catch (const verify::VerifyError& error) {
    throw CommandError(error.what());
  }
  const bool over = options.tolerance_mm > 0.0 && report.max_deviation_mm > options.tolerance_mm;
  if (!options.report.empty()) {
    nlohmann::json violations = nlohmann::json::array();
    for (const verify::JointViolation& v : report.violations) {
      violations.push_back({{"line", v.line},
                            {"joint", machine.joints()[static_cast<std::size_t>(v.joint)].name},
                            {"what", v.what},
                            {"value", v.value},
                            {"limit", v.limit}});
    }
    const nlohmann::json json = {{"joint_program", options.joints},
                                 {"job", options.job},
                                 {"blocks", report.blocks},
                                 {"max_deviation_mm", report.max_deviation_mm},
                                 {"rms_deviation_mm", report.rms_deviation_mm},
                                 {"max_deviation_joint_line", report.max_deviation_joint_line},
                                 {"max_deviation_job_line", report.max_deviation_job_line},
                                 {"tolerance_mm", options.tolerance_mm},
                                 {"within_tolerance", !over},
                                 {"violations", violations}};
    write_file_atomically(options.report, json.dump(2) + "\n");
  }
  std::printf(
      "%s against %s: %ld blocks, deviation max %.6f mm (line %d of the joint program, "
      "line %d of the job), RMS %.6f mm\n",
      options.joints.c_str(), options.job.c_str(), report.blocks, report.max_deviation_mm,
      report.max_deviation_joint_line, report.max_deviation_job_line, report.rms_deviation_mm);
  for (const verify::JointViolation& v : report.violations) {
    // Positions read as plan, post and ik say them; speeds name their limit.
    std::printf("  line %d: %s\n", v.line,
                v.what == "position"
                    ? machine.explain_joint(v.joint, v.value).c_str()
                    : ("joint '" + machine.joints()[static_cast<std::size_t>(v.joint)].name + "' " +
                       v.what + " " + std::to_string(v.value) + " beyond its limit " +
                       std::to_string(v.limit))
                          .c_str());
  }
  if (over) {
    throw CommandError("deviation " + std::to_string(report.max_deviation_mm) +
                       " mm exceeds the tolerance " + std::to_string(options.tolerance_mm) +
                       " mm at line " + std::to_string(report.max_deviation_joint_line) + " of " +
                       options.joints);
  }
  if (!report.violations.empty()) {
    throw CommandError(std::to_string(report.violations.size()) + " joint limit violations");
  }
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
      ->add_option("--tolerance", options->tolerance_mm,
                   "Exit non-zero when the deviation exceeds this, mm")
      ->check(number_in(kMinTolerance, kMaxTolerance));
  command->add_option("--report", options->report, "Write the report as JSON");
  add_pose_option(*command, "--origin", options->origin,
                  "Where the job's X0 Y0 Z0 sits in machine coordinates, mm and deg");
  command->callback([options] { run_verify(*options); });
}

}  // namespace pkm::app
