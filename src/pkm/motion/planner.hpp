// Time-division interpolation: every move of a G-code program split into equal time steps of
// the interpolation period, the tool pose at the end of each step turned into joint values by
// inverse kinematics, streamed to a sink.
//
// Moves are joined by look-ahead (G64 corner blends, tangent joins). Without a jerk limit the
// speed along each move is time-optimal under every limit at once (time_optimal.hpp: each
// joint's velocity and acceleration, the tool's acceleration as one budget, a hanging effector's
// cable tensions), with a reserve only near joins that need one; with a jerk limit (--jerk or a
// joint's max_jerk) each move has one top speed and acceleration and S-curve ramps. On a machine
// that does not move Z, Z takes no time; with a pen channel the pen changes at rest, where the
// program's Z crosses its height, for the pen's delay.
#pragma once

#include <filesystem>
#include <functional>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "pkm/gcode/interpreter.hpp"
#include "pkm/machine/machine.hpp"
#include "pkm/motion/segment.hpp"

namespace pkm::motion {

struct Sample {
  double time_s = 0.0;
  int line = 0;                                          // G-code line of the move
  geometry::Vector6d pose = geometry::Vector6d::Zero();  // x y z (mm) a b c (rad)
  kinematics::JointVector joints;                        // mm (rad for rotary joints)
  bool pen_down = false;  // the pen channel's state (machines with [tool] z = "pen")
};

// Where samples go: a file, a test, a controller.
class SampleSink {
 public:
  virtual ~SampleSink() = default;
  virtual void write(const Sample& sample) = 0;
};

// A piece of the path as the planner sampled it: a move after look-ahead's joins (a G64 blend arc
// between two lines, the lines shortened by it), whether the machine stops after it, and the
// timing the plan gave it. For a reference planner over the same path (tests/, bench/).
struct PlannedPiece {
  Segment segment;
  double length_mm = 0.0;  // as Segment::length()
  bool stop_after = false;
  double entry_speed_mm_per_s = 0.0, exit_speed_mm_per_s = 0.0;
  double duration_s = 0.0;
};

struct PlanOptions {
  double period_s = 0.001;              // LinuxCNC's servo period
  std::optional<geometry::Pose> start;  // default: the machine's home
  // Where the program's origin (X0 Y0 Z0 before any G54..G59.3/G92 offset) sits in machine
  // coordinates: mm and rad. Places a drawing made about (0, 0) on a plotter hanging below.
  geometry::Vector6d origin = geometry::Vector6d::Zero();
  // The tool axis along a great circle within each move (the paper's variable attitude) instead
  // of A B C interpolated linearly (LinuxCNC's way, the default).
  bool great_circle_attitude = false;
  // Tool-tip jerk limit, mm/s^3: accelerations rise and fall linearly (S-curves). 0: none,
  // accelerations switch at once (trapezoidal profiles, as LinuxCNC's planner).
  double jerk_mm_per_s3 = 0.0;
  // Called with the G-code line being planned, once per change of line: for progress.
  std::function<void(int line)> on_line;
  // Called with every piece of the path in order as it is planned (a reference's input).
  std::function<void(const PlannedPiece& piece)> on_piece;
  // Plan every move but make no samples: the report's duration, sample count, joint ranges and
  // feed limits without the inverse kinematics of every sample (which is most of the work) and
  // without writing. Ranges come from the joints along each move (every 0.5 mm) and peak
  // velocities from their rate along the path times the move's top speed.
  bool estimate_only = false;
  // The most samples a plan may make (0: no bound); a plan that needs more stops at the move
  // that would pass it, before sampling it. Estimates count on past it.
  long max_samples = 0;
};

// The bounds every interface (pkm plan, the Python module) puts on PlanOptions: a servo loop runs
// between a few microseconds and a second (period_s); a jerk limit (per s^3, in the interface's
// length unit) up to kMaxJerkPerS3.
inline constexpr double kMinPeriodS = 1e-6, kMaxPeriodS = 1.0;
inline constexpr double kMaxJerkPerS3 = 1e12;
// max_samples: at most kMaxSamplesBound (0: no bound, in the Python module), and unless told
// otherwise kDefaultMaxSamples: 14 hours at 1 ms, some 5 GB of NPY for a hexapod. A job past it is
// most likely a wrong period or machine file.
inline constexpr long kMaxSamplesBound = 1'000'000'000'000'000;
inline constexpr long kDefaultMaxSamples = 50'000'000;

// Where an estimate stops counting samples (a job of 30,000 years at 1 ms).
inline constexpr long kSampleCountCap = 1'000'000'000'000'000'000;

struct JointStatistics {
  double min = 0.0, max = 0.0;     // position reached
  double peak_velocity = 0.0;      // per s, from successive samples
  double peak_acceleration = 0.0;  // per s^2
};

// What lowered a move's feed or acceleration: a joint's velocity or acceleration limit, or (on a
// cable machine whose effector has a mass) a cable's tension limit.
enum class LimitCause { joint, tension };

// Which of a joint's limits lowered a move's feed: its velocity (its rate along the path times
// the speed), or its acceleration where the path bends in joint space (an arc, a G64 corner
// blend, a cable's line near its anchor: the joint's second derivative times the speed squared).
enum class JointBound { velocity, acceleration };

// The curve a move is, where its own bend bounds the speed: v^2/r within the Cartesian
// max_acceleration (half of it with a jerk limit). A blend is the arc G64 puts at the corner
// between two lines.
enum class CurveKind { none, arc, blend };

// A move whose feed a joint, or a cable's tension on a curve, lowered: the limit that did it and
// its numbers, so that a user can tell a joint too slow for the job from a corner too sharp.
struct FeedLimit {
  int line = 0;
  int joint = 0;  // for LimitCause::tension, the cable: 0 left, 1 right (its joint)
  double programmed_mm_per_s = 0.0;  // the program's F (the machine's max_feed for rapids)
  double allowed_mm_per_s = 0.0;
  LimitCause cause = LimitCause::joint;
  // For LimitCause::joint: the limit that bound, the joint's velocity (per s) or acceleration
  // (per s^2) the move would need at the programmed feed (capped at max_feed), and the part of
  // the limit a move may use (99.9 % of max_velocity and of max_acceleration for the bend; with
  // a jerk limit 99 % and 40 %). mm or rad, as the joint.
  JointBound bound = JointBound::velocity;
  double needed_at_programmed = 0.0;
  double usable = 0.0;
  // For LimitCause::tension: faster, the cable would go slack (else pass its maximum tension).
  bool slack = false;
  // The curve, when the move is one. For a blend, `line` is the line after the corner and
  // `previous_line` the one before; `turn_rad` the angle between them.
  CurveKind curve = CurveKind::none;
  int previous_line = 0;
  double radius_mm = 0.0;
  double turn_rad = 0.0;
  // What the Cartesian acceleration alone allows on the curve: the speed, and the part of
  // max_acceleration v^2/r may take. 0 off curves.
  double curve_allowed_mm_per_s = 0.0;
  double curve_acceleration_mm_per_s2 = 0.0;
};

// A move whose acceleration a cable's tension lowered: accelerating or braking harder along it
// would take the cable below tension_min_N (slack) or above tension_max_N.
struct TensionLimitedMove {
  int line = 0;
  int cable = 0;  // 0 left, 1 right (its joint)
  bool slack = false;
  double machine_mm_per_s2 = 0.0;  // what the joints and [cartesian] allowed the move
  double allowed_mm_per_s2 = 0.0;
};

struct PlanReport {
  double duration_s = 0.0;
  long samples = 0;  // estimates of an absurd job stop counting at kSampleCountCap
  double path_length_mm = 0.0;
  std::vector<JointStatistics> joints;
  std::vector<FeedLimit> feed_limits;
  std::vector<TensionLimitedMove> tension_limits;
  std::vector<gcode::Warning> warnings;
  int pen_changes = 0;  // times the pen channel went down or up
};

// A move the machine cannot make, with the G-code line and the reason (joint, limit).
class PlanError : public std::runtime_error {
 public:
  PlanError(std::string file, int line, const std::string& message)
      : std::runtime_error(file + ":" + std::to_string(line) + ": " + message), line_(line) {}
  int line() const { return line_; }

 private:
  int line_;
};

PlanReport plan_program(const machine::Machine& machine, const std::filesystem::path& program,
                        const gcode::InterpreterOptions& interpreter_options,
                        const PlanOptions& options, SampleSink& sink);

}  // namespace pkm::motion
