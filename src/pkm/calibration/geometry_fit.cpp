#include "pkm/calibration/geometry_fit.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>

namespace pkm::calibration {

namespace {

// The residuals of a geometry: for each measurement, modelled minus measured pose over the
// measured coordinates, from FK of the measured joints.
class PoseResiduals final : public ParameterResiduals {
 public:
  PoseResiduals(const kinematics::Kinematics& kinematics, const geometry::Pose& seed,
                const std::vector<Measurement>& measurements, double angle_weight)
      : model_(kinematics.clone()), measurements_(measurements), angle_weight_(angle_weight) {
    for (const Measurement& m : measurements_) {
      geometry::Vector6d values = seed.as_vector();
      for (int axis = 0; axis < geometry::kPoseSize; ++axis) {
        if (m.measured[axis]) values[axis] = m.pose[axis];
      }
      seeds_.push_back(geometry::Pose::from_vector(values));
      for (int axis = 0; axis < geometry::kPoseSize; ++axis) count_ += m.measured[axis] ? 1 : 0;
    }
  }

  int count() const override { return count_; }

  bool evaluate(std::span<const double> parameters, double* residuals) const override {
    try {
      model_->set_parameters(parameters);
    } catch (const std::invalid_argument&) {
      return false;
    }
    int k = 0;
    for (std::size_t i = 0; i < measurements_.size(); ++i) {
      const Measurement& m = measurements_[i];
      geometry::Pose pose = seeds_[i];
      if (!model_->forward(m.joints, pose).ok()) return false;
      const geometry::Vector6d modelled = pose.as_vector();
      for (int axis = 0; axis < geometry::kPoseSize; ++axis) {
        if (!m.measured[axis]) continue;
        const double difference = modelled[axis] - m.pose[axis];
        residuals[k++] = axis < 3 ? difference : difference * angle_weight_;
      }
    }
    return true;
  }

  void summarise(const std::vector<double>& residuals, double& rms, double& max,
                 int& max_line) const override {
    double sum = 0.0;
    max = 0.0;
    int k = 0;
    for (const Measurement& m : measurements_) {
      double squared = 0.0;
      for (int axis = 0; axis < geometry::kPoseSize; ++axis) {
        if (m.measured[axis]) squared += residuals[k] * residuals[k], ++k;
      }
      sum += squared;
      if (std::sqrt(squared) > max) {
        max = std::sqrt(squared);
        max_line = m.line;
      }
    }
    rms = std::sqrt(sum / static_cast<double>(measurements_.size()));
  }

  std::string nominal_failure_hint() const override {
    return "forward kinematics fails for a measurement; check that every row's joints are "
           "inside the machine's reach";
  }

  double extent_mm() const override {
    Eigen::Vector3d low = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
    Eigen::Vector3d high = -low;
    for (const Measurement& m : measurements_) {
      for (int axis = 0; axis < 3; ++axis) {
        if (!m.measured[axis]) continue;
        low[axis] = std::min(low[axis], m.pose[axis]);
        high[axis] = std::max(high[axis], m.pose[axis]);
      }
    }
    double squared = 0.0;
    for (int axis = 0; axis < 3; ++axis) {
      if (high[axis] >= low[axis]) squared += (high[axis] - low[axis]) * (high[axis] - low[axis]);
    }
    return std::sqrt(squared);
  }

 private:
  std::unique_ptr<kinematics::Kinematics> model_;
  const std::vector<Measurement>& measurements_;
  std::vector<geometry::Pose> seeds_;
  double angle_weight_;
  int count_ = 0;
};

}  // namespace

FitReport fit_geometry(kinematics::Kinematics& kinematics, const geometry::Pose& seed,
                       const std::vector<Measurement>& measurements, const FitOptions& options) {
  if (measurements.empty()) throw FitError("no measurements to fit");
  const std::vector<int> requested = requested_parameters(kinematics, options.parameters);
  const PoseResiduals residuals(kinematics, seed, measurements, options.angle_weight_mm_per_rad);
  FitReport report = fit_parameters(kinematics, residuals, requested, {}, options);
  report.measurements = static_cast<int>(measurements.size());
  return report;
}

}  // namespace pkm::calibration
