// Joint-space G-code for controllers without kinematics (Mach3, grbl, grblHAL, LinuxCNC with
// trivkins): axis words are joint positions, and the programmed path is covered adaptively by
// joint-linear blocks, each move from its start to its end and runs of short feed moves by blocks
// spanning several (covering.hpp), so that the tool tip of a controller that interpolates the
// joints linearly stays within a tolerance of it, by a bound on the deviation
// (deviation_bound.hpp, span_bound.hpp). Machines with a pen channel get the pen commands where
// the program's Z crosses the pen height.
#pragma once

#include <filesystem>
#include <functional>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "pkm/controller/grbl_planner.hpp"
#include "pkm/gcode/interpreter.hpp"
#include "pkm/machine/machine.hpp"
#include "pkm/motion/segment.hpp"

namespace pkm::post {

enum class Dialect { linuxcnc, mach3, grbl, grblhal };

// Number format, line length and axis letters of each controller.
struct DialectRules {
  int decimals = 5;          // digits after the point of joint values
  std::size_t max_line = 0;  // longest line accepted (0: no limit)
  std::string_view axes;     // the axis letters it accepts
};
DialectRules rules_of(Dialect dialect);

// How post writes a rapid. `g0`: as the controller's G0, which runs every joint at its own top
// rate (the tool may pass [cartesian] max_feed: each joint's limit is all a joint-space controller
// knows). `timed`: as an inverse-time G1 lasting the rapid's time at max_feed (longer where a
// joint's max_velocity needs it), the speed pkm plan gives it; a rapid with a spindle or laser on
// stays G0 (grbl's laser mode switches the laser off in G0 only) and is warned of.
enum class RapidsStyle { g0, timed };
// timed for grbl and grblHAL (a plotter's pen-up travel would otherwise outrun its tool limits,
// 3-32 % faster than planned on the example drawings), g0 for LinuxCNC and Mach3 (as before).
RapidsStyle rapids_style_of(Dialect dialect);
// The style of a name (g0, timed); throws std::invalid_argument.
RapidsStyle rapids_style_named(std::string_view name);
std::string_view dialect_name(Dialect dialect);
// The dialect of a name (linuxcnc, mach3, grbl, grblhal); throws std::invalid_argument.
Dialect dialect_named(std::string_view name);

// " X123.45678": a joint's axis word for `value` (mm or rad inside), written in mm or deg with
// the dialect's decimals.
std::string joint_word(const machine::JointSpec& joint, double value, const DialectRules& rules);

// Text for inside a G-code comment of `dialect`: parentheses would end or nest it, a line break
// end it; for grbl and grblHAL also ? ! ~ and bytes above 0x7F, which they act on even inside a
// comment (grbl_comment_text).
std::string comment_safe(Dialect dialect, std::string text);
// A comment line "(before text after)\n" within the dialect's longest line: `text` made safe and
// cut at its start, where a path or a name says least, marked by "...".
std::string comment_line(Dialect dialect, const std::string& before, std::string text,
                         const std::string& after);

// Throws std::invalid_argument, naming the letters and the dialects that take them, when the
// machine's joints use axis letters the dialect does not accept or more joints than it has axes.
void check_axis_letters(const machine::Machine& machine, Dialect dialect);

// The most blocks pkm post and pkmkit.post write unless told otherwise: 55 times the largest real
// job's (CAMotics' la_peinture raster, 181,694 blocks; docs/real-jobs.md), some 400 MB of
// LinuxCNC program. A job past it is most likely an arc of a million turns or a wrong tolerance.
constexpr long kDefaultMaxBlocks = 10'000'000;

struct PostOptions {
  double tolerance_mm = 0.01;
  Dialect dialect = Dialect::linuxcnc;
  geometry::Vector6d origin =
      geometry::Vector6d::Zero();  // where the program's X0 Y0 Z0 sits (mm, rad)
  // Called with the program's line being posted, once per change of line: for progress.
  std::function<void(int line)> on_line;
  // Let one block span consecutive feed moves where it keeps within the tolerance of all of them
  // (docs/post.md, "Spanning moves"); false: every move covered on its own.
  bool span_moves = true;
  // Refuse (BlockBoundError) a job that needs more motion blocks than this; 0: no bound.
  long max_blocks = 0;
  // How rapids (G0) are written (docs/post.md, "Rapids"); unset: the dialect's default,
  // rapids_style_of.
  std::optional<RapidsStyle> rapids;
};

struct PostReport {
  long blocks = 0;  // motion blocks written
  long moves = 0;   // programmed moves
  // An upper bound on the tool tip's distance from the programmed path over every written block
  // (joint rounding included); where the model has no such bound (formula machines), the largest
  // deviation found by forward kinematics at 33 points per block, and `bounded` is false.
  double max_deviation_mm = 0.0;
  bool bounded = true;
  int max_deviation_line = 0;  // source line of the move where it peaks
  std::vector<gcode::Warning> warnings;
  // The job and the subroutine files it called: what the joint program must not be written over.
  std::vector<std::filesystem::path> files_read;
  // With a [controller] table and the dialect grbl or grblhal: how long the controller takes to
  // run the program (controller/grbl_planner.hpp), and the warning where its look-ahead or its
  // serial line slow it (docs/grbl.md, "How post chooses blocks").
  std::optional<controller::GrblPrediction> controller;
};

// The warning, with numbers, where the controller's look-ahead or serial line make the program
// take over 2 % longer than its rate and acceleration limits alone, at the job line where the
// stretch they slow most starts; nothing otherwise.
std::optional<gcode::Warning> controller_warning(const machine::ControllerSettings& settings,
                                                 const controller::GrblPrediction& prediction);

class PostError : public std::runtime_error {
 public:
  PostError(const std::string& file, int line, const std::string& message)
      : std::runtime_error(file + ":" + std::to_string(line) + ": " + message) {}
};

// A job past PostOptions::max_blocks, refused at the move that would pass it: before that move's
// blocks where its estimate (estimated_blocks) already does, else at the block that does.
class BlockBoundError : public PostError {
 public:
  using PostError::PostError;
};

// The fewest blocks whose chords keep within `tolerance_mm` of the move in the tool tip's space:
// an arc's or a blend's sweep over the angle whose chord's sagitta is the tolerance, 1 for a
// line. Post's estimate of a move's blocks before it covers the move (a double: an arc of 1e15
// turns has no long).
double estimated_blocks(const motion::Segment& segment, double tolerance_mm);

// Writes the body of the joint program (every line through `write_line`, without a header).
PostReport post_program(const machine::Machine& machine, const std::filesystem::path& program,
                        const gcode::InterpreterOptions& interpreter_options,
                        const PostOptions& options,
                        const std::function<void(const std::string&)>& write_line);

}  // namespace pkm::post
