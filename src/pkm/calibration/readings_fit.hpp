// Calibration from joint readings alone, at poses nobody measured (Hangprinter's auto-calibration:
// the effector moved by hand or by G-code to a few dozen places, the motors' encoders read there).
// A model with more joints than coordinates over-determines each pose, and the surplus pins its
// geometry. The fit eliminates the poses (variable projection): for candidate parameters each
// sample's pose is the least-squares fit of its readings, and the residuals are what that pose
// leaves unexplained, one per joint reading (mm). Readings count from home (encoders zeroed at
// power-on with the effector at the machine's home pose), or are absolute joint values.
// What lengths cannot see (the frame turned about home, an anchor moved with its cable's attach
// point) is held at the machine file's values; the rest goes through the shared fit
// (parameter_fit.hpp): identification, standard deviations, what the data pin less well than the
// machine file, refusal of what no such hardware can be.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "pkm/calibration/parameter_fit.hpp"
#include "pkm/machine/machine.hpp"

namespace pkm::calibration {

// One sample: every joint's reading, in the model's units (mm; rad for rotary joints).
struct JointReadings {
  kinematics::JointVector values;
  int line = 0;  // source line, for reports
};

// What a file's numbers are: the joints' own values (mm, deg for rotary joints), or a cable
// robot's motor positions (deg of the motor shaft) counted from line position 0, the origin, as
// Hangprinter's encoders give them (M569.3; its auto-calibration script's motor_pos_samp). Motor
// degrees become line lengths counted from the origin through the machine file's spools
// (CableRobotKinematics::joint_from_motor_full_steps: RRF's build-up model, inverted exactly).
enum class ReadingUnit { joint, motor_degrees };

// Throws FitError naming the keys to add unless every joint of `machine` is a cable on a spool.
void require_spools(const machine::Machine& machine);

// Reads a CSV with a header row naming every joint `j_` + its name, each once, in any order;
// columns `t` and `line` are ignored. Errors as file:line:column (MeasurementFileError): an
// unknown or repeated column, a missing joint, a value that is not a finite number of at most 1e6
// in size, a motor position no line length gives, a row with too many or too few fields, no rows.
// With motor_degrees, FitError (require_spools) for a machine without spools.
std::vector<JointReadings> parse_readings_csv(const std::string& text,
                                              const std::string& source_name,
                                              const machine::Machine& machine,
                                              ReadingUnit unit = ReadingUnit::joint);
std::vector<JointReadings> read_readings_csv(const std::filesystem::path& path,
                                             const machine::Machine& machine,
                                             ReadingUnit unit = ReadingUnit::joint);

// A sample no pose fits with the machine file's geometry, at its source line.
class SampleFitError : public FitError {
 public:
  SampleFitError(int line, const std::string& message) : FitError(message), line_(line) {}
  int line() const { return line_; }

 private:
  int line_;
};

struct ReadingsFitOptions {
  FitOptions fit;
  // true: each reading counts from the joint's value at home (encoders zeroed there); false: the
  // readings are the joints' absolute values.
  bool relative_to_home = true;
};

struct ReadingsFitReport {
  FitReport fit;  // residuals per joint reading (mm); held_rigid_motion: what lengths cannot see
  int samples = 0;
  int readings_per_sample = 0;
  int pose_coordinates = 0;  // per sample, solved for
  // The noise of a reading the residuals show: their sum of squares over what is left free of
  // it (readings less pose coordinates less fitted parameters), mm.
  double noise_mm = 0.0;
  // The residuals' spread that one bad reading does not inflate: 1.4826 x their median size
  // (their standard deviation for Gaussian noise), mm.
  double residual_spread_mm = 0.0;
  std::vector<geometry::Pose> poses;         // each sample's pose with the fitted geometry
  std::vector<int> lines;                    // each sample's source line
  std::vector<geometry::Pose> poses_before;  // with the machine file's geometry
};

// The fewest samples that leave the noise some degrees of freedom when `parameters` are fitted:
// each sample adds (readings - pose coordinates) equations beyond its own pose.
int fewest_samples(int readings_per_sample, int pose_coordinates, int parameters);

// Fits `kinematics` (its current geometry is the machine file's; updated to the fit) to the
// readings. `home` seeds every sample's pose and, with relative_to_home, is where the readings
// were zeroed. Throws FitError with its numbers: a model with no more joints than coordinates,
// too few samples; SampleFitError for a sample no pose fits with the machine file's geometry.
ReadingsFitReport fit_readings(kinematics::Kinematics& kinematics, const geometry::Pose& home,
                               const std::vector<JointReadings>& samples,
                               const ReadingsFitOptions& options);

}  // namespace pkm::calibration
