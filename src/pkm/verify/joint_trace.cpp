#include "pkm/verify/joint_trace.hpp"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>

#include "pkm/gcode/block.hpp"
#include "pkm/verify/job_path.hpp"
#include "pkm/verify/joint_words.hpp"

namespace pkm::verify {

namespace {

constexpr std::string_view kAxisLetters = "XYZABCUVW";
// A block's tool path is sampled at least kMinIntervals times (verify's grid), and at most
// kSpacingMm apart up to kMaxIntervals: a 16-chord polyline of a 250 mm plotter stroke is short
// of its length by 1.6 um, at 1 mm spacing by 7 nm.
constexpr int kMinIntervals = 16;
constexpr double kSpacingMm = 1.0;
constexpr double kMaxIntervals = 4096.0;

std::string trimmed(const std::string& line) {
  const std::size_t first = line.find_first_not_of(" \t");
  if (first == std::string::npos) return "";
  const std::size_t last = line.find_last_not_of(" \t");
  return line.substr(first, last - first + 1);
}

// The column (from 1) of the first '#' outside comments, 0 when there is none.
int parameter_column(const std::string& line) {
  bool in_comment = false;
  for (std::size_t i = 0; i < line.size(); ++i) {
    if (line[i] == ';' && !in_comment) return 0;
    if (line[i] == '(') in_comment = true;
    if (line[i] == ')') in_comment = false;
    if (line[i] == '#' && !in_comment) return static_cast<int>(i) + 1;
  }
  return 0;
}

// The words of a joint program a controller without kinematics, or this machine, does not have,
// each refused at its column before anything is drawn. Lines the reader itself refuses are left
// to the interpreter, which says why at the same place.
class WordCheck {
 public:
  WordCheck(const machine::Machine& machine, const std::string& file, const JointDialect& dialect)
      : machine_(machine), file_(file), dialect_(dialect) {
    const machine::ToolChannel& tool = machine.tool();
    if (tool.z == machine::ToolZ::pen) events_ = {tool.down_command, tool.up_command};
    for (const machine::JointSpec& joint : machine.joints()) {
      if (!joints_text_.empty()) joints_text_ += ", ";
      joints_text_ += joint.name + " " + joint.axis_letter;
    }
  }

  void check(const std::string& line, int number) {
    if (dialect_.max_line > 0 && line.size() > dialect_.max_line) {
      fail(number, static_cast<int>(dialect_.max_line) + 1,
           "a line of " + std::to_string(line.size()) + " characters: " + dialect_.name +
               " reads at most " + std::to_string(dialect_.max_line));
    }
    const std::string text = trimmed(line);
    if (std::find(events_.begin(), events_.end(), text) != events_.end()) return;
    if (!dialect_.programming) {
      if (const int column = parameter_column(line); column > 0) {
        fail(number, column, dialect_.name + " has no #parameters");
      }
    }
    try {
      gcode::read_block(line, parameters_, block_);
    } catch (...) {  // the interpreter refuses it, located, in its own words
      return;
    }
    if (!dialect_.programming && block_.o_word) {
      fail(number, block_.o_word->column, dialect_.name + " has no O-words");
    }
    check_axes(number);
    check_codes(number);
  }

 private:
  [[noreturn]] void fail(int line, int column, const std::string& message) const {
    throw TraceError(file_ + ":" + std::to_string(line) + ":" + std::to_string(column) + ": " +
                     message);
  }

  void check_axes(int line) const {
    for (const char letter : kAxisLetters) {
      const char lower = static_cast<char>(std::tolower(static_cast<unsigned char>(letter)));
      if (!block_.has(lower)) continue;
      const int column = block_.word(lower)->column;
      const bool joint =
          std::any_of(machine_.joints().begin(), machine_.joints().end(),
                      [&](const machine::JointSpec& j) { return j.axis_letter == letter; });
      if (!joint) {
        fail(line, column,
             std::string(1, letter) + " word: no joint of " + machine_.name() + " is on " + letter +
                 " (its joints: " + joints_text_ +
                 "): is this the Cartesian job rather than its joint program?");
      }
      if (dialect_.axes.find(letter) == std::string_view::npos) {
        fail(line, column,
             std::string(1, letter) + " word: " + dialect_.name + " has no " + letter +
                 " axis (it takes " + std::string(dialect_.axes) + ")");
      }
    }
  }

  void check_codes(int line) const {
    for (const gcode::Code& code : block_.g_codes) {
      const int g = code.tenths;
      if (g == 20 || g == 30) {
        fail(line, code.column,
             "G" + std::to_string(g / 10) +
                 ": an arc of joint values is not drawn (a controller without kinematics would "
                 "turn the joints along it; pkm post writes G0 and G1 only)");
      }
      if ((g >= 382 && g <= 385) || g == 330 || g == 331 || g == 760) {
        fail(line, code.column,
             "G" + std::to_string(g / 10) + "." + std::to_string(g % 10) +
                 ": probing, threading and tapping in joint space are not drawn");
      }
    }
  }

  const machine::Machine& machine_;
  std::string file_;
  const JointDialect& dialect_;
  std::vector<std::string> events_;
  std::string joints_text_;
  gcode::Parameters parameters_;
  gcode::Block block_;
};

void check_words(const machine::Machine& machine, const std::filesystem::path& path,
                 const JointDialect& dialect) {
  std::ifstream in(path);
  if (!in) {
    throw TraceError(path.string() + ": cannot open (" + std::strerror(errno) + ")");
  }
  WordCheck check(machine, path.string(), dialect);
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    check.check(line, number);
  }
}

class Tracer {
 public:
  Tracer(const machine::Machine& machine, const std::filesystem::path& file,
         const TraceOptions& options)
      : machine_(machine),
        file_(file.string()),
        options_(options),
        words_(machine),
        mask_(position_mask(machine)) {
    if (!machine.inverse(machine.home(), previous_).ok()) throw TraceError("home is not usable");
    pose_ = machine.home();
    report_.has_pen = machine.tool().z == machine::ToolZ::pen;
    for (int i = 0; i < previous_.size(); ++i) {
      report_.joints.push_back({previous_[i], previous_[i], 0, 0});
    }
    emit({0, 0.0, pose_, previous_, false, true});
  }

  gcode::InterpreterOptions program_options() const {
    return words_.program_options(previous_, options_.bounds);
  }

  void on_canon(const gcode::Canon& canon) {
    using gcode::CanonKind;
    const machine::ToolChannel& tool = machine_.tool();
    if (canon.kind == CanonKind::event && report_.has_pen &&
        (canon.text == tool.down_command || canon.text == tool.up_command)) {
      const bool down = canon.text == tool.down_command;
      if (down && !pen_down_) ++report_.pen_downs;
      pen_down_ = down;
      return;
    }
    if (canon.kind == CanonKind::arc || canon.kind == CanonKind::probe ||
        canon.kind == CanonKind::rigid_tap) {
      fail(canon.line, "joint-space arcs, probes and rigid taps are not drawn (G0 and G1 only)");
    }
    if (canon.kind == CanonKind::traverse || canon.kind == CanonKind::feed) on_block(canon);
  }

  TraceReport finish() { return report_; }

 private:
  [[noreturn]] void fail(int line, const std::string& message) const {
    throw TraceError(file_ + ":" + std::to_string(line) + ": " + message);
  }

  void emit(const TracePoint& point) const {
    if (options_.on_point) options_.on_point(point);
  }

  std::string joints_text(const kinematics::JointVector& q) const {
    std::string text;
    for (int i = 0; i < q.size(); ++i) {
      const machine::JointSpec& joint = machine_.joints()[static_cast<std::size_t>(i)];
      text += (i > 0 ? ", " : "") + joint.name + " " + machine_.joint_value_text(i, q[i]);
    }
    return text;
  }

  void check_joints(int line, const kinematics::JointVector& q) {
    for (int i = 0; i < q.size(); ++i) {
      const machine::JointSpec& joint = machine_.joints()[static_cast<std::size_t>(i)];
      JointRange& range = report_.joints[static_cast<std::size_t>(i)];
      if (q[i] < range.low) range = {q[i], range.high, line, range.high_line};
      if (q[i] > range.high) range = {range.low, q[i], range.low_line, line};
      if (!(q[i] >= joint.min && q[i] <= joint.max)) {  // NaN is beyond every limit
        const double limit = q[i] < joint.min ? joint.min : joint.max;
        report_.position.add({line, 0, i, joint.to_interface(q[i]), joint.to_interface(limit),
                              machine_.explain_joint(i, q[i])});
      }
    }
  }

  void extend_drawing(const Eigen::Vector3d& point) {
    const Eigen::Vector2d xy = point.head<2>();
    report_.drawn_min =
        report_.drawn_min.array().isNaN().any() ? xy : report_.drawn_min.cwiseMin(xy);
    report_.drawn_max =
        report_.drawn_max.array().isNaN().any() ? xy : report_.drawn_max.cwiseMax(xy);
  }

  // Forward kinematics at `intervals` + 1 evenly spaced points of the joints' straight line from
  // previous_ to q, each seeded with the one before (kept in samples_).
  bool sample_block(const kinematics::JointVector& q, int intervals) {
    samples_.assign(1, pose_);
    for (int k = 1; k <= intervals; ++k) {
      geometry::Pose pose = samples_.back();
      const kinematics::JointVector at =
          previous_ + (static_cast<double>(k) / intervals) * (q - previous_);
      if (!machine_.kinematics().forward(at, pose).ok() || !kinematics::all_finite(pose))
        return false;
      samples_.push_back(pose);
    }
    return true;
  }

  double planar_distance(const geometry::Pose& a, const geometry::Pose& b) const {
    return (b.position_mm - a.position_mm).cwiseProduct(mask_).norm();
  }

  // Evenly spaced samples at most kSpacingMm apart along the tool's path (at least kMinIntervals
  // per block): a metre-long rapid of a plotter bends visibly, and its length with it.
  void sample(int line, const kinematics::JointVector& q) {
    bool sampled = sample_block(q, kMinIntervals);
    if (sampled) {
      double length = 0.0;
      for (std::size_t k = 1; k < samples_.size(); ++k) {
        length += planar_distance(samples_[k - 1], samples_[k]);
      }
      const int intervals =
          static_cast<int>(std::min(std::ceil(length / kSpacingMm), kMaxIntervals));
      if (intervals > kMinIntervals) sampled = sample_block(q, intervals);
    }
    if (!sampled) {
      fail(line, "no tool pose along the block from " + joints_text(previous_) + " to " +
                     joints_text(q) + ": the tool cannot be where these joints put it");
    }
  }

  void on_block(const gcode::Canon& canon) {
    const kinematics::JointVector q = words_.read(canon);
    check_joints(canon.line, q);
    sample(canon.line, q);
    const bool rapid = canon.kind == gcode::CanonKind::traverse;
    const bool drawn = report_.has_pen ? pen_down_ : !rapid;
    if (drawn) extend_drawing(pose_.position_mm);
    const int intervals = static_cast<int>(samples_.size()) - 1;
    double length = 0.0;
    for (int k = 1; k <= intervals; ++k) {
      const geometry::Pose& pose = samples_[static_cast<std::size_t>(k)];
      const double step = planar_distance(samples_[static_cast<std::size_t>(k - 1)], pose);
      length += step;
      along_mm_ += step;
      if (drawn) extend_drawing(pose.position_mm);
      const double lambda = static_cast<double>(k) / intervals;
      emit({canon.line, along_mm_, pose, previous_ + lambda * (q - previous_), drawn,
            k == intervals});
    }
    (drawn ? report_.drawn_mm : report_.travel_mm) += length;
    if (rapid) report_.rapid_mm += length;
    previous_ = q;
    pose_ = samples_.back();
    ++report_.blocks;
  }

  const machine::Machine& machine_;
  std::string file_;
  const TraceOptions& options_;
  JointWords words_;
  std::vector<geometry::Pose> samples_;
  Eigen::Vector3d mask_;
  kinematics::JointVector previous_;
  geometry::Pose pose_;
  bool pen_down_ = false;  // a plotter starts with its pen up
  double along_mm_ = 0.0;
  TraceReport report_;
};

}  // namespace

TraceReport trace_joint_program(const machine::Machine& machine,
                                const std::filesystem::path& joints, const TraceOptions& options) {
  check_words(machine, joints, options.dialect);
  Tracer tracer(machine, joints, options);
  gcode::LineProgress progress(options.on_line);
  gcode::Interpreter(joints, tracer.program_options()).run([&](const gcode::Canon& canon) {
    progress.see(canon.line);
    tracer.on_canon(canon);
  });
  return tracer.finish();
}

}  // namespace pkm::verify
