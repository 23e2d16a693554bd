// Shared pieces of the command-line layer.
#pragma once

#include <CLI/CLI.hpp>
#include <stdexcept>
#include <string>
#include <vector>

#include "pkm/gcode/interpreter.hpp"
#include "pkm/machine/machine.hpp"

namespace pkm::app {

// A failure the user caused (bad pose, unreachable target): message to stderr, exit status 1.
class CommandError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The machine named by -m, or the embedded default (the paper's hexapod) when none is given.
Machine load_machine_or_default(const std::string& path);

// x y z [a b c] in mm and deg from the command line; missing coordinates take the home pose's.
Pose pose_from_arguments(const Machine& machine, const std::vector<double>& values);

// `base` (mm, rad) with its leading coordinates replaced by `values` (x y z a b c, mm and deg).
Vector6d pose_vector_over(Vector6d base, const std::vector<double>& values);

// When the job's moves, placed at `origin` (mm, rad), lie outside the machine's reach: a line
// with both boxes and the --origin that would centre the job, to append to the error; "" when
// the job fits (or cannot be read again).
std::string job_reach_hint(const Machine& machine, const std::string& program,
                           const gcode::InterpreterOptions& options, const Vector6d& origin);

void register_kinematics_commands(CLI::App& app);
void register_calibrate_commands(CLI::App& app);
void register_gcode_commands(CLI::App& app);
void register_plan_commands(CLI::App& app);
void register_post_commands(CLI::App& app);
void register_verify_commands(CLI::App& app);

}  // namespace pkm::app
