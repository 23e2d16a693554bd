// Least-squares fitting of a model's named geometric parameters to measured tool poses.
#pragma once

#include <string>
#include <vector>

#include "pkm/calibration/measurements.hpp"
#include "pkm/calibration/parameter_fit.hpp"

namespace pkm::calibration {

// Fits `kinematics` (updated in place to the fitted geometry) to the measurements. `seed` is the
// pose FK starts from where a controlled coordinate was not measured (home).
FitReport fit_geometry(kinematics::Kinematics& kinematics, const geometry::Pose& seed,
                       const std::vector<Measurement>& measurements, const FitOptions& options);

}  // namespace pkm::calibration
