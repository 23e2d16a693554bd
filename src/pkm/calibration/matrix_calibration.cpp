#include "pkm/calibration/matrix_calibration.hpp"

#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace pkm {

namespace {

void require_finite(const std::pair<double, double>& values, const char* name) {
  if (!std::isfinite(values.first) || !std::isfinite(values.second)) {
    throw std::invalid_argument(std::string(name) + ": values must be finite numbers");
  }
}

void require_positive(double value, const char* name, const char* what) {
  if (!(value > 0.0)) {
    throw std::invalid_argument(std::string(name) + ": " + what + " must be a positive length");
  }
}

void require_nonzero(double value, const char* name, const char* what) {
  if (value == 0.0) throw std::invalid_argument(std::string(name) + ": " + what + " must not be 0");
}

}  // namespace

Eigen::Matrix3d calibrate_matrix(const MatrixMeasurements& m, const Eigen::Matrix3d& start) {
  Eigen::Matrix3d matrix = start;
  if (m.diagonals) {
    const auto [a, b] = *m.diagonals;
    require_finite(*m.diagonals, "--diagonals");
    require_positive(a, "--diagonals", "A (X+/Y+ diagonal)");
    require_positive(b, "--diagonals", "B (X+/Y- diagonal)");
    matrix(0, 1) += (b * b - a * a) / (2.0 * a * b);
  }
  if (m.widths) {
    const auto [width_x, width_y] = *m.widths;
    require_finite(*m.widths, "--widths");
    require_positive(width_x, "--widths", "WX");
    require_positive(width_y, "--widths", "WY");
    // The widths were cut with the current C_yy in effect: scale it, keeping X the reference.
    matrix(1, 1) += start(1, 1) * (width_x / width_y - 1.0);
  }
  if (m.x_to_spindle) {
    const auto [reading, travel] = *m.x_to_spindle;
    require_finite(*m.x_to_spindle, "--x-to-spindle");
    require_nonzero(travel, "--x-to-spindle", "X travel");
    matrix(2, 0) += reading / travel;
  }
  if (m.y_to_spindle) {
    const auto [reading, travel] = *m.y_to_spindle;
    require_finite(*m.y_to_spindle, "--y-to-spindle");
    require_nonzero(travel, "--y-to-spindle", "Y travel");
    matrix(2, 1) += reading / travel;
  }
  if (m.z_tilt_x) {
    const auto [difference, travel] = *m.z_tilt_x;
    require_finite(*m.z_tilt_x, "--z-tilt-x");
    require_nonzero(travel, "--z-tilt-x", "Z travel");
    matrix(0, 2) += -difference / travel;
  }
  if (m.z_tilt_y) {
    const auto [difference, travel] = *m.z_tilt_y;
    require_finite(*m.z_tilt_y, "--z-tilt-y");
    require_nonzero(travel, "--z-tilt-y", "Z travel");
    matrix(1, 2) += -difference / travel;
  }
  return matrix;
}

std::string linuxcnc_setp_lines(const Eigen::Matrix3d& matrix, const std::string& component) {
  static constexpr const char* kNames = "xyz";
  std::string lines;
  for (int row = 0; row < 3; ++row) {
    for (int col = 0; col < 3; ++col) {
      char number[40];
      std::snprintf(number, sizeof number, "%.12g", matrix(row, col));
      lines += "setp " + component + ".C_" + kNames[row] + kNames[col] + " " + number + "\n";
    }
  }
  return lines;
}

}  // namespace pkm
