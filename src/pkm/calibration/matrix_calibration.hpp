// LinuxCNC matrixkins calibration: the third source document's shop measurements turned into
// coefficient adjustments. Every adjustment adds to the starting matrix, as a re-calibration with
// an old calibration in effect must.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <string>

namespace pkm::calibration {

// Each measurement is optional; lengths in mm (any one unit, the formulas use ratios).
struct MatrixMeasurements {
  // Octagon diagonals: A along X+/Y+, B along X+/Y-. C_xy += (B^2 - A^2) / (2 A B).
  std::optional<std::pair<double, double>> diagonals;
  // Octagon widths along X and Y: Y's scale is matched to X's, C_yy += C_yy (WX / WY - 1).
  std::optional<std::pair<double, double>> widths;
  // Dial reading D after moving X (Y) by the given distance, indicator swung about the spindle:
  // C_zx += D / X, C_zy += D / Y.
  std::optional<std::pair<double, double>> x_to_spindle;
  std::optional<std::pair<double, double>> y_to_spindle;
  // Indicator difference X (Y) against a rod in the spindle over a Z travel:
  // C_xz += -X / Z, C_yz += -Y / Z.
  std::optional<std::pair<double, double>> z_tilt_x;
  std::optional<std::pair<double, double>> z_tilt_y;
};

// The starting matrix (identity for a first calibration) plus the adjustments the measurements
// give. Throws std::invalid_argument naming the measurement when a value is impossible (a zero
// or negative length, a zero travel, NaN).
Eigen::Matrix3d calibrate_matrix(const MatrixMeasurements& measurements,
                                 const Eigen::Matrix3d& start = Eigen::Matrix3d::Identity());

// "setp matrixkins.C_xx 1.0002" lines, one per coefficient, for a LinuxCNC HAL file.
std::string linuxcnc_setp_lines(const Eigen::Matrix3d& matrix,
                                const std::string& component = "matrixkins");

}  // namespace pkm::calibration
