// Least-squares fitting of a model's named geometric parameters to measured tool poses.
#pragma once

#include <string>
#include <vector>

#include "pkm/calibration/measurements.hpp"

namespace pkm {

struct FitOptions {
  // Parameter names to fit; '*' matches any run of characters ("leg*.offset"). Empty: all.
  std::vector<std::string> parameters;
  // Angle residuals count as this many mm per radian (a 100 mm lever).
  double angle_weight_mm_per_rad = 100.0;
  // A direction of parameter space whose (column-normalised) singular value is below this
  // fraction of the largest cannot be told apart by the data.
  double rank_tolerance = 1e-6;
};

struct ParameterEstimate {
  std::string name;
  std::string unit;
  double nominal = 0.0;
  double fitted = 0.0;
  double standard_deviation = 0.0;  // 0 for parameters held at nominal
  bool free = false;                // fitted (true) or held at its nominal value
};

struct FitReport {
  int measurements = 0;
  // Per-measurement distance between modelled and measured pose over the measured coordinates
  // (angles weighted by angle_weight_mm_per_rad), in mm.
  double rms_before_mm = 0.0;
  double max_before_mm = 0.0;
  double rms_after_mm = 0.0;
  double max_after_mm = 0.0;
  int max_after_line = 0;
  std::vector<ParameterEstimate> parameters;
  // Groups of parameters the data cannot tell apart, each a direction of parameter space the
  // residuals do not see; the fit holds enough of them at their nominal values.
  std::vector<std::vector<std::string>> indistinguishable;
  std::vector<std::string> held;  // requested parameters held at nominal
  bool converged = false;
  int iterations = 0;
};

class FitError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Fits `kinematics` (updated in place to the fitted geometry) to the measurements. `seed` is the
// pose FK starts from where a controlled coordinate was not measured (home).
FitReport fit_geometry(Kinematics& kinematics, const Pose& seed,
                       const std::vector<Measurement>& measurements, const FitOptions& options);

}  // namespace pkm
