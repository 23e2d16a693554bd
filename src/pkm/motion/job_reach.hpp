// The hint a plan's or post's error ends with when the job does not fit the machine: its moves'
// box and the machine's reach, and the --origin that would centre the job (pkm plan, pkm post,
// and the Python module's PlanError and PostError).
#pragma once

#include <filesystem>
#include <string>

#include "pkm/gcode/interpreter.hpp"
#include "pkm/machine/machine.hpp"

namespace pkm::motion {

// When the job's moves, placed at `origin` (mm, rad), lie outside the machine's reach:
// "\n  hint: " and a line with both boxes and the --origin that would centre the job, to append
// to the error; "" when the job fits (or cannot be read again).
std::string job_reach_hint(const machine::Machine& machine, const std::filesystem::path& program,
                           const gcode::InterpreterOptions& options,
                           const geometry::Vector6d& origin);

}  // namespace pkm::motion
