// Joint-space G-code for controllers without kinematics (Mach3, grbl, LinuxCNC with trivkins):
// axis words are joint positions, and the programmed path is split adaptively so that the tool
// tip of a controller that interpolates the joints linearly stays within a tolerance of it,
// measured by forward kinematics.
#pragma once

#include <filesystem>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include "pkm/gcode/interpreter.hpp"
#include "pkm/machine/machine.hpp"

namespace pkm::post {

enum class Dialect { linuxcnc, mach3, grbl };

// Number format and line length of each controller.
struct DialectRules {
  int decimals = 5;          // digits after the point of joint values
  std::size_t max_line = 0;  // longest line accepted (0: no limit)
};
DialectRules rules_of(Dialect dialect);

struct PostOptions {
  double tolerance_mm = 0.01;
  Dialect dialect = Dialect::linuxcnc;
  Vector6d origin = Vector6d::Zero();  // where the program's X0 Y0 Z0 sits (mm, rad)
};

struct PostReport {
  long blocks = 0;                // motion blocks written
  long moves = 0;                 // programmed moves
  double max_deviation_mm = 0.0;  // verified: forward kinematics along each written block
  int max_deviation_line = 0;     // source line of the move where it peaks
  std::vector<gcode::Warning> warnings;
};

class PostError : public std::runtime_error {
 public:
  PostError(const std::string& file, int line, const std::string& message)
      : std::runtime_error(file + ":" + std::to_string(line) + ": " + message) {}
};

// Writes the body of the joint program (every line through `write_line`, without a header).
PostReport post_program(const Machine& machine, const std::filesystem::path& program,
                        const gcode::InterpreterOptions& interpreter_options,
                        const PostOptions& options,
                        const std::function<void(const std::string&)>& write_line);

}  // namespace pkm::post
