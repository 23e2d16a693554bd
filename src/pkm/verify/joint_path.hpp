// Verification of any joint-space program (pkmkit's or anyone's): the tool path a controller
// makes by interpolating its joints linearly, reconstructed by forward kinematics, measured
// against the Cartesian job it is meant to follow; and its joint limits and speeds.
#pragma once

#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include "pkm/gcode/interpreter.hpp"
#include "pkm/machine/machine.hpp"

namespace pkm::verify {

struct VerifyOptions {
  int points_per_block = 32;           // forward kinematics along each block
  Vector6d origin = Vector6d::Zero();  // where the job's X0 Y0 Z0 sits (mm, rad)
};

struct JointViolation {
  int line = 0;  // line of the joint program
  int joint = 0;
  std::string what;  // "position" or "velocity"
  double value = 0.0, limit = 0.0;
};

struct VerifyReport {
  long blocks = 0;
  double max_deviation_mm = 0.0;
  double rms_deviation_mm = 0.0;
  int max_deviation_joint_line = 0;  // line of the joint program where the deviation peaks
  int max_deviation_job_line = 0;    // line of the job whose path is nearest there
  std::vector<JointViolation> violations;
};

class VerifyError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

VerifyReport verify_joint_program(const Machine& machine, const std::filesystem::path& joints,
                                  const std::filesystem::path& job, const VerifyOptions& options);

}  // namespace pkm::verify
