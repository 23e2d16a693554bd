// The certified check of a whole job: every programmed move, read as post and verify read it
// (from the machine's home, program zero at `origin`), proven to keep the machine within its
// limits at every pose (move_proof.hpp), or the first move where that fails or cannot be shown.
#pragma once

#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "pkm/certify/move_proof.hpp"
#include "pkm/gcode/interpreter.hpp"

namespace pkm::certify {

struct JobCheckOptions {
  gcode::InterpreterOptions job_options;
  geometry::Vector6d origin =
      geometry::Vector6d::Zero();  // where the job's X0 Y0 Z0 sits (mm, rad)
  ProofOptions proof;
  std::function<void(int line)> on_line;  // progress: each source line as it is read
};

// The first move that was not proven.
struct FailedMove {
  long index = 0;  // of the move, from 0
  int line = 0;    // its G-code line
  Verdict verdict = Verdict::undecided;
  Finding finding;
};

struct JobCheck {
  std::string file;
  long moves = 0, proven = 0, violated = 0, undecided = 0;
  long pieces = 0;  // pieces bounded over all moves
  std::optional<FailedMove> first_failure;
  std::string unavailable;               // why no move can be proven on this machine, or empty
  std::vector<gcode::Warning> warnings;  // a plotter's pen that never goes down or up
  bool certified() const { return moves == proven; }
};

// Throws gcode::GcodeError for a job that cannot be read (file:line:column).
JobCheck check_job(const machine::Machine& machine, const std::filesystem::path& job,
                   const JobCheckOptions& options);

}  // namespace pkm::certify
