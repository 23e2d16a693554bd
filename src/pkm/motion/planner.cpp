#include "pkm/motion/planner.hpp"

#include <cmath>

#include "pkm/motion/feed_limits.hpp"
#include "pkm/motion/look_ahead.hpp"
#include "pkm/motion/pen_path.hpp"
#include "pkm/motion/plan_sampling.hpp"
#include "pkm/motion/segment.hpp"
#include "pkm/motion/segment_builder.hpp"

namespace pkm::motion {

namespace {

// One G-code program planned: its moves in order, through the feed limits and look-ahead, sampled
// (plan_sampling.hpp); dwells and the pen's changes stop the motion and take their time.
class Planner {
 public:
  Planner(const machine::Machine& machine, const PlanOptions& options, SampleSink& sink,
          std::string file)
      : machine_(machine),
        file_(std::move(file)),
        builder_((options.start ? *options.start : machine.home()).as_vector(), options.origin,
                 options.great_circle_attitude),
        pen_(machine.tool().z == machine::ToolZ::pen),
        pen_path_(machine),
        limits_(machine, options, file_, report_),
        look_ahead_(limits_, builder_),
        sampler_(machine, options, sink, file_, report_),
        period_s_(options.period_s) {
    builder_.set_z_free(!machine.kinematics().dof().controls(static_cast<int>(geometry::Axis::z)));
    builder_.set_file(file_);
    pose_ = builder_.pose();
    const int joints = static_cast<int>(machine.joints().size());
    report_.joints.resize(static_cast<std::size_t>(joints));
    kinematics::JointVector start_joints;
    const kinematics::Status status =
        machine_.inverse(geometry::Pose::from_vector(pose_), start_joints);
    if (!status.ok()) {
      throw PlanError(file_, 0,
                      "the start pose is not usable: " +
                          machine_.explain(geometry::Pose::from_vector(pose_), status));
    }
    require_numbers(machine_, file_, pose_, start_joints, 0, "at the start pose");
    for (int i = 0; i < joints; ++i) {
      report_.joints[static_cast<std::size_t>(i)].min = start_joints[i];
      report_.joints[static_cast<std::size_t>(i)].max = start_joints[i];
    }
    sampler_.emit(0.0, 0, pose_);  // t = 0: where the machine starts
  }

  void on_canon(const gcode::Canon& canon) {
    for (const Segment& segment : builder_.take(canon)) {
      if (segment.kind == SegmentKind::dwell) {
        flush(true);
        entry_speed_ = 0.0;
        run_dwell(segment);
      } else if (pen_) {
        add_with_pen(segment);
      } else {
        add(segment);
      }
    }
  }

  PlanReport finish() {
    flush(true);
    const double time = sampler_.time_s();
    if (!std::isfinite(time)) {
      throw PlanError(file_, last_line_,
                      "the job would take forever: check the machine's feeds and accelerations");
    }
    // The last sample lands exactly on the end of the program (a sum of many phases may pass a
    // multiple of the period by its rounding: that sample is the end).
    if (sampler_.last_sample_time_s() < time - 1e-9 * period_s_) {
      sampler_.emit(time, last_line_, pose_);
    }
    report_.duration_s = time;
    if (const auto warning = pen_path_.warning(); pen_ && warning) {
      report_.warnings.push_back(*warning);
    }
    return report_;
  }

 private:
  void add(const Segment& segment) {
    last_line_ = segment.line;
    const double length = segment.length();
    if (length <= 0.0) {
      pose_ = segment.end;  // a move to where the tool is: nothing to plan
      return;
    }
    const bool full = look_ahead_.add(limits_.piece(segment, length));
    pose_ = segment.end;
    if (full) flush(false);
  }

  // Plans the speeds of the pieces held and samples them: all, or all but those look-ahead keeps.
  void flush(bool all) {
    look_ahead_.release(all, entry_speed_, [&](const Piece& piece) {
      if (piece.grid.ready) limits_.report_grid_limits(piece);  // once, as the piece is final
      sampler_.run_piece(piece);
    });
  }

  void run_dwell(const Segment& segment) {
    last_line_ = segment.line;
    sampler_.sample_until(sampler_.time_s() + segment.dwell_s, segment.line,
                          [&](double) { return segment.start; });
  }

  // A move on a machine with a pen channel: wherever the pen changes along it (pen_path.hpp)
  // the machine stops, the pen goes down or up (samples carry the new state from then on) and
  // the pen's delay passes; the move runs on from there.
  void add_with_pen(const Segment& segment) {
    double from = 0.0;
    for (const PenChange& change : pen_path_.follow(segment)) {
      if (change.u > from) add(segment.part(from, change.u));
      flush(true);
      entry_speed_ = 0.0;
      sampler_.set_pen_down(change.down);
      ++report_.pen_changes;
      last_line_ = segment.line;
      const geometry::Vector6d here = pose_;
      sampler_.sample_until(sampler_.time_s() + machine_.tool().delay_s, segment.line,
                            [&](double) { return here; });
      from = change.u;
    }
    add(from > 0.0 ? segment.part(from, 1.0) : segment);
  }

  const machine::Machine& machine_;
  std::string file_;        // before the parts below, which keep a reference to it
  SegmentBuilder builder_;  // before pose_: the constructor takes the start from it
  bool pen_ = false;        // the machine has a pen channel
  PenPath pen_path_;        // where the pen changes
  PlanReport report_;       // before the parts below, which fill it in
  FeedLimits limits_;
  LookAhead look_ahead_;
  Sampler sampler_;
  geometry::Vector6d pose_ = geometry::Vector6d::Zero();
  double entry_speed_ = 0.0;  // the speed the first piece look-ahead holds is entered at
  double period_s_ = 0.0;
  int last_line_ = 0;
};

}  // namespace

PlanReport plan_program(const machine::Machine& machine, const std::filesystem::path& program,
                        const gcode::InterpreterOptions& interpreter_options,
                        const PlanOptions& options, SampleSink& sink) {
  if (!(options.period_s > 0.0)) throw std::invalid_argument("the period must be positive");
  Planner planner(machine, options, sink, program.string());
  // The program starts where the machine is: axes it never names stay at the start pose.
  gcode::Interpreter interpreter(
      program,
      starting_at(interpreter_options,
                  (options.start ? *options.start : machine.home()).as_vector(), options.origin));
  gcode::LineProgress progress(options.on_line);
  interpreter.run([&](const gcode::Canon& canon) {
    progress.see(canon.line);
    planner.on_canon(canon);
  });
  PlanReport report = planner.finish();
  // The interpreter's warnings first, in the job's order; the planner's own (the pen) after.
  report.warnings.insert(report.warnings.begin(), interpreter.warnings().begin(),
                         interpreter.warnings().end());
  return report;
}

}  // namespace pkm::motion
