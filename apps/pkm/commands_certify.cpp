// pkm check -m MACHINE JOB: the certified check of a job (docs/certified-check.md). Prints the
// verdict, or names the first move that is not proven and exits non-zero.
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <nlohmann/json.hpp>

#include "app.hpp"
#include "pkm/certify/job_check.hpp"
#include "pkm/gcode/gcode_error.hpp"
#include "pkm/kinematics/cable_tensions.hpp"
#include "pkm/kinematics/derivative_bounds.hpp"
#include "pkm/kinematics/hanging_cables.hpp"
#include "pkm/motion/job_reach.hpp"
#include "progress.hpp"

namespace pkm::app {

namespace {

std::string_view quantity_name(certify::Quantity quantity) {
  switch (quantity) {
    case certify::Quantity::joint:
      return "joint";
    case certify::Quantity::envelope:
      return "envelope";
    case certify::Quantity::joint_angle:
      return "joint_angle";
    case certify::Quantity::clearance:
      return "clearance";
    case certify::Quantity::assembly_mode:
      return "assembly_mode";
    case certify::Quantity::pull:
      return "pull";
    case certify::Quantity::tension:
      return "tension";
    case certify::Quantity::reach:
      return "reach";
    case certify::Quantity::none:
      break;
  }
  return "pose";
}

// What the proof covered on this machine, for the verdict's sentence.
std::string covered(const machine::Machine& machine) {
  std::string text = "joints within their limits";
  if (machine.cartesian().has_envelope()) text += ", the work envelope";
  if (machine.kinematics().has_mechanism_limits()) text += ", joint angles and leg clearances";
  if (machine.kinematics().assembly_mode(machine.home()) != 0) text += ", the assembly mode";
  if (const kinematics::HangingCables* cables = machine.kinematics().hanging_cables()) {
    text += ", both cables pulling";
    if (cables->tension_limited()) text += ", the cables' tension limits";
  }
  if (const kinematics::CableTensions* tensions = machine.kinematics().cable_tensions();
      tensions != nullptr && tensions->tension_limited()) {
    text += ", tensions within tension_limits holding the effector";
  }
  return text;
}

// A value in the file's units: joints and envelope coordinates as the machine writes them,
// angles in deg, clearances in the length unit.
double value_in_file_units(const machine::Machine& machine, const certify::Finding& finding,
                           double value) {
  switch (finding.quantity) {
    case certify::Quantity::joint:
      return machine.joint_to_file(finding.index, value);
    case certify::Quantity::envelope:
      return machine.axis_to_file(finding.index, value);
    case certify::Quantity::joint_angle:
      return geometry::radians_to_degrees(value);
    case certify::Quantity::clearance:
      return value / machine.mm_per_unit();
    case certify::Quantity::reach: {
      const kinematics::DerivativeBounds* own = machine.kinematics().derivative_bounds();
      const bool newtons = own != nullptr && own->reach_margin(finding.index).newtons;
      return newtons ? value : value / machine.mm_per_unit();
    }
    default:
      return value;
  }
}

nlohmann::json check_json(const machine::Machine& machine, const certify::JobCheck& check) {
  const certify::MoveProver names(machine);
  nlohmann::json failure = nullptr;
  if (check.first_failure) {
    const certify::Finding& f = check.first_failure->finding;
    nlohmann::json pose = nlohmann::json::object();
    for (int axis = 0; axis < geometry::kPoseSize; ++axis) {
      if (machine.kinematics().dof().controls(axis)) {
        pose[std::string(geometry::kAxisNames[axis])] = machine.axis_to_file(axis, f.pose[axis]);
      }
    }
    failure = {{"move", check.first_failure->index + 1},
               {"line", check.first_failure->line},
               {"verdict", std::string(certify::verdict_name(check.first_failure->verdict))},
               {"u", {f.u0, f.u1}},
               {"pose", pose},
               {"quantity", std::string(quantity_name(f.quantity))},
               {"constraint", names.quantity_name(f.quantity, f.index, f.other)},
               {"value", value_in_file_units(machine, f, f.value)},
               {"limit", value_in_file_units(machine, f, f.limit)},
               {"message", f.text}};
  }
  nlohmann::json warnings = nlohmann::json::array();
  for (const gcode::Warning& warning : check.warnings) {
    warnings.push_back({{"line", warning.line}, {"message", warning.message}});
  }
  return {{"job", check.file},
          {"machine", machine.name()},
          {"units", machine.length_unit()},
          {"certified", check.certified()},
          {"moves", check.moves},
          {"proven", check.proven},
          {"violated", check.violated},
          {"undecided", check.undecided},
          {"pieces", check.pieces},
          {"warnings", warnings},
          {"first_failure", failure}};
}

}  // namespace

void run_certified_check(const machine::Machine& machine,
                         const CertifiedCheckArguments& arguments) {
  certify::JobCheckOptions options;
  options.origin = pose_vector_over(machine, options.origin, arguments.origin);
  ProgressBar progress("check " + std::filesystem::path(arguments.job).filename().string(),
                       arguments.job);
  options.on_line = progress.on_line();
  certify::JobCheck check;
  try {
    check = certify::check_job(machine, arguments.job, options);
  } catch (const gcode::GcodeError& error) {
    throw CommandError(error.what());
  }
  progress.clear();
  for (const gcode::Warning& warning : check.warnings) {
    std::fprintf(stderr, "pkm: warning: %s:%d: %s\n", arguments.job.c_str(), warning.line,
                 warning.message.c_str());
  }
  if (arguments.json) std::cout << check_json(machine, check).dump(2) << "\n";
  const std::string counts = std::to_string(check.proven) + " of " + std::to_string(check.moves) +
                             " moves proven, " + std::to_string(check.violated) + " violated, " +
                             std::to_string(check.undecided) + " undecided";
  if (check.certified()) {
    if (!arguments.json) {
      std::printf("certified: %s on %s: all %ld moves proven (%ld pieces): every pose keeps %s\n",
                  arguments.job.c_str(), machine.name().c_str(), check.moves, check.pieces,
                  covered(machine).c_str());
    }
    return;
  }
  const certify::FailedMove& failed = *check.first_failure;
  // A job placed off the machine says where it would fit, as plan and post say it.
  std::string hint;
  if (failed.finding.quantity == certify::Quantity::joint ||
      failed.finding.quantity == certify::Quantity::envelope) {
    hint = motion::job_reach_hint(machine, arguments.job, options.job_options, options.origin);
  }
  throw CommandError(arguments.job + ":" + std::to_string(failed.line) + ": move " +
                     std::to_string(failed.index + 1) + " " +
                     std::string(certify::verdict_name(failed.verdict)) + ": " +
                     failed.finding.text + " (" + counts + ")" + hint);
}

}  // namespace pkm::app
