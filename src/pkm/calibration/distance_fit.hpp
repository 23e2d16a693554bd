// Calibration with a tape measure: distances measured between the marks a calibration pattern
// drew (a CSV), and the fit of a model's parameters to them. The machine drew mark k with the
// joints its nominal model gives for the mark's nominal position, q_k = IK_nominal(p_k); with a
// candidate geometry the pen was at FK(q_k); a residual is |FK(q_a) - FK(q_b)| - measured.
// Distances cannot see where the whole drawing sits or how it is turned (a rigid motion): the
// fit holds the parameters that only move the drawing as a whole, and, as every fit, those the
// distances pin less well than the machine file does (parameter_fit.hpp).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "pkm/calibration/calibration_pattern.hpp"
#include "pkm/calibration/parameter_fit.hpp"

namespace pkm::calibration {

struct MarkDistance {
  int a = 0;  // indices into the pattern's marks
  int b = 0;
  double distance_mm = 0.0;
  int line = 0;  // source line, for reports
};

// Reads `mark_a,mark_b,distance_mm` (a header row naming those three columns, in any order, then
// one row per measured pair; blank lines skipped). Errors as file:line:column
// (MeasurementFileError): a mark the pattern does not have, a mark paired with itself, a pair
// measured twice (either way round), a distance not a number, not finite, not positive or over
// 1e6 mm, a row with too many or too few fields, no rows.
std::vector<MarkDistance> parse_distances_csv(const std::string& text,
                                              const std::string& source_name,
                                              const std::vector<PatternMark>& marks);
std::vector<MarkDistance> read_distances_csv(const std::filesystem::path& path,
                                             const std::vector<PatternMark>& marks);

// Every pair of marks (a < b) at its nominal distance: what a pattern identifies when all are
// measured.
std::vector<MarkDistance> all_pairs(const std::vector<PatternMark>& marks);

// What measured distances between the marks can identify, at the nominal geometry: the rank
// identification of the fit, then what a tape of FitOptions::design_noise_mm would pin less well
// than the machine file does (held, as the fit holds it).
struct DistanceIdentification {
  std::vector<std::string> identified;
  std::vector<PoorlyDetermined> poorly_determined;
  std::vector<std::string> held_rigid_motion;  // they only move the whole drawing
  std::vector<std::vector<std::string>> indistinguishable;
  std::vector<std::string> no_effect;  // FitReport::no_effect
};
DistanceIdentification identify_from_distances(const kinematics::Kinematics& kinematics,
                                               const geometry::Pose& home,
                                               const std::vector<PatternMark>& marks,
                                               const std::vector<MarkDistance>& distances,
                                               const FitOptions& options);

// Fits `kinematics` (its current geometry is the nominal the pattern was drawn with; updated to
// the fit) to the distances. Marks are poses at `home` with x, y replaced. Throws FitError (a
// mark outside the model's reach names its place in pattern.json).
FitReport fit_distances(kinematics::Kinematics& kinematics, const geometry::Pose& home,
                        const std::vector<PatternMark>& marks,
                        const std::vector<MarkDistance>& distances, const FitOptions& options);

}  // namespace pkm::calibration
