// The calibration pattern of tape-measure calibration: numbered crosses spread over what a
// machine reaches, as a G-code program to draw them and as pattern.json (the marks' nominal pen
// positions), which `pkm calibrate fit --pattern` reads back.
#pragma once

#include <Eigen/Core>
#include <array>
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "pkm/machine/machine.hpp"

namespace pkm::calibration {

struct PatternMark {
  int id = 0;                                             // the number drawn beside it, 1..
  Eigen::Vector2d position_mm = Eigen::Vector2d::Zero();  // nominal pen position x, y
  std::string location;  // "pattern.json:12:7" of its entry, for errors; empty when made here
};

// An error in pattern.json, located as file:line:column.
class PatternFileError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// {"marks": [{"id": 1, "x": ..., "y": ...}, ...]}: ids positive whole numbers, each once; x, y
// finite numbers of at most 1e6 mm in size; no other keys.
std::vector<PatternMark> parse_pattern_json(const std::string& text,
                                            const std::string& source_name);
std::vector<PatternMark> read_pattern_json(const std::filesystem::path& path);
std::string pattern_json_text(const std::vector<PatternMark>& marks);

struct PatternOptions {
  int marks = 12;
  // Half the arm of a cross (mm), the height of its digits; 0: 1/80 of the sheet's smaller side,
  // 2..10 mm.
  double cross_size_mm = 0.0;
  // The sheet as x min, y min, x max, y max (mm, machine coordinates); none: the reach box.
  std::optional<std::array<double, 4>> sheet_mm;
};

// A designed pattern: its marks, their size and the sheet they were spread over.
struct CalibrationPattern {
  std::vector<PatternMark> marks;
  double cross_size_mm = 0.0;  // half the arm of a cross; digits are as high
  double sheet_min_x_mm = 0.0, sheet_max_x_mm = 0.0, sheet_min_y_mm = 0.0, sheet_max_y_mm = 0.0;
};

// Smallest over largest singular value of d joints / d (x, y) at `pose`: 0 where the pen's
// position is ill-defined (a hanging plotter's cables in line), 1 where every direction of pen
// motion moves the joints alike. Marks go where it is at least kMinPatternConditioning: there an
// error in the geometry moves the pen by a few times the error at most (on a hanging plotter
// under the middle: the cables 14 deg or more below the horizontal).
double planar_conditioning(const kinematics::Kinematics& kinematics, const geometry::Pose& pose);
inline constexpr double kMinPatternConditioning = 0.25;

// Chooses `options.marks` marks spread over the sheet: candidates on a grid over the sheet (by
// default the reachable box, reach_box) whose whole mark (cross and number, with a margin) the
// machine reaches (Machine::inverse: IK, tension, joint limits, envelope) where it is well
// conditioned (planar_conditioning), then farthest-point sampling from the corners inward. Throws
// std::invalid_argument when fewer candidates exist than marks.
CalibrationPattern design_pattern(const machine::Machine& machine, const PatternOptions& options);

// The polylines (mm, machine x y) that draw a mark: its cross, then its number's digits to the
// upper right of it, in a seven-segment stroke font as high as cross_size_mm.
std::vector<std::vector<Eigen::Vector2d>> mark_strokes(const PatternMark& mark,
                                                       double cross_size_mm);

// The program's Z with the pen down and up (mm, machine coordinates). By default: on a machine
// whose kinematics controls Z (a Maslow's router), down at 0 and up at home's Z (5 mm if home is
// at or below 0); otherwise 1 mm past the [tool] table's height on its drawing side and 5 mm
// past it on the other (down_below - 1 and + 5, down_above + 1 and - 5; -1 and 5 without the
// table, whose machine ignores Z).
struct PenHeights {
  double down_mm = -1.0;
  double up_mm = 5.0;
};
PenHeights default_pen_heights(const machine::Machine& machine);

// Ordinary Cartesian G-code (G21 G90, machine coordinates, program zero at the machine's origin)
// drawing every mark: G0 to each stroke's start with the pen up, G1 along it with the pen down,
// at half the machine's max_feed. Throws std::invalid_argument naming the first point (at its
// pen height) the machine cannot reach.
std::string pattern_gcode(const machine::Machine& machine, const CalibrationPattern& pattern,
                          const PenHeights& pen);

}  // namespace pkm::calibration
