// The JSON reports of `pkm plan` and `pkm verify` (--report): the numbers their summaries print,
// made here so the command line and the Python module (pkmkit.plan, pkmkit.verify) give the same
// document. Values in the machine's interface units (mm, deg).
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "pkm/machine/machine.hpp"
#include "pkm/motion/planner.hpp"
#include "pkm/verify/joint_path.hpp"

namespace pkm::view {

// The report of a plan of `program` at `period_s`; `estimate`: the planner made no samples (the
// peak accelerations are then null: an estimate has none).
nlohmann::json plan_report_json(const Machine& machine, const motion::PlanReport& report,
                                const std::string& program, double period_s, bool estimate);

// The report of a verification of the joint program `joint_program` against the job `job`.
nlohmann::json verify_report_json(const Machine& machine, const std::string& joint_program,
                                  const std::string& job, const verify::VerifyReport& report);

// The unit of a finding's value and limit: a joint's own (mm or deg, per s for speeds) followed by
// `unit`, or `unit` alone where no joint is concerned (deviations and pen stretches, mm).
std::string violation_unit(const Machine& machine, const verify::Violation& v,
                           const std::string& unit);

}  // namespace pkm::view
