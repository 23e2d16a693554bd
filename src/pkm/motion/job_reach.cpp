#include "pkm/motion/job_reach.hpp"

#include <algorithm>
#include <cmath>

namespace pkm::motion {

std::string job_reach_hint(const machine::Machine& machine, const std::filesystem::path& program,
                           const gcode::InterpreterOptions& options,
                           const geometry::Vector6d& origin) {
  machine::PoseBox job;
  job.min = geometry::Vector6d::Constant(INFINITY);
  job.max = geometry::Vector6d::Constant(-INFINITY);
  try {
    gcode::Interpreter(program, options).run([&](const gcode::Canon& canon) {
      if (canon.kind != gcode::CanonKind::traverse && canon.kind != gcode::CanonKind::feed) return;
      const double scale = canon.units == gcode::LengthUnits::inch ? 25.4 : 1.0;
      for (int axis = 0; axis < 3; ++axis) {
        job.min[axis] = std::min(job.min[axis], canon.end[axis] * scale);
        job.max[axis] = std::max(job.max[axis], canon.end[axis] * scale);
      }
    });
  } catch (const std::exception&) {
    return "";  // the error being reported says what is wrong with the job
  }
  for (int axis = 0; axis < 3; ++axis) {
    if (!std::isfinite(job.min[axis])) return "";
    job.axes = job.axes.with(axis);
  }
  const std::string hint = machine::outside_reach_hint(machine, job, origin);
  return hint.empty() ? "" : "\n  hint: " + hint;
}

}  // namespace pkm::motion
