#include "pkm/calibration/matrix_calibration.hpp"

#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>

namespace pkm::calibration {

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

// The largest corrections measurements of a real machine give: a squareness or tilt of 0.1
// (5.7 deg) and a scale of half or twice. Beyond them (inches against mm, a typo, a denormal
// travel that makes a quotient infinite) the measurement is wrong, not the machine.
constexpr double kLargestSkew = 0.1;
constexpr double kLargestScaleChange = 0.5;

// `coefficient` + `correction`, refused unless the correction is one a machine can need.
void add_correction(double& coefficient, double correction, double largest, const char* name,
                    const std::string& measured) {
  if (!std::isfinite(correction) || std::abs(correction) > largest) {
    char text[200];
    std::snprintf(text, sizeof text,
                  ": %s gives a correction of %.6g, more than the %g a real machine needs: check "
                  "the values and their units",
                  measured.c_str(), correction, largest);
    throw std::invalid_argument(std::string(name) + text);
  }
  coefficient += correction;
}

std::string pair_text(const char* first, double a, const char* second, double b) {
  char text[160];
  std::snprintf(text, sizeof text, "%s %.6g %s %.6g", first, a, second, b);
  return text;
}

}  // namespace

Eigen::Matrix3d calibrate_matrix(const MatrixMeasurements& m, const Eigen::Matrix3d& start) {
  Eigen::Matrix3d matrix = start;
  if (m.diagonals) {
    const auto [a, b] = *m.diagonals;
    require_finite(*m.diagonals, "--diagonals");
    require_positive(a, "--diagonals", "A (X+/Y+ diagonal)");
    require_positive(b, "--diagonals", "B (X+/Y- diagonal)");
    add_correction(matrix(0, 1), (b * b - a * a) / (2.0 * a * b), kLargestSkew, "--diagonals",
                   pair_text("diagonals A", a, "and B", b));
  }
  if (m.widths) {
    const auto [width_x, width_y] = *m.widths;
    require_finite(*m.widths, "--widths");
    require_positive(width_x, "--widths", "WX");
    require_positive(width_y, "--widths", "WY");
    // The widths were cut with the current C_yy in effect: scale it, keeping X the reference.
    add_correction(matrix(1, 1), start(1, 1) * (width_x / width_y - 1.0),
                   kLargestScaleChange * std::abs(start(1, 1)), "--widths",
                   pair_text("widths WX", width_x, "and WY", width_y));
  }
  if (m.x_to_spindle) {
    const auto [reading, travel] = *m.x_to_spindle;
    require_finite(*m.x_to_spindle, "--x-to-spindle");
    require_nonzero(travel, "--x-to-spindle", "X travel");
    add_correction(matrix(2, 0), reading / travel, kLargestSkew, "--x-to-spindle",
                   pair_text("a reading of", reading, "over a travel of", travel));
  }
  if (m.y_to_spindle) {
    const auto [reading, travel] = *m.y_to_spindle;
    require_finite(*m.y_to_spindle, "--y-to-spindle");
    require_nonzero(travel, "--y-to-spindle", "Y travel");
    add_correction(matrix(2, 1), reading / travel, kLargestSkew, "--y-to-spindle",
                   pair_text("a reading of", reading, "over a travel of", travel));
  }
  if (m.z_tilt_x) {
    const auto [difference, travel] = *m.z_tilt_x;
    require_finite(*m.z_tilt_x, "--z-tilt-x");
    require_nonzero(travel, "--z-tilt-x", "Z travel");
    add_correction(matrix(0, 2), -difference / travel, kLargestSkew, "--z-tilt-x",
                   pair_text("a difference of", difference, "over a travel of", travel));
  }
  if (m.z_tilt_y) {
    const auto [difference, travel] = *m.z_tilt_y;
    require_finite(*m.z_tilt_y, "--z-tilt-y");
    require_nonzero(travel, "--z-tilt-y", "Z travel");
    add_correction(matrix(1, 2), -difference / travel, kLargestSkew, "--z-tilt-y",
                   pair_text("a difference of", difference, "over a travel of", travel));
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

}  // namespace pkm::calibration
