#include "pkm/post/joint_program.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <optional>

#include "pkm/motion/pen_path.hpp"
#include "pkm/motion/segment_builder.hpp"
#include "pkm/post/covering.hpp"
#include "pkm/post/deviation_bound.hpp"
#include "pkm/post/grbl_settings.hpp"
#include "pkm/post/passed_commands.hpp"
#include "pkm/post/span_bound.hpp"

namespace pkm::post {

namespace {

// A joint program moves the joints to computed targets: it cannot stop on contact along the job's
// straight line, and what a job does after a probe depends on where it touched (docs/post.md).
constexpr const char* kProbeRefusal =
    "a probing move (G38.2-G38.5) cannot go into a joint program: the controller would drive the "
    "joints to the probe's end without stopping on contact along the job's line, and the rest of "
    "the job depends on where it touched; run the job on a controller that has the machine's "
    "kinematics (pkm export linuxcnc), or take the probing out of the job";

using motion::Segment;
using motion::SegmentKind;

constexpr int kSampledPoints = 32;  // FK checks per block where the model has no bound
constexpr int kFeedDecimals = 3;    // digits after the point of G93 F, more for very slow blocks

// Whether the coordinates the model controls change along the move (a plotter's Z-only move
// does not move it).
bool moves_controlled(const Segment& segment, geometry::Dof dof) {
  const geometry::Vector6d change = segment.end - segment.start;
  for (int axis = 0; axis < geometry::kPoseSize; ++axis) {
    if (dof.controls(axis) && change[axis] != 0.0) return true;
  }
  if (segment.kind == SegmentKind::arc) {
    return segment.sweep_rad != 0.0 &&
           (dof.controls(segment.first_axis) || dof.controls(segment.second_axis));
  }
  return segment.kind == SegmentKind::blend;
}

// G93 F of a block lasting `duration_s`, rounded down (a smaller F is a longer, slower block) to
// kFeedDecimals digits, or as many more as keep it above zero.
std::string inverse_time_feed(double duration_s) {
  const double exact = 60.0 / duration_s;
  for (int decimals = kFeedDecimals; decimals <= 12; ++decimals) {
    const double scale = std::pow(10.0, decimals);
    const double rounded = std::floor(exact * scale) / scale;
    if (rounded > 0.0) {
      char text[48];
      std::snprintf(text, sizeof text, " F%.*f", decimals, rounded);
      return text;
    }
  }
  throw std::invalid_argument("a block too slow for inverse time");
}

class Poster : private CoveringHost {
 public:
  // `write_line` gets each line with the job line it was written for.
  Poster(const machine::Machine& machine, const PostOptions& options,
         const std::function<void(const std::string&, int)>& write_line, std::string file)
      : machine_(machine),
        options_(options),
        rules_(rules_of(options.dialect)),
        write_line_(write_line),
        file_(std::move(file)),
        builder_(machine.home().as_vector(), options.origin, false),
        bound_(machine, options.tolerance_mm),
        covering_(*this, options.tolerance_mm),
        pen_path_(machine),
        timed_rapids_(options.rapids.value_or(rapids_style_of(options.dialect)) ==
                      RapidsStyle::timed) {
    kinematics::JointVector home;
    const kinematics::Status status = machine_.inverse(machine_.home(), home);
    if (!status.ok())
      throw PostError(file_, 0, "home is not usable: " + machine_.explain(machine_.home(), status));
    joints_ = rounded(home);
    report_.bounded = bound_.available();
    write("G21 G90 G94", 0);
    if (pen()) set_pen(false, 0);  // a plotter starts with its pen up, whatever home's Z
  }

  void on_canon(const gcode::Canon& canon) {
    if (!spans_across(canon)) covering_.finish();
    if (on_machine_command(canon)) return;
    if (const auto passed = passed_command(canon, options_.dialect)) return pass_on(canon, *passed);
    const motion::Moves moves = builder_.take(canon);
    if (canon.kind == gcode::CanonKind::rigid_tap) return rigid_tap(moves);
    for (const Segment& segment : moves) {
      if (segment.kind == SegmentKind::dwell) {
        write(format("G4 P%.3f", segment.dwell_s), segment.line);
        continue;
      }
      if (segment.length() <= 0.0) continue;
      ++report_.moves;
      refuse_past_block_bound(segment);
      move(segment, true);
    }
  }

  PostReport finish() {
    covering_.finish();
    if (!ended_) end_program(0);
    if (const auto warning = pen_path_.warning(); pen() && warning) {
      report_.warnings.push_back(*warning);
    }
    return report_;
  }

 private:
  bool pen() const { return machine_.tool().z == machine::ToolZ::pen; }

  // A rigid tap (G33.1) in joint space: timed moves in and out at the pitch times S, with the
  // spindle reversed for the way out (as G84 does it) where the controller would have
  // reversed it for the synchronised tap; the joints cannot follow the spindle's turns.
  void rigid_tap(const motion::Moves& moves) {
    if (moves.empty() || moves.front().length() <= 0.0) return;
    const int line = moves.front().line;
    ++report_.moves;
    move(moves.front(), false);
    if (!pen()) write(spindle_clockwise_ ? "M4" : "M3", line);
    ++report_.moves;
    move(moves[1], false);
    if (!pen()) write(spindle_clockwise_ ? "M3" : "M4", line);
  }

  // Before a move is covered: the blocks written and the move's estimate past the bound refuse the
  // job here, so an arc of a million turns costs no work (and writes nothing) before it does.
  void refuse_past_block_bound(const Segment& segment) const {
    if (options_.max_blocks <= 0) return;
    const double needed = estimated_blocks(segment, options_.tolerance_mm);
    if (static_cast<double>(report_.blocks) + needed <= static_cast<double>(options_.max_blocks))
      return;
    const bool arc = segment.kind != SegmentKind::line;
    const std::string turns =
        arc ? format(", %.10g turns", std::abs(segment.sweep_rad) / (2.0 * std::numbers::pi)) : "";
    char text[400];
    std::snprintf(text, sizeof text,
                  "this %s (%.10g mm of path%s) needs about %.0f blocks to keep within %g mm; with "
                  "the %ld written before it, the joint program would pass the bound of %ld blocks",
                  arc ? "arc" : "move", segment.length(), turns.c_str(), needed,
                  options_.tolerance_mm, report_.blocks, options_.max_blocks);
    throw BlockBoundError(file_, segment.line, text);
  }

  static std::string format(const char* pattern, double value) {
    char text[160];
    std::snprintf(text, sizeof text, pattern, value);
    return text;
  }

  // Every line goes out here: the dialect's line length is checked on each.
  void write(const std::string& line, int source_line) {
    if (rules_.max_line > 0 && line.size() > rules_.max_line) {
      throw PostError(file_, source_line,
                      "a line of " + std::to_string(line.size()) + " characters exceeds the " +
                          std::to_string(rules_.max_line) + " dialect " +
                          std::string(dialect_name(options_.dialect)) + " accepts: " + line);
    }
    write_line_(line, source_line);
  }

  // Spindle, coolant and the program end; true when the command was one of them. On a machine
  // with a pen channel the pen commands own the tool, so the job's spindle words are dropped.
  bool on_machine_command(const gcode::Canon& canon) {
    using gcode::CanonKind;
    const char* code = nullptr;
    switch (canon.kind) {
      case CanonKind::spindle_speed:
        if (!pen()) write(format("S%.1f", canon.value), canon.line);
        return true;
      case CanonKind::spindle_clockwise:
      case CanonKind::spindle_counterclockwise:
        if (!pen()) write(canon.kind == CanonKind::spindle_clockwise ? "M3" : "M4", canon.line);
        spindle_on_ = true;
        spindle_clockwise_ = canon.kind == CanonKind::spindle_clockwise;
        return true;
      case CanonKind::spindle_stop:
        // The interpreter stops the spindle again at M2: one M5 is enough.
        if (!pen() && spindle_on_ != false) write("M5", canon.line);
        spindle_on_ = false;
        return true;
      case CanonKind::mist_on:
        code = "M7";
        break;
      case CanonKind::flood_on:
        code = "M8";
        break;
      case CanonKind::flood_off:
        code = "M9";
        break;
      case CanonKind::program_end:
        if (!ended_) end_program(canon.line);
        return true;
      default:
        return false;
    }
    write(code, canon.line);
    return true;
  }

  void pass_on(const gcode::Canon& canon, const PassedCommand& passed) {
    if (!passed.refusal.empty()) throw PostError(file_, canon.line, passed.refusal);
    if (!passed.warning.empty()) report_.warnings.push_back({canon.line, passed.warning});
    if (!passed.line.empty()) write(passed.line, canon.line);
  }

  void end_program(int source_line) {
    if (pen() && pen_down_) set_pen(false, source_line);
    write("M2", source_line);
    ended_ = true;
  }

  void set_pen(bool down, int source_line) {
    const machine::ToolChannel& tool = machine_.tool();
    write(down ? tool.down_command : tool.up_command, source_line);
    if (tool.delay_s > 0.0) write(format("G4 P%.3f", tool.delay_s), source_line);
    pen_down_ = down;
  }

  // Whether a command may stand between two moves one block spans: what only sets the state of
  // the next moves (the feed, the plane, units, offsets: their moves carry it), comments, and on
  // a machine with a pen channel the spindle words post leaves out. Everything else post writes
  // or the job means at that point (a dwell, a stop, a tool change, an event, G61) ends the run.
  bool spans_across(const gcode::Canon& canon) const {
    using gcode::CanonKind;
    switch (canon.kind) {
      case CanonKind::feed:
      case CanonKind::arc:
      case CanonKind::set_feed_rate:
      case CanonKind::set_feed_mode:
      case CanonKind::select_plane:
      case CanonKind::use_length_units:
      case CanonKind::comment:
      case CanonKind::tool_length_offset:
      case CanonKind::g5x_offset:
      case CanonKind::g92_offset:
      case CanonKind::xy_rotation:
        return true;
      case CanonKind::spindle_speed:
      case CanonKind::spindle_clockwise:
      case CanonKind::spindle_counterclockwise:
      case CanonKind::spindle_stop:
        return pen();
      default:
        return false;
    }
  }

  // Whether a block may span the move with its neighbours (docs/post.md, "Spanning moves"): a
  // feed move (line or arc) in G64 that keeps the attitude, on a model with a deviation bound.
  bool spannable(const Segment& segment) const {
    if (!options_.span_moves || !bound_.available() || segment.rapid) return false;
    if (builder_.path_mode() != 64) return false;  // G61, G61.1: every vertex exactly
    if (segment.kind == SegmentKind::dwell) return false;
    const geometry::Dof dof = machine_.kinematics().dof();
    for (int axis = 3; axis < geometry::kPoseSize; ++axis) {
      if (dof.controls(axis) && segment.start[axis] != segment.end[axis]) return false;
    }
    return true;
  }

  void move(const Segment& segment, bool may_span) {
    const bool moves = moves_controlled(segment, machine_.kinematics().dof());
    if (moves) {
      kinematics::JointVector end;
      const kinematics::Status status =
          machine_.inverse(geometry::Pose::from_vector(segment.end), end);
      if (!status.ok()) {
        throw PostError(file_, segment.line,
                        "the move leaves the machine's reach " +
                            machine_.explain_path([&](double v) { return segment.at(v); }));
      }
    }
    const std::vector<motion::PenChange> changes =
        pen() ? pen_path_.follow(segment) : std::vector<motion::PenChange>{};
    if (!moves && changes.empty()) return;  // nothing written, nothing that ends a run
    // A run of moves at one feed: a block spanning moves of different feeds would share its
    // time out evenly where the job does not.
    const bool spanned = may_span && changes.empty() && spannable(segment);
    if (!spanned || segment.feed_mm_per_s != run_feed_mm_per_s_) covering_.finish();
    double from = 0.0;
    for (const motion::PenChange& change : changes) {
      if (moves && change.u > from) covering_.add(segment, from, change.u);
      covering_.finish();
      set_pen(change.down, segment.line);
      from = change.u;
    }
    if (moves) covering_.add(segment, from, 1.0);
    if (!spanned) covering_.finish();
    run_feed_mm_per_s_ = segment.feed_mm_per_s;
  }

  // Joint values as the controller will read them: rounded to the dialect's decimals in
  // interface units (mm, deg).
  kinematics::JointVector rounded(const kinematics::JointVector& q) const {
    kinematics::JointVector result = q;
    const double scale = std::pow(10.0, rules_.decimals);
    for (int i = 0; i < q.size(); ++i) {
      const machine::JointSpec& joint = machine_.joints()[static_cast<std::size_t>(i)];
      result[i] = joint.from_interface(std::round(joint.to_interface(q[i]) * scale) / scale);
    }
    return result;
  }

  JointsAt joints_at(const Segment& segment, double u) const override {
    kinematics::JointVector q;
    const kinematics::Status status =
        machine_.inverse(geometry::Pose::from_vector(segment.at(u)), q);
    if (!status.ok()) {
      throw PostError(file_, segment.line,
                      "the move leaves the machine's reach " +
                          machine_.explain_path([&](double v) { return segment.at(v); }));
    }
    return {q, rounded(q)};
  }

  const kinematics::JointVector& written_joints() const override { return joints_; }

  // The bound; for models without one (no spanning there), the largest distance to the
  // programmed point at the same fraction found by forward kinematics at kSampledPoints + 1
  // points (infinity where FK fails).
  double deviation(const Span& span, const BlockEnds& ends) const override {
    if (bound_.available()) return span_deviation_bound(bound_, span, ends, options_.tolerance_mm);
    const Segment& segment = span.first().segment;
    const double u0 = span.start, u1 = span.end;
    double worst = 0.0;
    for (int k = 0; k <= kSampledPoints; ++k) {
      const double lambda = static_cast<double>(k) / kSampledPoints;
      const geometry::Vector6d programmed = segment.at(u0 + (u1 - u0) * lambda);
      geometry::Pose pose = geometry::Pose::from_vector(programmed);  // FK's seed
      const kinematics::JointVector q = ends.written0 + lambda * (ends.written1 - ends.written0);
      if (!machine_.forward(q, pose).ok()) return INFINITY;
      double squared = 0.0;
      for (int axis = 0; axis < 3; ++axis) {
        if (!machine_.kinematics().dof().controls(axis)) continue;
        squared += std::pow(pose.position_mm[axis] - programmed[axis], 2);
      }
      worst = std::max(worst, std::sqrt(squared));
    }
    return worst;
  }

  [[noreturn]] void cannot_keep_within(const Segment& segment) const override {
    throw PostError(file_, segment.line,
                    format("cannot keep within %g mm here: no block, however short, is "
                           "(a singularity, or a tolerance too small for joints rounded to ",
                           options_.tolerance_mm) +
                        std::to_string(rules_.decimals) + " decimals)");
  }

  // The shortest time a block to q1 takes with every joint within its max_velocity (s).
  double joint_limited_s(const kinematics::JointVector& q1) const {
    double duration = 0.0;
    for (int i = 0; i < q1.size(); ++i) {
      duration =
          std::max(duration, std::abs(q1[i] - joints_[i]) /
                                 machine_.joints()[static_cast<std::size_t>(i)].max_velocity);
    }
    return duration;
  }

  // A spindle or laser on, as opposed to a pen the spindle output lifts.
  bool cutting() const { return !pen() && spindle_on_ == true; }

  // A timed rapid kept as G0 for the spindle: warned of once per job line where its blocks, at
  // the joints' top rates, take the tool above max_feed on average.
  void warn_of_fast_rapid(const Span& span, const kinematics::JointVector& q1, int line) {
    const double joints_s = joint_limited_s(q1);
    const double max_feed = machine_.cartesian().max_feed_mm_per_s();
    if (line == fast_rapid_warned_line_ || !(joints_s > 0.0)) return;
    const double tool_mm_per_s = span.length_mm() / joints_s;
    if (tool_mm_per_s <= max_feed * (1.0 + 1e-9)) return;
    fast_rapid_warned_line_ = line;
    char numbers[160];
    std::snprintf(numbers, sizeof numbers,
                  "the tool averages up to %.1f mm/s over a block, above max_feed %.1f mm/s",
                  tool_mm_per_s, max_feed);
    report_.warnings.push_back(
        {line, std::string("a rapid with the spindle on is written as G0 (grbl's laser mode "
                           "switches the laser off in G0 only), where each joint runs at its own "
                           "top rate: ") +
                   numbers +
                   "; stop the spindle (M5) before the rapid, or give --rapids g0 to accept it"});
  }

  void write_block(const Span& span, const kinematics::JointVector& q1,
                   double deviation_mm) override {
    const Segment& segment = span.first().segment;
    const bool kept_for_spindle = segment.rapid && timed_rapids_ && cutting();
    if (kept_for_spindle) warn_of_fast_rapid(span, q1, segment.line);
    const bool as_g0 = segment.rapid && (!timed_rapids_ || kept_for_spindle);
    std::string line = as_g0 ? "G0" : "G1";
    if (!as_g0 && !inverse_time_) {
      line = "G93 " + line;
      inverse_time_ = true;
    }
    for (int i = 0; i < q1.size(); ++i) {
      line += joint_word(machine_.joints()[static_cast<std::size_t>(i)], q1[i], rules_);
    }
    if (!as_g0) {
      // Inverse time: the block takes the programmed path's time at the programmed feed (the
      // sum over the moves it spans; a rapid's at max_feed), or longer where a joint would
      // otherwise exceed its velocity.
      line += inverse_time_feed(std::max(
          span.programmed_s(machine_.cartesian().max_feed_mm_per_s()), joint_limited_s(q1)));
    }
    if (options_.max_blocks > 0 && report_.blocks >= options_.max_blocks) {
      throw BlockBoundError(file_, segment.line,
                            "the joint program would pass the bound of " +
                                std::to_string(options_.max_blocks) + " blocks here");
    }
    write(line, segment.line);
    ++report_.blocks;
    joints_ = q1;
    if (deviation_mm > report_.max_deviation_mm) {
      report_.max_deviation_mm = deviation_mm;
      report_.max_deviation_line = segment.line;
    }
  }

  const machine::Machine& machine_;
  const PostOptions& options_;
  DialectRules rules_;
  const std::function<void(const std::string&, int)>& write_line_;
  std::string file_;
  motion::SegmentBuilder builder_;
  DeviationBound bound_;
  Covering covering_;
  motion::PenPath pen_path_;        // where the pen changes along the job
  double run_feed_mm_per_s_ = 0.0;  // of the moves the open block may span
  kinematics::JointVector joints_;  // as last written
  bool inverse_time_ = false;
  const bool timed_rapids_;  // RapidsStyle::timed
  int fast_rapid_warned_line_ = -1;
  bool ended_ = false;
  bool pen_down_ = false;
  std::optional<bool> spindle_on_;  // unknown until the program says
  bool spindle_clockwise_ = true;   // M3 (or M4) last
  PostReport report_;
};

constexpr Dialect kDialects[] = {Dialect::linuxcnc, Dialect::mach3, Dialect::grbl,
                                 Dialect::grblhal};

}  // namespace

double estimated_blocks(const Segment& segment, double tolerance_mm) {
  double radius_mm = 0.0;
  if (segment.kind == SegmentKind::arc) {
    radius_mm =
        std::hypot(segment.start[segment.first_axis] - segment.centre[segment.first_axis],
                   segment.start[segment.second_axis] - segment.centre[segment.second_axis]);
  } else if (segment.kind == SegmentKind::blend) {
    radius_mm = segment.radius_mm;
  } else {
    return 1.0;
  }
  // A chord over the angle t lies at most r (1 - cos(t / 2)) from its arc.
  const double chord_angle = tolerance_mm >= radius_mm
                                 ? std::numbers::pi
                                 : 2.0 * std::acos(1.0 - tolerance_mm / radius_mm);
  return std::max(1.0, std::ceil(std::abs(segment.sweep_rad) / chord_angle));
}

std::string joint_word(const machine::JointSpec& joint, double value, const DialectRules& rules) {
  char word[48];
  std::snprintf(word, sizeof word, " %c%.*f", joint.axis_letter, rules.decimals,
                joint.to_interface(value));
  return word;
}

std::string comment_safe(Dialect dialect, std::string text) {
  if (dialect == Dialect::grbl || dialect == Dialect::grblhal) return grbl_comment_text(text);
  for (char& c : text) {
    if (c == '(') c = '[';
    if (c == ')') c = ']';
    if (static_cast<unsigned char>(c) < 0x20) c = ' ';  // a line break would end the comment
  }
  return text;
}

std::string comment_line(Dialect dialect, const std::string& before, std::string text,
                         const std::string& after) {
  text = comment_safe(dialect, text);
  const std::size_t width = rules_of(dialect).max_line;
  const std::size_t room = before.size() + after.size() + 2;
  if (width > 0 && room + text.size() > width) {
    text = width > room + 3 ? "..." + text.substr(text.size() - (width - room - 3)) : "";
  }
  return "(" + before + text + after + ")\n";
}

DialectRules rules_of(Dialect dialect) {
  switch (dialect) {
    case Dialect::linuxcnc:
      return {5, 0, "XYZABCUVW"};
    case Dialect::mach3:
      return {4, 1024, "XYZABC"};
    case Dialect::grbl:
      return {3, 80, "XYZ"};
    case Dialect::grblhal:
      return {4, 256, "XYZABCUVW"};
  }
  return {};
}

std::string_view dialect_name(Dialect dialect) {
  switch (dialect) {
    case Dialect::linuxcnc:
      return "linuxcnc";
    case Dialect::mach3:
      return "mach3";
    case Dialect::grbl:
      return "grbl";
    case Dialect::grblhal:
      return "grblhal";
  }
  return "";
}

RapidsStyle rapids_style_of(Dialect dialect) {
  return dialect == Dialect::grbl || dialect == Dialect::grblhal ? RapidsStyle::timed
                                                                 : RapidsStyle::g0;
}

RapidsStyle rapids_style_named(std::string_view name) {
  if (name == "g0") return RapidsStyle::g0;
  if (name == "timed") return RapidsStyle::timed;
  throw std::invalid_argument("unknown rapids style '" + std::string(name) + "' (g0 or timed)");
}

Dialect dialect_named(std::string_view name) {
  for (const Dialect dialect : kDialects) {
    if (dialect_name(dialect) == name) return dialect;
  }
  throw std::invalid_argument("unknown dialect '" + std::string(name) +
                              "' (linuxcnc, mach3, grbl or grblhal)");
}

void check_axis_letters(const machine::Machine& machine, Dialect dialect) {
  const std::string_view accepted = rules_of(dialect).axes;
  std::string refused;
  std::string letters;
  for (const machine::JointSpec& joint : machine.joints()) {
    letters += joint.axis_letter;
    if (accepted.find(joint.axis_letter) == std::string_view::npos) {
      refused +=
          std::string(refused.empty() ? "" : ", ") + "'" + joint.name + "' as " + joint.axis_letter;
    }
  }
  if (refused.empty() && machine.joints().size() <= accepted.size()) return;
  std::string takers;
  for (const Dialect other : kDialects) {
    const std::string_view axes = rules_of(other).axes;
    const bool takes = std::all_of(letters.begin(), letters.end(), [&](char letter) {
      return axes.find(letter) != std::string_view::npos;
    });
    if (takes)
      takers += std::string(takers.empty() ? "" : " or ") + std::string(dialect_name(other));
  }
  std::string spaced;
  for (const char letter : accepted) spaced += std::string(spaced.empty() ? "" : " ") + letter;
  std::string message =
      "dialect " + std::string(dialect_name(dialect)) + " accepts the axes " + spaced + " only; ";
  message += refused.empty() ? "this machine has " + std::to_string(letters.size()) + " joints"
                             : "the machine writes joint " + refused;
  message += takers.empty() ? "" : ": use --dialect " + takers;
  throw std::invalid_argument(message + (refused.empty() ? ""
                                                         : ", or change the joints' axis "
                                                           "letters in the machine file"));
}

PostReport post_program(const machine::Machine& machine, const std::filesystem::path& program,
                        const gcode::InterpreterOptions& interpreter_options,
                        const PostOptions& options,
                        const std::function<void(const std::string&)>& write_line) {
  if (!(options.tolerance_mm > 0.0) || !std::isfinite(options.tolerance_mm)) {
    throw std::invalid_argument("the tolerance must be a positive number of mm");
  }
  if (!options.origin.allFinite()) {
    throw std::invalid_argument("the origin must be finite (mm, deg)");
  }
  check_axis_letters(machine, options.dialect);
  // The controller model reads every line as the sender will stream it.
  std::optional<controller::GrblTimeModel> model;
  const bool grbl_class = options.dialect == Dialect::grbl || options.dialect == Dialect::grblhal;
  if (grbl_class && machine.controller()) model.emplace(controller::grbl_setup_of(machine));
  const std::function<void(const std::string&, int)> write_and_model = [&](const std::string& line,
                                                                           int job_line) {
    if (model) model->add_line(line, job_line);
    write_line(line);
  };
  Poster poster(machine, options, write_and_model, program.string());
  // The program starts where the machine is: axes it never names stay at home.
  gcode::InterpreterOptions job_options =
      motion::starting_at(interpreter_options, machine.home().as_vector(), options.origin);
  job_options.probe_refusal = kProbeRefusal;
  gcode::Interpreter interpreter(program, job_options);
  gcode::LineProgress progress(options.on_line);
  interpreter.run([&](const gcode::Canon& canon) {
    progress.see(canon.line);
    poster.on_canon(canon);
  });
  PostReport report = poster.finish();
  // The interpreter's warnings first, in the job's order; post's own (the pen) after.
  report.warnings.insert(report.warnings.begin(), interpreter.warnings().begin(),
                         interpreter.warnings().end());
  report.files_read = interpreter.files_read();
  if (model) {
    report.controller = model->finish();
    if (auto warning = controller_warning(*machine.controller(), *report.controller)) {
      report.warnings.push_back(*warning);
    }
  }
  return report;
}

std::optional<gcode::Warning> controller_warning(const machine::ControllerSettings& settings,
                                                 const controller::GrblPrediction& prediction) {
  const double run_s = prediction.time_s - prediction.motion_start_s;
  if (prediction.blocks == 0 || run_s <= 1.02 * prediction.unlimited_time_s) return std::nullopt;
  const double mean_length = prediction.path_length / static_cast<double>(prediction.blocks);
  const double cap =
      std::sqrt(2.0 * prediction.mean_acceleration * (settings.planner_blocks - 1) * mean_length);
  char text[700];
  std::snprintf(text, sizeof text,
                "%s's %d-block look-ahead and its %d-baud line slow this program: it takes "
                "%.1f s on the controller instead of %.1f s at its joints' rate and acceleration "
                "limits alone; its %ld blocks average %.4g units, and a run of such blocks goes "
                "no faster than sqrt(2 a %d L) = %.4g units/min; the stretch slowed most (%.1f s "
                "lost) starts at this line; a larger --tolerance gives longer blocks",
                machine::controller_kind_name(settings.kind), settings.planner_blocks,
                settings.baud, run_s, prediction.unlimited_time_s, prediction.blocks, mean_length,
                settings.planner_blocks - 1, cap * 60.0, prediction.slowest_stretch_lost_s);
  return gcode::Warning{prediction.slowest_stretch_tag, text};
}

}  // namespace pkm::post
