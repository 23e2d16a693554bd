// Verification of any joint-space program (pkmkit's or anyone's) against the Cartesian job it is
// meant to follow: the tool path a controller makes by interpolating its joints linearly,
// reconstructed by forward kinematics, held block by block against the stretch of the job each
// block must trace (found by walking the job forward, so coverage is proven with the deviation);
// the joints' limits and speeds; and, on machines with a pen channel, the pen. Both programs are
// streamed: memory does not grow with their length.
#pragma once

#include <filesystem>
#include <functional>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "pkm/gcode/interpreter.hpp"
#include "pkm/machine/machine.hpp"

namespace pkm::verify {

// One block of the joint program as verify reconstructs it by forward kinematics: for a view.
struct VerifiedBlock {
  int line = 0;             // joint program
  int job_line = 0;         // the job's line it was held against where it deviates most
  geometry::Pose end_pose;  // the tool's pose at the block's end (mm, rad)
  kinematics::JointVector joints;
  double deviation_mm = 0.0;  // the block's largest distance from the job
};

struct VerifyOptions {
  double tolerance_mm = 0.01;  // largest deviation accepted, mm (post's default; > 0)
  geometry::Vector6d origin =
      geometry::Vector6d::Zero();  // where the job's X0 Y0 Z0 sits (mm, rad)
  // The job's tool table and block delete; its loop bounds hold for the joint program too.
  gcode::InterpreterOptions job_options;
  // Called with the joint program's line being verified, once per change of line: for progress.
  std::function<void(int line)> on_line;
  // Called after each block is measured (optional): what pkm's HTML views draw.
  std::function<void(const VerifiedBlock& block)> on_block;
};

// One finding, at a line of the joint program and the job line it was held against.
struct Violation {
  int line = 0;                     // joint program
  int job_line = 0;                 // job (0 where there is none)
  int joint = -1;                   // the joint, for position and velocity
  double value = 0.0, limit = 0.0;  // mm, mm/s, deg or deg/s; pen: the stretch's length, mm
  std::string detail;  // pen: what the pen does against what the job asks; position: the joint
                       // and limit as ik, plan and post explain them
};

// Findings of one kind, summarised: a job with thousands is shown by its count, worst and first.
struct ViolationSummary {
  static constexpr std::size_t kFirst = 5;
  long count = 0;
  Violation worst;               // the one furthest beyond its limit
  std::vector<Violation> first;  // the first kFirst, in order
  void add(const Violation& violation);
};

struct VerifyReport {
  long blocks = 0;
  double tolerance_mm = 0.0;
  double max_deviation_mm = 0.0;
  double rms_deviation_mm = 0.0;
  int max_deviation_joint_line = 0;  // line of the joint program where the deviation peaks
  int max_deviation_job_line = 0;    // line of the job held against it there
  ViolationSummary deviation;        // blocks beyond the tolerance
  ViolationSummary position;         // block ends beyond a joint's travel
  ViolationSummary velocity;         // feed blocks driving a joint beyond its max_velocity
  ViolationSummary pen;              // stretches drawn with the pen where the job lifts it, or not
  // Pen downs: strokes without length (dots) leave no stretch, so they are counted. Equal on a
  // machine without a pen channel (0).
  long pen_downs = 0;
  long job_pen_downs = 0;
  int first_job_pen_down_line = 0;
  // Coverage: the job traced from its start to its end, in order.
  bool covered = false;
  double job_length_mm = 0.0;  // in the coordinates the machine controls
  double traced_mm = 0.0;
  int coverage_stopped_job_line = 0;    // the first job line left untraced (when not covered)
  int coverage_stopped_joint_line = 0;  // the joint program's last block (0: none)
  // The job's pauses, tool changes, I/O and user M-codes (gcode/machine_commands.hpp) found in
  // the joint program in the same order at the same place; otherwise the first that is not,
  // "job line 6: M62 P1 is not in the joint program" (override switches, which change no
  // position, are not compared).
  std::string commands_mismatch;

  bool passed() const {
    return covered && deviation.count == 0 && position.count == 0 && velocity.count == 0 &&
           pen.count == 0 && pen_downs == job_pen_downs && commands_mismatch.empty();
  }
};

class VerifyError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

VerifyReport verify_joint_program(const machine::Machine& machine,
                                  const std::filesystem::path& joints,
                                  const std::filesystem::path& job, const VerifyOptions& options);

// The tolerance pkm post wrote in the joint program's header ("(tolerance 0.010000 mm; ..."), if
// any of its first lines carries one. Throws VerifyError when it is there but not a positive
// finite number.
std::optional<double> tolerance_in_header(const std::filesystem::path& joints);

}  // namespace pkm::verify
