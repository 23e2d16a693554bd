#include "pkm/calibration/geometry_fit.hpp"

#include <ceres/ceres.h>

#include <Eigen/QR>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <memory>

namespace pkm {

namespace {

bool matches(const std::string& pattern, const std::string& name) {
  // Glob with '*' only, by dynamic programming over the two strings.
  std::vector<bool> row(name.size() + 1, false);
  row[0] = true;
  for (const char p : pattern) {
    std::vector<bool> next(name.size() + 1, false);
    if (p == '*') {
      bool any = false;
      for (std::size_t i = 0; i <= name.size(); ++i) {
        any = any || row[i];
        next[i] = any;
      }
    } else {
      for (std::size_t i = 1; i <= name.size(); ++i) next[i] = row[i - 1] && name[i - 1] == p;
    }
    row = std::move(next);
  }
  return row[name.size()];
}

// The residuals of a geometry: for each measurement, modelled minus measured pose over the
// measured coordinates, from FK of the measured joints.
class Residuals {
 public:
  Residuals(const Kinematics& kinematics, const Pose& seed,
            const std::vector<Measurement>& measurements, double angle_weight)
      : model_(kinematics.clone()), measurements_(measurements), angle_weight_(angle_weight) {
    for (const Parameter& p : kinematics.parameters()) nominal_.push_back(p.value);
    for (const Measurement& m : measurements_) {
      Pose start = seed;
      Vector6d values = start.as_vector();
      for (int axis = 0; axis < kPoseSize; ++axis) {
        if (m.measured[axis]) values[axis] = m.pose[axis];
      }
      seeds_.push_back(Pose::from_vector(values));
      for (int axis = 0; axis < kPoseSize; ++axis) count_ += m.measured[axis] ? 1 : 0;
    }
  }

  int count() const { return count_; }
  const std::vector<double>& nominal() const { return nominal_; }

  // Residuals for the full parameter vector; false where the geometry is impossible or FK fails.
  bool evaluate(const std::vector<double>& parameters, double* residuals) const {
    try {
      model_->set_parameters(parameters);
    } catch (const std::invalid_argument&) {
      return false;
    }
    int k = 0;
    for (std::size_t i = 0; i < measurements_.size(); ++i) {
      const Measurement& m = measurements_[i];
      Pose pose = seeds_[i];
      if (!model_->forward(m.joints, pose).ok()) return false;
      const Vector6d modelled = pose.as_vector();
      for (int axis = 0; axis < kPoseSize; ++axis) {
        if (!m.measured[axis]) continue;
        const double difference = modelled[axis] - m.pose[axis];
        residuals[k++] = axis < 3 ? difference : difference * angle_weight_;
      }
    }
    return true;
  }

  // Per-measurement distances (mm) from a residual vector.
  void distances(const std::vector<double>& residuals, double& rms, double& max,
                 int& max_line) const {
    double sum = 0.0;
    max = 0.0;
    int k = 0;
    for (const Measurement& m : measurements_) {
      double squared = 0.0;
      for (int axis = 0; axis < kPoseSize; ++axis) {
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

  // Central-difference Jacobian of the residuals over the parameters `free` (full-vector indices).
  // A parameter that cannot move both ways from here (a pulley radius or a mass of 0, a cable's
  // attachment point on an effector given no mass) gets a zero column: the fit holds it (give a
  // nominal value inside its range to fit it).
  bool jacobian(const std::vector<double>& parameters, const std::vector<int>& free,
                Eigen::MatrixXd& result) const {
    result.resize(count_, static_cast<Eigen::Index>(free.size()));
    std::vector<double> shifted = parameters;
    std::vector<double> plus(count_), minus(count_);
    for (std::size_t c = 0; c < free.size(); ++c) {
      const int index = free[c];
      const double step = 1e-6 * std::max(1.0, std::abs(parameters[index]));
      shifted[index] = parameters[index] + step;
      const bool up = evaluate(shifted, plus.data());
      shifted[index] = parameters[index] - step;
      const bool down = evaluate(shifted, minus.data());
      shifted[index] = parameters[index];
      for (int r = 0; r < count_; ++r) {
        result(r, static_cast<Eigen::Index>(c)) =
            up && down ? (plus[r] - minus[r]) / (2.0 * step) : 0.0;
      }
    }
    return true;
  }

 private:
  std::unique_ptr<Kinematics> model_;
  const std::vector<Measurement>& measurements_;
  std::vector<Pose> seeds_;
  std::vector<double> nominal_;
  double angle_weight_;
  int count_ = 0;
};

// Ceres sees only the free parameters; the others stay at their nominal values.
struct FreeParameterCost {
  const Residuals* residuals;
  std::vector<int> free;
  std::vector<double> nominal;
  bool operator()(double const* const* parameters, double* out) const {
    std::vector<double> full = nominal;
    for (std::size_t i = 0; i < free.size(); ++i) full[free[i]] = parameters[0][i];
    return residuals->evaluate(full, out);
  }
};

}  // namespace

FitReport fit_geometry(Kinematics& kinematics, const Pose& seed,
                       const std::vector<Measurement>& measurements, const FitOptions& options) {
  if (measurements.empty()) throw FitError("no measurements to fit");
  const std::vector<Parameter> parameters = kinematics.parameters();
  std::vector<int> requested;
  for (int i = 0; i < static_cast<int>(parameters.size()); ++i) {
    bool wanted = options.parameters.empty();
    for (const std::string& pattern : options.parameters)
      wanted = wanted || matches(pattern, parameters[i].name);
    if (wanted) requested.push_back(i);
  }
  for (const std::string& pattern : options.parameters) {
    bool used = false;
    for (const Parameter& p : parameters) used = used || matches(pattern, p.name);
    if (!used) {
      std::string names;
      for (const Parameter& p : parameters) names += (names.empty() ? "" : ", ") + p.name;
      throw FitError("'" + pattern + "' names no parameter of this " +
                     std::string(kinematics.type()) + " model (its parameters: " + names + ")");
    }
  }

  const Residuals residuals(kinematics, seed, measurements, options.angle_weight_mm_per_rad);
  const std::vector<double>& nominal = residuals.nominal();
  FitReport report;
  report.measurements = static_cast<int>(measurements.size());
  std::vector<double> before(residuals.count());
  if (!residuals.evaluate(nominal, before.data())) {
    throw FitError(
        "forward kinematics fails for a measurement with the nominal geometry: check "
        "that every row's joints are inside the machine's reach");
  }
  int line = 0;
  residuals.distances(before, report.rms_before_mm, report.max_before_mm, line);
  if (!std::isfinite(report.rms_before_mm)) {
    throw FitError(
        "the residuals with the nominal geometry are not finite: a measurement is "
        "far outside this machine");
  }

  // Which requested parameters the data can identify: QR with column pivoting of the
  // column-normalised Jacobian picks a well-conditioned subset; the SVD names the groups.
  Eigen::MatrixXd jacobian;
  if (!residuals.jacobian(nominal, requested, jacobian)) {
    throw FitError("forward kinematics fails next to the nominal geometry");
  }
  Eigen::VectorXd column_norms = jacobian.colwise().norm();
  const double largest_norm = column_norms.size() ? column_norms.maxCoeff() : 0.0;
  // A parameter whose effect is at rounding level is not seen by the data at all; normalising
  // its column would blow that rounding noise up into a direction of its own.
  const double unseen = 1e-9 * largest_norm;
  Eigen::MatrixXd normalised = jacobian;
  for (Eigen::Index c = 0; c < jacobian.cols(); ++c) {
    if (column_norms[c] > unseen) {
      normalised.col(c) /= column_norms[c];
    } else {
      normalised.col(c).setZero();
      column_norms[c] = 0.0;
    }
  }
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(normalised);
  qr.setThreshold(options.rank_tolerance);
  const Eigen::Index rank = qr.rank();
  std::vector<int> free;
  std::vector<bool> is_free(parameters.size(), false);
  for (Eigen::Index k = 0; k < rank; ++k) {
    const int column = qr.colsPermutation().indices()[k];
    if (column_norms[column] == 0.0) continue;
    free.push_back(requested[column]);
    is_free[requested[column]] = true;
  }
  std::sort(free.begin(), free.end());
  if (rank < static_cast<Eigen::Index>(requested.size())) {
    const Eigen::JacobiSVD<Eigen::MatrixXd> svd(normalised, Eigen::ComputeFullV);
    const Eigen::VectorXd& singular = svd.singularValues();
    for (Eigen::Index k = 0; k < singular.size(); ++k) {
      if (singular[k] > options.rank_tolerance * singular[0]) continue;
      std::vector<std::string> group;
      for (Eigen::Index c = 0; c < svd.matrixV().rows(); ++c) {
        if (std::abs(svd.matrixV()(c, k)) > 0.1) group.push_back(parameters[requested[c]].name);
      }
      if (!group.empty()) report.indistinguishable.push_back(group);
    }
  }
  for (const int index : requested) {
    if (!is_free[index]) report.held.push_back(parameters[index].name);
  }
  if (residuals.count() <= static_cast<int>(free.size())) {
    throw FitError(std::to_string(residuals.count()) + " measured values cannot fit " +
                   std::to_string(free.size()) + " parameters: measure more poses");
  }

  std::vector<double> values(free.size());
  for (std::size_t i = 0; i < free.size(); ++i) values[i] = nominal[free[i]];
  ceres::Problem problem;
  auto* cost = new ceres::DynamicNumericDiffCostFunction<FreeParameterCost, ceres::CENTRAL>(
      new FreeParameterCost{&residuals, free, nominal});
  cost->AddParameterBlock(static_cast<int>(free.size()));
  cost->SetNumResiduals(residuals.count());
  if (!free.empty())
    problem.AddResidualBlock(cost, nullptr, values.data());
  else
    delete cost;
  ceres::Solver::Options solver;
  solver.linear_solver_type = ceres::DENSE_QR;
  solver.max_num_iterations = 200;
  solver.function_tolerance = 1e-15;
  solver.gradient_tolerance = 1e-15;
  solver.parameter_tolerance = 1e-14;
  solver.logging_type = ceres::SILENT;
  solver.minimizer_progress_to_stdout = false;
  ceres::Solver::Summary summary;
  if (!free.empty()) ceres::Solve(solver, &problem, &summary);
  report.converged = free.empty() || summary.IsSolutionUsable();
  report.iterations = static_cast<int>(summary.iterations.size());

  std::vector<double> fitted = nominal;
  for (std::size_t i = 0; i < free.size(); ++i) fitted[free[i]] = values[i];
  std::vector<double> after(residuals.count());
  if (!residuals.evaluate(fitted, after.data())) {
    throw FitError("the fitted geometry fails forward kinematics for a measurement");
  }
  residuals.distances(after, report.rms_after_mm, report.max_after_mm, report.max_after_line);

  // Standard deviations from the Jacobian at the solution: sigma^2 (J^T J)^-1, with sigma^2
  // estimated from the residuals.
  std::vector<double> deviation(parameters.size(), 0.0);
  if (!free.empty()) {
    Eigen::MatrixXd final_jacobian;
    if (residuals.jacobian(fitted, free, final_jacobian)) {
      double sum_of_squares = 0.0;
      for (const double r : after) sum_of_squares += r * r;
      const double variance =
          sum_of_squares / static_cast<double>(residuals.count() - static_cast<int>(free.size()));
      const Eigen::MatrixXd normal = final_jacobian.transpose() * final_jacobian;
      const Eigen::MatrixXd covariance =
          variance * normal.completeOrthogonalDecomposition().pseudoInverse();
      for (std::size_t i = 0; i < free.size(); ++i) {
        deviation[free[i]] = std::sqrt(
            std::max(0.0, covariance(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(i))));
      }
    }
  }
  const bool finite =
      std::isfinite(report.rms_after_mm) && std::isfinite(report.max_after_mm) &&
      std::all_of(fitted.begin(), fitted.end(), [](double value) { return std::isfinite(value); });
  if (!finite) {
    throw FitError("the fit did not reach a finite geometry (residual RMS " +
                   std::to_string(report.rms_after_mm) +
                   " mm): nothing written; check the measurements");
  }
  for (const int index : requested) {
    report.parameters.push_back({parameters[index].name, parameters[index].unit, nominal[index],
                                 fitted[index], deviation[index], is_free[index]});
  }
  kinematics.set_parameters(fitted);
  return report;
}

}  // namespace pkm
