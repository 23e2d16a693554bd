#include "pkm/verify/joint_path.hpp"

#include <algorithm>
#include <cmath>
#include <string_view>

#include "pkm/geometry/distance.hpp"
#include "pkm/motion/segment_builder.hpp"

namespace pkm::verify {

namespace {

constexpr std::string_view kLetters = "XYZABCUVW";
constexpr int kPathPoints = 256;  // polyline of each programmed move for the distance

// The programmed path: each move of the job as a dense polyline with its source line.
struct PathPiece {
  int line = 0;
  std::vector<Eigen::Vector3d> points;
};

double distance_to_piece(const Eigen::Vector3d& p, const PathPiece& piece) {
  return distance_to_polyline(p, piece.points);
}

std::vector<PathPiece> read_job(const Machine& machine, const std::filesystem::path& job,
                                const VerifyOptions& options) {
  const gcode::InterpreterOptions interpreter_options =
      motion::starting_at({}, machine.home().as_vector(), options.origin);
  motion::SegmentBuilder builder(machine.home().as_vector(), options.origin, false);
  std::vector<PathPiece> path;
  gcode::Interpreter(job, interpreter_options).run([&](const gcode::Canon& canon) {
    const auto segment = builder.take(canon);
    if (!segment || segment->kind == motion::SegmentKind::dwell || segment->length() <= 0.0) {
      return;
    }
    PathPiece piece;
    piece.line = segment->line;
    const int points = segment->kind == motion::SegmentKind::line ? 1 : kPathPoints;
    for (int k = 0; k <= points; ++k)
      piece.points.push_back(segment->at(k / double(points)).head<3>());
    path.push_back(std::move(piece));
  });
  return path;
}

}  // namespace

VerifyReport verify_joint_program(const Machine& machine, const std::filesystem::path& joints,
                                  const std::filesystem::path& job, const VerifyOptions& options) {
  const std::vector<PathPiece> path = read_job(machine, job, options);
  if (path.empty()) throw VerifyError(job.string() + ": the job has no moves to compare with");
  const int joint_count = static_cast<int>(machine.joints().size());
  std::vector<int> index_of_joint(static_cast<std::size_t>(joint_count));
  for (int i = 0; i < joint_count; ++i) {
    index_of_joint[static_cast<std::size_t>(i)] =
        static_cast<int>(kLetters.find(machine.joints()[static_cast<std::size_t>(i)].axis_letter));
  }
  // The joint program starts where the machine is: at home.
  JointVector previous;
  if (!machine.inverse(machine.home(), previous).ok()) throw VerifyError("home is not usable");
  gcode::InterpreterOptions interpreter_options;
  for (int i = 0; i < joint_count; ++i) {
    interpreter_options.start_position[index_of_joint[static_cast<std::size_t>(i)]] =
        machine.joints()[static_cast<std::size_t>(i)].to_interface(previous[i]);
  }
  VerifyReport report;
  double sum_of_squares = 0.0;
  long count = 0;
  std::size_t cursor = 0;  // the path piece the tool was last nearest to
  Pose pose = machine.home();
  gcode::Interpreter(joints, interpreter_options).run([&](const gcode::Canon& canon) {
    if (canon.kind != gcode::CanonKind::traverse && canon.kind != gcode::CanonKind::feed) return;
    const double scale = canon.units == gcode::LengthUnits::inch ? 25.4 : 1.0;
    JointVector q(joint_count);
    for (int i = 0; i < joint_count; ++i) {
      const JointSpec& joint = machine.joints()[static_cast<std::size_t>(i)];
      const double value = canon.end[index_of_joint[static_cast<std::size_t>(i)]];
      q[i] = joint.kind == JointKind::rotary ? degrees_to_radians(value) : value * scale;
      if (q[i] < joint.min || q[i] > joint.max) {
        report.violations.push_back(
            {canon.line, i, "position", q[i], q[i] < joint.min ? joint.min : joint.max});
      }
    }
    ++report.blocks;
    // Joint speeds: G93 blocks take 1/F minutes; G94 moves the joint vector at F per minute;
    // rapids are the controller's own business.
    if (canon.kind == gcode::CanonKind::feed && canon.value > 0.0) {
      const double length = (q - previous).norm();
      const double duration = canon.feed_mode == gcode::FeedMode::inverse_time
                                  ? 60.0 / canon.value
                                  : length / (canon.value * scale / 60.0);
      for (int i = 0; i < joint_count && duration > 0.0; ++i) {
        const double speed = std::abs(q[i] - previous[i]) / duration;
        const double limit = machine.joints()[static_cast<std::size_t>(i)].max_velocity;
        if (speed > limit * (1.0 + 1e-9)) {
          report.violations.push_back({canon.line, i, "velocity", speed, limit});
        }
      }
    }
    for (int k = 1; k <= options.points_per_block; ++k) {
      const JointVector at = previous + (k / double(options.points_per_block)) * (q - previous);
      if (!machine.kinematics().forward(at, pose).ok()) {
        throw VerifyError(joints.string() + ":" + std::to_string(canon.line) +
                          ": no tool pose for these joints (forward kinematics failed)");
      }
      // Nearest programmed piece, searched about the cursor: the program follows its job.
      double nearest = INFINITY;
      std::size_t nearest_piece = cursor;
      const std::size_t from = cursor > 2 ? cursor - 2 : 0;
      const std::size_t to = std::min(path.size(), cursor + 64);
      for (std::size_t p = from; p < to; ++p) {
        const double d = distance_to_piece(pose.position_mm, path[p]);
        if (d < nearest) {
          nearest = d;
          nearest_piece = p;
        }
      }
      cursor = nearest_piece;
      sum_of_squares += nearest * nearest;
      ++count;
      if (nearest > report.max_deviation_mm) {
        report.max_deviation_mm = nearest;
        report.max_deviation_joint_line = canon.line;
        report.max_deviation_job_line = path[nearest_piece].line;
      }
    }
    previous = q;
  });
  report.rms_deviation_mm =
      count > 0 ? std::sqrt(sum_of_squares / static_cast<double>(count)) : 0.0;
  return report;
}

}  // namespace pkm::verify
