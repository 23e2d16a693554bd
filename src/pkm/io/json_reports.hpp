// The JSON reports of `pkm plan`, `pkm post`, `pkm verify` and `pkm view` (--report): the numbers
// their summaries print, made here so the command line, the Python module (pkmkit.plan,
// pkmkit.post, pkmkit.verify) and the HTML pages (which embed them) give the same document.
// Values in the machine's interface units (mm, deg).
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "pkm/machine/machine.hpp"
#include "pkm/motion/planner.hpp"
#include "pkm/post/joint_program.hpp"
#include "pkm/verify/joint_path.hpp"
#include "pkm/verify/joint_trace.hpp"

namespace pkm::io {

// The report of a plan of `program` at `period_s`; `estimate`: the planner made no samples (the
// peak accelerations are then null: an estimate has none).
nlohmann::json plan_report_json(const machine::Machine& machine, const motion::PlanReport& report,
                                const std::string& program, double period_s, bool estimate);

// Why a move's feed was lowered, in the machine file's units: the limit that did it with its
// value at the programmed feed against what the move may use, and the curve (arc or G64 corner
// blend) with what the Cartesian acceleration alone allows on it, e.g.
// "F1500.0 lowered to F271.3 at the G64 corner blend after line 7 (turn 90.0 deg, radius
// 0.0341 mm): joint right's acceleration would be 18342.7 mm/s^2 at F1500.0, over the 600.0
// mm/s^2 it may use on a bend (half of 80 % of max_acceleration 1500.0); the tool's own v^2/r
// allows F271.6 (within 600.0 mm/s^2, half the acceleration the move may use; max_acceleration
// 1200.0)", or "F30000.0 lowered to F314.2 ...: the right cable would go slack at a higher
// speed". Feeds in the machine's length unit per minute.
std::string feed_limit_text(const machine::Machine& machine, const motion::FeedLimit& limit);

// The report of `pkm post` of `program` into `output`: the numbers its summary line prints.
nlohmann::json post_report_json(const machine::Machine& machine, const std::string& program,
                                const std::string& output, const post::PostReport& report,
                                double tolerance_mm);

// The report of a verification of the joint program `joint_program` against the job `job`.
nlohmann::json verify_report_json(const machine::Machine& machine, const std::string& joint_program,
                                  const std::string& job, const verify::VerifyReport& report);

// The report of `pkm view` of the joint program `joint_program` (docs/html-views.md, "A joint
// program alone"): lengths in mm, each joint's range against its travel in its interface unit.
nlohmann::json view_report_json(const machine::Machine& machine, const std::string& joint_program,
                                const verify::TraceReport& report);

// The unit of a finding's value and limit: a joint's own (mm or deg, per s for speeds) followed by
// `unit`, or `unit` alone where no joint is concerned (deviations and pen stretches, mm).
std::string violation_unit(const machine::Machine& machine, const verify::Violation& v,
                           const std::string& unit);

}  // namespace pkm::io
