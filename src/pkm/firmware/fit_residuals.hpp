// The residuals of the firmware fits (the nearest form, the nearest delta on one circle): values
// in mm, several per workspace pose, summarised as calibration's fits summarise theirs.
#pragma once

#include <cmath>
#include <vector>

#include "pkm/calibration/parameter_fit.hpp"

namespace pkm::firmware {

class MillimetreResiduals : public calibration::ParameterResiduals {
 public:
  explicit MillimetreResiduals(int values_per_pose) : values_per_pose_(values_per_pose) {}

  // Over single values; the "line" of the largest is its pose's index.
  void summarise(const std::vector<double>& residuals, double& rms_mm, double& max_mm,
                 int& max_line) const override {
    double sum = 0.0;
    max_mm = 0.0;
    for (std::size_t k = 0; k < residuals.size(); ++k) {
      sum += residuals[k] * residuals[k];
      if (std::abs(residuals[k]) > max_mm) {
        max_mm = std::abs(residuals[k]);
        max_line = static_cast<int>(k) / values_per_pose_;
      }
    }
    rms_mm = residuals.empty() ? 0.0 : std::sqrt(sum / static_cast<double>(residuals.size()));
  }
  // No plausibility is judged on these fits (calibration::least_squares alone).
  double extent_mm() const override { return 0.0; }

 private:
  int values_per_pose_ = 1;
};

}  // namespace pkm::firmware
