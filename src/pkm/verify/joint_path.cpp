#include "pkm/verify/joint_path.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <string_view>

#include "pkm/gcode/machine_commands.hpp"
#include "pkm/verify/block_deviation.hpp"
#include "pkm/verify/job_cursor.hpp"
#include "pkm/verify/joint_words.hpp"

namespace pkm::verify {

namespace {

constexpr int kHeaderLines = 10;           // where tolerance_in_header looks
constexpr double kCoveredWithinMm = 1e-9;  // left of the job by a program that traces it all

std::string fixed_mm(double value) {
  char text[40];
  std::snprintf(text, sizeof text, "%.3f mm", value);
  return text;
}

// The first of the job's machine commands the joint program does not carry in order and in
// place (within `slack_mm` of the job's arc length where the job gives it), or "".
std::string commands_mismatch(const std::vector<PlacedCommand>& job,
                              const std::vector<PlacedCommand>& joints, double slack_mm) {
  const std::size_t common = std::min(job.size(), joints.size());
  for (std::size_t i = 0; i < common; ++i) {
    // A tool change carried out as a pause (post's M6 for grbl) is the job's M6.
    const bool same =
        job[i].text == joints[i].text || (job[i].text == "M6" && joints[i].text == "M0");
    if (!same) {
      return "job line " + std::to_string(job[i].line) + ": " + job[i].text +
             " is not in the joint program, whose line " + std::to_string(joints[i].line) +
             " has " + joints[i].text + " in its place";
    }
    const double from_mm = joints[i].along_mm;
    const double to_mm = std::max(from_mm, joints[i].reached_mm);
    if (job[i].along_mm < from_mm - slack_mm || job[i].along_mm > to_mm + slack_mm) {
      return "job line " + std::to_string(job[i].line) + ": " + job[i].text + " comes at " +
             fixed_mm(job[i].along_mm) + " along the job, the joint program's (line " +
             std::to_string(joints[i].line) + ") at " + fixed_mm(joints[i].along_mm);
    }
  }
  if (job.size() > common) {
    return "job line " + std::to_string(job[common].line) + ": " + job[common].text +
           " is not in the joint program";
  }
  if (joints.size() > common) {
    return "joint program line " + std::to_string(joints[common].line) + ": " +
           joints[common].text + " is not in the job";
  }
  return "";
}

// How far along the job a block may end: twice the block's own length (a path that wiggles within
// the tolerance is longer than the tool's), plus a few tolerances for blocks of no length.
double reach_mm(double block_length_mm, double tolerance_mm) {
  return 2.0 * block_length_mm + 4.0 * tolerance_mm;
}

// What the job asks of the pen over a range: down (1), up (0), or either (-1, the range crosses
// the pen's height, or where the pen starts following the job's Z: motion/pen_path.hpp).
int pen_asked(const machine::ToolChannel& tool, const PieceRange& range) {
  const double from = range.piece->pen_follows_from;
  if (range.u1 <= from) return 0;
  if (range.u0 < from) return -1;
  const bool down0 = tool.pen_down(range.piece->segment.at(range.u0)[2]);
  const bool down1 = tool.pen_down(range.piece->segment.at(range.u1)[2]);
  return down0 == down1 ? int(down0) : -1;
}

class Verifier {
 public:
  Verifier(const machine::Machine& machine, const std::filesystem::path& joints,
           const std::filesystem::path& job, const VerifyOptions& options)
      : machine_(machine),
        tool_(machine.tool()),
        file_(joints.string()),
        options_(options),
        path_(machine, job, options.job_options, options.origin),
        cursor_(path_),
        measure_(machine),
        words_(machine) {
    if (!path_.piece(0)) throw VerifyError(job.string() + ": the job has no moves to compare with");
    if (!machine.inverse(machine.home(), previous_).ok()) throw VerifyError("home is not usable");
    pose_ = machine.home();
    report_.tolerance_mm = options.tolerance_mm;
  }

  // The joint program starts where the machine is: at home. The job's loop bounds hold for it
  // too: a joint program's repeat count can ask for as much work as the job's.
  gcode::InterpreterOptions joint_program_options() const {
    return words_.program_options(previous_, options_.job_options);
  }

  void on_canon(const gcode::Canon& canon) {
    using gcode::CanonKind;
    if (canon.kind == CanonKind::event && tool_.z == machine::ToolZ::pen &&
        (canon.text == tool_.down_command || canon.text == tool_.up_command)) {
      close_pen_stretch();
      const bool down = canon.text == tool_.down_command;
      if (down && !pen_down_) ++pen_downs_;
      pen_down_ = down;
      return;
    }
    if (std::string text = gcode::machine_command_text(canon); compared_command(text)) {
      joint_commands_.push_back(
          {std::move(text), canon.line, cursor_.along_mm(), cursor_.reached_along_mm()});
      return;
    }
    if (canon.kind == CanonKind::arc || canon.kind == CanonKind::probe ||
        canon.kind == CanonKind::rigid_tap) {
      fail(canon.line,
           "joint-space arcs, probes and rigid taps are not verified (only G0 and G1 blocks)");
    }
    if (canon.kind == CanonKind::traverse || canon.kind == CanonKind::feed) on_block(canon);
  }

  VerifyReport finish() {
    close_pen_stretch();
    const JobCursor::Rest rest = cursor_.rest();
    report_.commands_mismatch =
        commands_mismatch(path_.commands(), joint_commands_, options_.tolerance_mm + 1e-6);
    report_.pen_downs = pen_downs_;
    report_.job_pen_downs = path_.pen_downs();
    report_.first_job_pen_down_line = path_.first_pen_down_line();
    report_.job_length_mm = rest.job_length_mm;
    report_.traced_mm = rest.traced_mm;
    // Covered where the job beyond the last block's end lies within the tolerance of it, all of
    // it: then the place reached is the job's end (JobCursor::dwell_end). A job left shorter than
    // the tolerance is not enough: 0.009 mm of it beyond an end 0.005 mm off the path leaves the
    // job's end 0.0103 mm from anything the tool does, at 0.01 mm.
    report_.covered = rest.job_length_mm - rest.traced_mm <= kCoveredWithinMm;
    if (!report_.covered) {
      report_.coverage_stopped_job_line = rest.first_line;
      report_.coverage_stopped_joint_line = last_line_;
    }
    report_.rms_deviation_mm =
        grid_points_ > 0 ? std::sqrt(sum_of_squares_ / static_cast<double>(grid_points_)) : 0.0;
    return report_;
  }

 private:
  [[noreturn]] void fail(int line, const std::string& message) const {
    throw VerifyError(file_ + ":" + std::to_string(line) + ": " + message);
  }

  void check_positions(int line, const kinematics::JointVector& q) {
    for (int i = 0; i < q.size(); ++i) {
      const machine::JointSpec& joint = machine_.joints()[static_cast<std::size_t>(i)];
      if (!(q[i] >= joint.min && q[i] <= joint.max)) {  // NaN is beyond every limit
        const double limit = q[i] < joint.min ? joint.min : joint.max;
        report_.position.add({line, cursor_.line(), i, joint.to_interface(q[i]),
                              joint.to_interface(limit), machine_.explain_joint(i, q[i])});
      }
    }
  }

  // G94's F as LinuxCNC reads it: the length of the block's X Y Z move per minute (mm or inch);
  // without one, of its U V W move; without either, of its A B C move in deg per minute (G20 or
  // not). Joint values as written: mm for linear joints, deg for rotary ones.
  double units_per_minute_duration_s(const gcode::Canon& canon,
                                     const kinematics::JointVector& q) const {
    double squares[3] = {0.0, 0.0, 0.0};  // X Y Z, A B C, U V W
    for (std::size_t i = 0; i < machine_.joints().size(); ++i) {
      const int index = words_.position_index(i);
      if (index < 0) continue;
      const machine::JointSpec& joint = machine_.joints()[i];
      const double step = joint.to_interface(q[int(i)]) - joint.to_interface(previous_[int(i)]);
      squares[index / 3] += step * step;
    }
    const double scale = canon.units == gcode::LengthUnits::inch ? 25.4 : 1.0;
    const double per_minute = units_per_minute(canon);
    const double mm_per_s = per_minute * scale / 60.0;
    if (squares[0] > 0.0) return std::sqrt(squares[0]) / mm_per_s;
    if (squares[2] > 0.0) return std::sqrt(squares[2]) / mm_per_s;
    return std::sqrt(squares[1]) / (per_minute / 60.0);
  }

  // F per minute; fed per revolution (G95, G33), F or the pitch times the spindle's speed, which
  // must turn.
  double units_per_minute(const gcode::Canon& canon) const {
    if (canon.feed_mode != gcode::FeedMode::units_per_revolution) return canon.value;
    if (!(canon.spindle_rpm > 0.0)) {
      fail(canon.line, "a block fed per revolution (G95, G33) with the spindle stopped or at S0");
    }
    return canon.value * canon.spindle_rpm;
  }

  // G93 blocks take 1/F minutes; G94 ones as units_per_minute_duration_s; rapids are the
  // controller's own business.
  void check_speeds(const gcode::Canon& canon, const kinematics::JointVector& q) {
    if (canon.kind != gcode::CanonKind::feed || !(canon.value > 0.0)) return;
    const double duration = canon.feed_mode == gcode::FeedMode::inverse_time
                                ? 60.0 / canon.value
                                : units_per_minute_duration_s(canon, q);
    for (int i = 0; i < q.size() && duration > 0.0; ++i) {
      const machine::JointSpec& joint = machine_.joints()[static_cast<std::size_t>(i)];
      const double speed = std::abs(q[i] - previous_[i]) / duration;
      if (speed > joint.max_velocity * (1.0 + 1e-9)) {
        report_.velocity.add({canon.line, cursor_.line(), i, joint.to_interface(speed),
                              joint.to_interface(joint.max_velocity), ""});
      }
    }
  }

  void on_block(const gcode::Canon& canon) {
    const kinematics::JointVector q = words_.read(canon);
    check_positions(canon.line, q);
    check_speeds(canon, q);
    if (!measure_.sample_grid(previous_, q, pose_)) {
      fail(canon.line, "no tool pose for these joints (forward kinematics fails along the block)");
    }
    // Beyond twice the block's length, as far as the job stays near the block: a path that
    // wiggles within the tolerance is far longer than the block that traces it.
    const double inside_until_mm =
        cursor_.inside_box_until_mm(measure_.grid_box(2.0 * options_.tolerance_mm));
    const JobPlace end = cursor_.find_end(
        measure_.end_point(), reach_mm(measure_.grid_length_mm(), options_.tolerance_mm),
        0.25 * options_.tolerance_mm, inside_until_mm);
    cursor_.stretch_to(end, stretch_);
    BlockDeviation deviation;
    if (!measure_.measure(stretch_, options_.tolerance_mm, deviation)) {
      fail(canon.line, "no tool pose for these joints (forward kinematics fails along the block)");
    }
    record(canon.line, deviation);
    if (options_.on_block) {
      options_.on_block({canon.line, deviation.job_line, measure_.end_pose(), q, deviation.max_mm});
    }
    check_pen(canon.line);
    cursor_.advance(end, reached_after(end));
    previous_ = q;
    pose_ = measure_.end_pose();
    last_line_ = canon.line;
    ++report_.blocks;
  }

  // How far the job is traced once the block ends at `end`. A tool standing at the block's end is
  // within the tolerance of all the job beyond `end` that stays within the tolerance of that
  // point (the job turning back on itself there, a job going back and forth by 1 um): it is
  // traced too. Where that falls short of what the blocks before reached and the whole block is
  // within the tolerance of the job's point there, the block may stand for that point alone, and
  // the job beyond it is traced as far as it stays within the tolerance of the block's end.
  JobPlace reached_after(const JobPlace& end) {
    const double tolerance = options_.tolerance_mm;
    const JobPlace reached = cursor_.dwell_end(end, measure_.end_point(), tolerance);
    if (!reached.before(cursor_.reached())) return reached;
    cursor_.point_reached(point_stretch_);
    BlockDeviation at_point;
    if (point_stretch_.empty() || !measure_.measure(point_stretch_, tolerance, at_point) ||
        at_point.max_mm > tolerance) {
      return reached;
    }
    return cursor_.dwell_end(cursor_.reached(), measure_.end_point(), tolerance);
  }

  void record(int line, const BlockDeviation& deviation) {
    sum_of_squares_ += deviation.sum_of_squares_mm2;
    grid_points_ += deviation.grid_points;
    if (deviation.max_mm > report_.max_deviation_mm) {
      report_.max_deviation_mm = deviation.max_mm;
      report_.max_deviation_joint_line = line;
      report_.max_deviation_job_line = deviation.job_line;
    }
    if (deviation.max_mm > options_.tolerance_mm) {
      report_.deviation.add(
          {line, deviation.job_line, -1, deviation.max_mm, options_.tolerance_mm, ""});
    }
  }

  // A stretch drawn with the pen where the job lifts it, or travelled with it up where the job
  // draws: one violation per stretch of consecutive blocks, its length the value.
  void check_pen(int line) {
    if (tool_.z != machine::ToolZ::pen) return;
    bool wrong = false;
    double length_mm = 0.0;
    int job_line = 0;
    for (const PieceRange& range : stretch_) {
      const int asked = pen_asked(tool_, range);
      if (range.u1 <= range.u0 || asked < 0 || asked == int(pen_down_)) continue;
      if (!wrong) job_line = range.piece->line();
      wrong = true;
      length_mm += (range.u1 - range.u0) * range.piece->length_mm;
    }
    if (wrong && pen_stretch_open_) {
      pen_stretch_.value += length_mm;
      return;
    }
    close_pen_stretch();
    if (!wrong) return;
    pen_stretch_open_ = true;
    pen_stretch_ = {
        line, job_line,
        -1,   length_mm,
        0.0,  pen_down_ ? "pen down where the job lifts it" : "pen up where the job draws"};
  }

  // A stretch shorter than the tolerance is within what the position may stray: where a block
  // ends a hair before a pen change, the next block carries the hair.
  void close_pen_stretch() {
    if (pen_stretch_open_ && pen_stretch_.value > options_.tolerance_mm) {
      report_.pen.add(pen_stretch_);
    }
    pen_stretch_open_ = false;
  }

  const machine::Machine& machine_;
  const machine::ToolChannel& tool_;
  std::string file_;
  const VerifyOptions& options_;
  JobPath path_;
  JobCursor cursor_;
  BlockMeasure measure_;
  JointWords words_;
  std::vector<PieceRange> stretch_;
  std::vector<PieceRange> point_stretch_;
  kinematics::JointVector previous_;
  geometry::Pose pose_;
  bool pen_down_ = false;  // a plotter starts with its pen up
  long pen_downs_ = 0;
  bool pen_stretch_open_ = false;
  Violation pen_stretch_;
  int last_line_ = 0;
  std::vector<PlacedCommand> joint_commands_;
  double sum_of_squares_ = 0.0;
  long grid_points_ = 0;
  VerifyReport report_;
};

}  // namespace

void ViolationSummary::add(const Violation& violation) {
  ++count;
  if (first.size() < kFirst) first.push_back(violation);
  if (count == 1 ||
      std::abs(violation.value - violation.limit) > std::abs(worst.value - worst.limit)) {
    worst = violation;
  }
}

VerifyReport verify_joint_program(const machine::Machine& machine,
                                  const std::filesystem::path& joints,
                                  const std::filesystem::path& job, const VerifyOptions& options) {
  if (!(options.tolerance_mm > 0.0) || !std::isfinite(options.tolerance_mm)) {
    throw VerifyError("the tolerance must be a positive number of mm");
  }
  Verifier verifier(machine, joints, job, options);
  gcode::LineProgress progress(options.on_line);
  gcode::Interpreter(joints, verifier.joint_program_options()).run([&](const gcode::Canon& canon) {
    progress.see(canon.line);
    verifier.on_canon(canon);
  });
  return verifier.finish();
}

std::optional<double> tolerance_in_header(const std::filesystem::path& joints) {
  std::ifstream in(joints);
  if (!in) {  // said here, before "no tolerance" could be blamed on the header
    throw VerifyError(joints.string() + ": cannot open (" + std::strerror(errno) + ")");
  }
  std::string line;
  for (int n = 1; n <= kHeaderLines && std::getline(in, line); ++n) {
    const std::size_t at = line.find("(tolerance ");
    if (at == std::string::npos) continue;
    const char* text = line.c_str() + at + 11;
    char* end = nullptr;
    const double value = std::strtod(text, &end);
    if (end == text || !std::isfinite(value) || !(value > 0.0)) {
      throw VerifyError(joints.string() + ":" + std::to_string(n) +
                        ": the header's tolerance is not a positive number of mm");
    }
    return value;
  }
  return std::nullopt;
}

}  // namespace pkm::verify
