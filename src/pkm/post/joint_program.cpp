#include "pkm/post/joint_program.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "pkm/geometry/distance.hpp"
#include "pkm/motion/segment_builder.hpp"

namespace pkm::post {

namespace {

using motion::Segment;
using motion::SegmentKind;

constexpr int kCheckPoints = 32;  // interior points of a block checked by FK
constexpr int kPathPoints = 64;   // polyline of the programmed sub-path the distance is taken to
constexpr int kMaxDepth = 40;     // halvings of one move before giving up

class Poster {
 public:
  Poster(const Machine& machine, const PostOptions& options,
         const std::function<void(const std::string&)>& write_line, std::string file)
      : machine_(machine),
        options_(options),
        rules_(rules_of(options.dialect)),
        write_line_(write_line),
        file_(std::move(file)),
        builder_(machine.home().as_vector(), options.origin, false) {
    JointVector home;
    const Status status = machine_.inverse(machine_.home(), home);
    if (!status.ok())
      throw PostError(file_, 0, "home is not usable: " + machine_.explain(machine_.home(), status));
    joints_ = rounded(home);
    write_line_("G21 G90 G94");
  }

  void on_canon(const gcode::Canon& canon) {
    using gcode::CanonKind;
    switch (canon.kind) {
      case CanonKind::spindle_speed:
        write_line_(format("S%.1f", canon.value));
        return;
      case CanonKind::spindle_clockwise:
        write_line_("M3");
        return;
      case CanonKind::spindle_counterclockwise:
        write_line_("M4");
        return;
      case CanonKind::spindle_stop:
        write_line_("M5");
        return;
      case CanonKind::mist_on:
        write_line_("M7");
        return;
      case CanonKind::flood_on:
        write_line_("M8");
        return;
      case CanonKind::flood_off:
        write_line_("M9");
        return;
      case CanonKind::program_end:
        if (!ended_) write_line_("M2");
        ended_ = true;
        return;
      default:
        break;
    }
    const std::optional<Segment> segment = builder_.take(canon);
    if (!segment) return;
    if (segment->kind == SegmentKind::dwell) {
      write_line_(format("G4 P%.3f", segment->dwell_s));
      return;
    }
    if (segment->length() <= 0.0) return;
    ++report_.moves;
    JointVector end;
    const Status status = machine_.inverse(Pose::from_vector(segment->end), end);
    if (!status.ok()) {
      throw PostError(file_, segment->line,
                      "the move leaves the machine's reach " +
                          machine_.explain_path([&](double v) { return segment->at(v); }));
    }
    split(*segment, 0.0, 1.0, joints_, rounded(end), 0);
  }

  PostReport finish() {
    if (!ended_) write_line_("M2");
    return report_;
  }

 private:
  static std::string format(const char* pattern, double value) {
    char text[64];
    std::snprintf(text, sizeof text, pattern, value);
    return text;
  }

  // Joint values as the controller will read them: rounded to the dialect's decimals in
  // interface units (mm, deg).
  JointVector rounded(const JointVector& q) const {
    JointVector result = q;
    const double scale = std::pow(10.0, rules_.decimals);
    for (int i = 0; i < q.size(); ++i) {
      const JointSpec& joint = machine_.joints()[static_cast<std::size_t>(i)];
      result[i] = joint.from_interface(std::round(joint.to_interface(q[i]) * scale) / scale);
    }
    return result;
  }

  // The largest distance between the tool tip of a joint-linear move from q0 to q1 and the
  // programmed path between u0 and u1, or infinity where forward kinematics fails.
  double deviation(const Segment& segment, double u0, double u1, const JointVector& q0,
                   const JointVector& q1) const {
    std::array<Eigen::Vector3d, kPathPoints + 1> path;
    for (int m = 0; m <= kPathPoints; ++m) {
      path[static_cast<std::size_t>(m)] = segment.at(u0 + (u1 - u0) * m / kPathPoints).head<3>();
    }
    double worst = 0.0;
    for (int k = 0; k <= kCheckPoints; ++k) {
      const double lambda = static_cast<double>(k) / kCheckPoints;
      Pose pose = Pose::from_vector(segment.at(u0 + (u1 - u0) * lambda));  // FK's seed
      const JointVector q = q0 + lambda * (q1 - q0);
      if (!machine_.forward(q, pose).ok()) return INFINITY;
      const double nearest = distance_to_polyline(pose.position_mm, path);
      worst = std::max(worst, nearest);
    }
    return worst;
  }

  // The joints at fraction u of a move, as the controller will read them.
  JointVector joints_at(const Segment& segment, double u) const {
    JointVector q;
    const Status status = machine_.inverse(Pose::from_vector(segment.at(u)), q);
    if (!status.ok()) {
      throw PostError(file_, segment.line,
                      "the move leaves the machine's reach " +
                          machine_.explain_path([&](double v) { return segment.at(v); }));
    }
    return rounded(q);
  }

  // Covers the move greedily with blocks as long as the tolerance allows: from each block's
  // start, the furthest end (found by halving, then bisection) whose joint-linear move stays
  // within the tolerance. Block lengths follow how sharply the kinematics bends the path.
  void split(const Segment& segment, double u0, double /*u1*/, const JointVector& q_start,
             const JointVector& q_end, int /*depth*/) {
    JointVector q0 = q_start;
    double start = u0;
    while (start < 1.0) {
      const double rest = deviation(segment, start, 1.0, q0, q_end);
      if (rest <= options_.tolerance_mm) {
        write_block(segment, start, 1.0, q0, q_end, rest);
        return;
      }
      double step = 0.5 * (1.0 - start);
      double good = -1.0, good_deviation = 0.0;
      JointVector q_good;
      for (int halvings = 0; halvings < kMaxDepth; ++halvings, step *= 0.5) {
        const JointVector q = joints_at(segment, start + step);
        const double d = deviation(segment, start, start + step, q0, q);
        if (d <= options_.tolerance_mm) {
          good = start + step;
          good_deviation = d;
          q_good = q;
          break;
        }
      }
      if (good < 0.0) {
        throw PostError(file_, segment.line,
                        "cannot keep within " + std::to_string(options_.tolerance_mm) +
                            " mm here (a singularity, or a tolerance below the dialect's " +
                            std::to_string(rules_.decimals) + " decimals)");
      }
      // Between `good` (within) and twice the step (not, or the end): bisect for the furthest.
      double bad = std::min(1.0, start + 2.0 * step);
      for (int i = 0; i < 10; ++i) {
        const double middle = 0.5 * (good + bad);
        const JointVector q = joints_at(segment, middle);
        const double d = deviation(segment, start, middle, q0, q);
        if (d <= options_.tolerance_mm) {
          good = middle;
          good_deviation = d;
          q_good = q;
        } else {
          bad = middle;
        }
      }
      write_block(segment, start, good, q0, q_good, good_deviation);
      q0 = q_good;
      start = good;
    }
  }

  void write_block(const Segment& segment, double u0, double u1, const JointVector& q0,
                   const JointVector& q1, double worst) {
    std::string line = segment.rapid ? "G0" : "G1";
    if (!segment.rapid && !inverse_time_) {
      line = "G93 " + line;
      inverse_time_ = true;
    }
    char number[48];
    for (int i = 0; i < q1.size(); ++i) {
      const JointSpec& joint = machine_.joints()[static_cast<std::size_t>(i)];
      std::snprintf(number, sizeof number, " %c%.*f", joint.axis_letter, rules_.decimals,
                    joint.to_interface(q1[i]));
      line += number;
    }
    if (!segment.rapid) {
      // Inverse time: the block takes the programmed path's length at the programmed feed, or
      // longer where a joint would otherwise exceed its velocity.
      double duration = segment.length() * (u1 - u0) / segment.feed_mm_per_s;
      for (int i = 0; i < q1.size(); ++i) {
        duration =
            std::max(duration, std::abs(q1[i] - q0[i]) /
                                   machine_.joints()[static_cast<std::size_t>(i)].max_velocity);
      }
      std::snprintf(number, sizeof number, " F%.*f", 3, 60.0 / duration);
      line += number;
    }
    if (rules_.max_line > 0 && line.size() > rules_.max_line) {
      throw PostError(file_, segment.line,
                      "a block of " + std::to_string(line.size()) + " characters exceeds the " +
                          std::to_string(rules_.max_line) + " this dialect accepts");
    }
    write_line_(line);
    ++report_.blocks;
    joints_ = q1;
    if (worst > report_.max_deviation_mm) {
      report_.max_deviation_mm = worst;
      report_.max_deviation_line = segment.line;
    }
  }

  const Machine& machine_;
  const PostOptions& options_;
  DialectRules rules_;
  const std::function<void(const std::string&)>& write_line_;
  std::string file_;
  motion::SegmentBuilder builder_;
  JointVector joints_;
  bool inverse_time_ = false;
  bool ended_ = false;
  PostReport report_;
};

}  // namespace

DialectRules rules_of(Dialect dialect) {
  switch (dialect) {
    case Dialect::linuxcnc:
      return {5, 0};
    case Dialect::mach3:
      return {4, 1024};
    case Dialect::grbl:
      return {3, 80};
  }
  return {};
}

PostReport post_program(const Machine& machine, const std::filesystem::path& program,
                        const gcode::InterpreterOptions& interpreter_options,
                        const PostOptions& options,
                        const std::function<void(const std::string&)>& write_line) {
  if (!(options.tolerance_mm > 0.0)) throw std::invalid_argument("the tolerance must be positive");
  Poster poster(machine, options, write_line, program.string());
  // The program starts where the machine is: axes it never names stay at home.
  gcode::Interpreter interpreter(
      program,
      motion::starting_at(interpreter_options, machine.home().as_vector(), options.origin));
  interpreter.run([&](const gcode::Canon& canon) { poster.on_canon(canon); });
  PostReport report = poster.finish();
  report.warnings = interpreter.warnings();
  return report;
}

}  // namespace pkm::post
