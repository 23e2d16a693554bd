#include "pkm/calibration/parameter_fit.hpp"

#include <ceres/ceres.h>

#include <Eigen/QR>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>

#include "pkm/calibration/parameter_plausibility.hpp"

namespace pkm::calibration {

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

// Ceres sees only the free parameters; the others stay at their nominal values. The Jacobian is
// differenced here rather than by Ceres so that a parameter the fit drives to the edge of its
// range (a pulley radius towards 0) is differenced on its one valid side instead of ending the
// solve.
class FreeParameterCost final : public ceres::CostFunction {
 public:
  FreeParameterCost(const ParameterResiduals& residuals, std::vector<int> free,
                    std::vector<double> nominal)
      : residuals_(residuals), free_(std::move(free)), nominal_(std::move(nominal)) {
    set_num_residuals(residuals.count());
    mutable_parameter_block_sizes()->push_back(static_cast<int>(free_.size()));
  }

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    const auto of_free = [&](std::span<const double> values, double* out) {
      std::vector<double> full = nominal_;
      for (std::size_t i = 0; i < free_.size(); ++i) full[free_[i]] = values[i];
      return residuals_.evaluate(full, out);
    };
    const std::vector<double> values(parameters[0], parameters[0] + free_.size());
    if (!of_free(values, residuals)) return false;
    if (jacobians == nullptr || jacobians[0] == nullptr) return true;
    std::vector<int> all(free_.size());
    for (std::size_t i = 0; i < all.size(); ++i) all[i] = static_cast<int>(i);
    Eigen::MatrixXd jacobian;
    if (!parameter_jacobian(of_free, residuals_.count(), values, all, jacobian,
                            Differencing::one_sided_at_edges))
      return false;
    Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
        jacobians[0], jacobian.rows(), jacobian.cols()) = jacobian;
    return true;
  }

 private:
  const ParameterResiduals& residuals_;
  std::vector<int> free_;
  std::vector<double> nominal_;
};

}  // namespace

LeastSquaresSolution least_squares(const ParameterResiduals& residuals,
                                   const std::vector<double>& nominal,
                                   const std::vector<int>& free) {
  LeastSquaresSolution solution{nominal};
  if (free.empty()) return solution;
  std::vector<double> values(free.size());
  for (std::size_t i = 0; i < free.size(); ++i) values[i] = nominal[free[i]];
  ceres::Problem problem;
  problem.AddResidualBlock(new FreeParameterCost(residuals, free, nominal), nullptr, values.data());
  ceres::Solver::Options solver;
  solver.linear_solver_type = ceres::DENSE_QR;
  solver.max_num_iterations = 200;
  solver.function_tolerance = 1e-15;
  solver.gradient_tolerance = 1e-15;
  solver.parameter_tolerance = 1e-14;
  solver.logging_type = ceres::SILENT;
  solver.minimizer_progress_to_stdout = false;
  ceres::Solver::Summary summary;
  ceres::Solve(solver, &problem, &summary);
  solution.converged = summary.IsSolutionUsable();
  solution.iterations = static_cast<int>(summary.iterations.size());
  for (std::size_t i = 0; i < free.size(); ++i) solution.fitted[free[i]] = values[i];
  return solution;
}

namespace {

// The residuals' Jacobian over the free parameters at a solution, and the noise sigma (mm) the
// residuals there show: sqrt(sum of squares / (measurements - free parameters)).
struct SolutionJacobian {
  Eigen::MatrixXd jacobian;
  double sigma = 0.0;
  bool ok = false;  // false where the model fails beside the solution: no precision known
};

SolutionJacobian solution_jacobian(const ParameterResiduals& residuals,
                                   const std::vector<double>& fitted, const std::vector<int>& free,
                                   const std::vector<double>& after) {
  SolutionJacobian result;
  const auto function = [&](std::span<const double> p, double* out) {
    return residuals.evaluate(p, out);
  };
  // One-sided at the edge of a range: a pulley radius the fit drove to 0 has a precision too.
  if (free.empty() || !parameter_jacobian(function, residuals.count(), fitted, free,
                                          result.jacobian, Differencing::one_sided_at_edges))
    return result;
  double sum_of_squares = 0.0;
  for (const double r : after) sum_of_squares += r * r;
  const int degrees_of_freedom =
      residuals.count() - static_cast<int>(free.size()) - residuals.eliminated_unknowns();
  result.sigma = std::sqrt(sum_of_squares / static_cast<double>(degrees_of_freedom));
  result.ok = true;
  return result;
}

std::vector<double> evaluated(const ParameterResiduals& residuals,
                              const std::vector<double>& values) {
  std::vector<double> result(static_cast<std::size_t>(residuals.count()));
  if (!residuals.evaluate(values, result.data())) {
    throw FitError("the fitted geometry fails for a measurement: nothing written");
  }
  return result;
}

// Throws FitError naming every fitted value more than kImplausibleDeviations plausible
// deviations from its nominal value, with its standard deviation and what it trades with.
// `precision` unknown (the model fails beside the solution): said so instead of its numbers.
void refuse_implausible(const std::vector<ScreenedParameter>& screened, const Precision& precision,
                        bool precision_known) {
  std::string message;
  for (std::size_t c = 0; c < screened.size(); ++c) {
    const ScreenedParameter& p = screened[c];
    const double off = std::abs(p.fitted - p.nominal);
    if (!(p.plausible_deviation > 0.0) || off <= kImplausibleDeviations * p.plausible_deviation)
      continue;
    const std::string unit = p.unit.empty() ? "" : " " + p.unit;
    message += std::string(message.empty() ? "" : "; ") + p.name + " = " + shown_number(p.fitted) +
               unit +
               (precision_known
                    ? " (standard deviation " + shown_number(precision.deviation[c]) + unit + ")"
                    : " (standard deviation unknown: the model fails beside it)") +
               " is nonsense for " + p.kind + " of this machine: " + shown_number(off) + unit +
               " from the machine file's " + shown_number(p.nominal) + unit + ", more than " +
               shown_number(kImplausibleDeviations) + " x " + shown_number(p.plausible_deviation) +
               unit + " (" + p.rule + ")" +
               (precision_known ? "; it trades with " + describe_trades(precision.trades[c]) : "");
  }
  if (message.empty()) return;
  throw FitError("the fit is nonsense, nothing written: " + message +
                 ". Check the measurements and the machine file's values, or fit fewer "
                 "parameters with --params");
}

}  // namespace

std::vector<int> requested_parameters(const kinematics::Kinematics& kinematics,
                                      const std::vector<std::string>& patterns) {
  const std::vector<kinematics::Parameter> parameters = kinematics.parameters();
  for (const std::string& pattern : patterns) {
    bool used = false;
    for (const kinematics::Parameter& p : parameters) used = used || matches(pattern, p.name);
    if (!used) {
      std::string names;
      for (const kinematics::Parameter& p : parameters)
        names += (names.empty() ? "" : ", ") + p.name;
      throw FitError("'" + pattern + "' names no parameter of this " +
                     std::string(kinematics.type()) + " model (its parameters: " + names + ")");
    }
  }
  std::vector<int> requested;
  for (int i = 0; i < static_cast<int>(parameters.size()); ++i) {
    bool wanted = patterns.empty();
    for (const std::string& pattern : patterns)
      wanted = wanted || matches(pattern, parameters[i].name);
    if (wanted) requested.push_back(i);
  }
  return requested;
}

bool parameter_jacobian(const VectorFunction& function, int rows, const std::vector<double>& at,
                        const std::vector<int>& columns, Eigen::MatrixXd& result,
                        Differencing differencing) {
  result.setZero(rows, static_cast<Eigen::Index>(columns.size()));
  std::vector<double> centre(rows), plus(rows), minus(rows);
  if (!function(at, centre.data())) return false;
  std::vector<double> shifted = at;
  for (std::size_t c = 0; c < columns.size(); ++c) {
    const int index = columns[c];
    const double step = 1e-6 * std::max(1.0, std::abs(at[index]));
    shifted[index] = at[index] + step;
    const bool up = function(shifted, plus.data());
    shifted[index] = at[index] - step;
    const bool down = function(shifted, minus.data());
    shifted[index] = at[index];
    // A parameter that cannot move both ways from here (a pulley radius or a mass of 0, a
    // cable's attachment point on an effector given no mass) gets a zero column where the
    // identification asks: the fit holds it (give a nominal value inside its range to fit it).
    // The solver differences it on its valid side.
    if (up && down) {
      for (int r = 0; r < rows; ++r)
        result(r, static_cast<Eigen::Index>(c)) = (plus[r] - minus[r]) / (2.0 * step);
    } else if (differencing == Differencing::one_sided_at_edges && (up || down)) {
      const std::vector<double>& side = up ? plus : minus;
      for (int r = 0; r < rows; ++r)
        result(r, static_cast<Eigen::Index>(c)) = (up ? 1.0 : -1.0) * (side[r] - centre[r]) / step;
    } else if (differencing == Differencing::one_sided_at_edges) {
      return false;
    }
  }
  return true;
}

Identification identify_parameters(const Eigen::MatrixXd& jacobian,
                                   const std::vector<int>& candidates,
                                   const std::vector<kinematics::Parameter>& parameters,
                                   double rank_tolerance) {
  Identification result;
  result.candidates = candidates;
  Eigen::VectorXd column_norms = jacobian.colwise().norm();
  const double largest_norm = column_norms.size() ? column_norms.maxCoeff() : 0.0;
  // A parameter whose effect is at rounding level is not seen by the data at all; normalising
  // its column would blow that rounding noise up into a direction of its own.
  // So is one whose effect is below the differencing noise of an iterative forward kinematics
  // (solved to about 1e-9 mm, differenced over a step of 1e-6 max(1, |value|)): on a sled, the
  // effector's mass scales both tensions and moves nothing.
  const double unseen = 1e-9 * largest_norm;
  const double rows = static_cast<double>(std::max<Eigen::Index>(1, jacobian.rows()));
  Eigen::MatrixXd normalised = jacobian;
  for (Eigen::Index c = 0; c < jacobian.cols(); ++c) {
    const double value = parameters[static_cast<std::size_t>(candidates[c])].value;
    const double noise = 1e-3 * std::sqrt(rows) / std::max(1.0, std::abs(value));
    if (column_norms[c] > std::max(unseen, noise)) {
      normalised.col(c) /= column_norms[c];
    } else {
      normalised.col(c).setZero();
      column_norms[c] = 0.0;
    }
  }
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(normalised);
  qr.setThreshold(rank_tolerance);
  const Eigen::Index rank = qr.rank();
  for (Eigen::Index k = 0; k < rank; ++k) {
    const int column = qr.colsPermutation().indices()[k];
    if (column_norms[column] == 0.0) continue;
    result.free.push_back(candidates[column]);
  }
  std::sort(result.free.begin(), result.free.end());
  std::vector<Eigen::Index> seen;
  for (Eigen::Index c = 0; c < normalised.cols(); ++c) {
    if (column_norms[c] > 0.0)
      seen.push_back(c);
    else
      result.no_effect.push_back(parameters[candidates[c]].name);
  }
  if (rank < static_cast<Eigen::Index>(seen.size()) && !seen.empty()) {
    Eigen::MatrixXd acting(normalised.rows(), static_cast<Eigen::Index>(seen.size()));
    for (std::size_t c = 0; c < seen.size(); ++c)
      acting.col(static_cast<Eigen::Index>(c)) = normalised.col(seen[c]);
    const Eigen::JacobiSVD<Eigen::MatrixXd> svd(acting, Eigen::ComputeFullV);
    const Eigen::VectorXd& singular = svd.singularValues();
    for (Eigen::Index k = 0; k < svd.matrixV().cols(); ++k) {
      // Columns past the row count have no singular value: null directions too.
      if (k < singular.size() && singular[k] > rank_tolerance * singular[0]) continue;
      std::vector<std::string> group;
      for (Eigen::Index c = 0; c < svd.matrixV().rows(); ++c) {
        if (std::abs(svd.matrixV()(c, k)) > 0.1)
          group.push_back(parameters[candidates[seen[static_cast<std::size_t>(c)]]].name);
      }
      if (!group.empty()) result.indistinguishable.push_back(group);
    }
  }
  return result;
}

Identification identify_at_nominal(const kinematics::Kinematics& kinematics,
                                   const ParameterResiduals& residuals,
                                   const std::vector<int>& requested,
                                   const std::vector<std::string>& held, double rank_tolerance) {
  const std::vector<kinematics::Parameter> parameters = kinematics.parameters();
  std::vector<double> nominal;
  for (const kinematics::Parameter& p : parameters) nominal.push_back(p.value);
  std::vector<int> candidates;
  for (const int index : requested) {
    if (std::find(held.begin(), held.end(), parameters[index].name) == held.end())
      candidates.push_back(index);
  }
  Eigen::MatrixXd jacobian;
  const auto function = [&](std::span<const double> p, double* out) {
    return residuals.evaluate(p, out);
  };
  if (!parameter_jacobian(function, residuals.count(), nominal, candidates, jacobian)) {
    throw FitError("the model fails with the nominal geometry: " +
                   residuals.nominal_failure_hint());
  }
  return identify_parameters(jacobian, candidates, parameters, rank_tolerance);
}

std::vector<ScreenedParameter> screened_parameters(const kinematics::Kinematics& kinematics,
                                                   const std::vector<int>& free,
                                                   const std::vector<double>& values,
                                                   double extent_mm) {
  const std::vector<kinematics::Parameter> parameters = kinematics.parameters();
  const double size_mm = machine_size_mm(parameters, extent_mm);
  std::vector<ScreenedParameter> result;
  for (const int index : free) {
    const kinematics::Parameter& p = parameters[static_cast<std::size_t>(index)];
    const Plausibility plausibility = parameter_plausibility(p, size_mm);
    result.push_back({p.name, p.unit, plausibility.kind, p.value,
                      values[static_cast<std::size_t>(index)], plausibility.deviation,
                      plausibility.rule});
  }
  return result;
}

namespace {

// The solution with the poorly determined parameters held, and what the precision is taken from.
struct FinalSolution {
  LeastSquaresSolution solution;
  std::vector<double> after;  // residuals
  SolutionJacobian at_solution;
  std::vector<ScreenedParameter> screened;  // the free parameters, at the solution
};

// Fits `free`, holds what the solution shows the data pin less well than the machine file
// (removed from `free`, added to report.poorly_determined), and fits again without it: each
// round holds at least one parameter, so this ends.
FinalSolution solve_holding_poorly_determined(const kinematics::Kinematics& kinematics,
                                              const ParameterResiduals& residuals,
                                              const std::vector<double>& nominal,
                                              std::vector<int>& free, FitReport& report) {
  const std::vector<kinematics::Parameter> parameters = kinematics.parameters();
  FinalSolution result;
  for (;;) {
    result.solution = least_squares(residuals, nominal, free);
    result.after = evaluated(residuals, result.solution.fitted);
    result.at_solution = solution_jacobian(residuals, result.solution.fitted, free, result.after);
    result.screened =
        screened_parameters(kinematics, free, result.solution.fitted, residuals.extent_mm());
    if (!result.at_solution.ok) return result;
    const std::vector<PoorlyDetermined> poor =
        poorly_determined(result.at_solution.jacobian, result.screened, result.at_solution.sigma);
    if (poor.empty()) return result;
    for (const PoorlyDetermined& p : poor) {
      report.poorly_determined.push_back(p);
      free.erase(std::find_if(free.begin(), free.end(), [&](int index) {
        return parameters[static_cast<std::size_t>(index)].name == p.name;
      }));
    }
  }
}

}  // namespace

FitReport fit_parameters(kinematics::Kinematics& kinematics, const ParameterResiduals& residuals,
                         const std::vector<int>& requested,
                         const std::vector<std::string>& held_rigid_motion,
                         const FitOptions& options) {
  const std::vector<kinematics::Parameter> parameters = kinematics.parameters();
  std::vector<double> nominal;
  for (const kinematics::Parameter& p : parameters) nominal.push_back(p.value);
  FitReport report;
  std::vector<double> before(residuals.count());
  if (!residuals.evaluate(nominal, before.data())) {
    throw FitError("the model fails with the nominal geometry: " +
                   residuals.nominal_failure_hint());
  }
  int line = 0;
  residuals.summarise(before, report.rms_before_mm, report.max_before_mm, line);
  if (!std::isfinite(report.rms_before_mm)) {
    throw FitError(
        "the residuals with the nominal geometry are not finite: a measurement is "
        "far outside this machine");
  }

  const Identification identified = identify_at_nominal(kinematics, residuals, requested,
                                                        held_rigid_motion, options.rank_tolerance);
  std::vector<int> free = identified.free;
  report.indistinguishable = identified.indistinguishable;
  report.no_effect = identified.no_effect;
  report.held_rigid_motion = held_rigid_motion;
  if (residuals.count() - residuals.eliminated_unknowns() <= static_cast<int>(free.size())) {
    const std::string also =
        residuals.eliminated_unknowns() > 0
            ? " and " + std::to_string(residuals.eliminated_unknowns()) + " pose coordinates"
            : std::string();
    throw FitError(std::to_string(residuals.count()) + " measured values cannot fit " +
                   std::to_string(free.size()) + " parameters" + also +
                   ": measure more, or fit fewer with --params");
  }

  const FinalSolution final_solution =
      solve_holding_poorly_determined(kinematics, residuals, nominal, free, report);
  const LeastSquaresSolution& solution = final_solution.solution;
  const std::vector<double>& after = final_solution.after;
  const SolutionJacobian& at_solution = final_solution.at_solution;
  const std::vector<ScreenedParameter>& screened = final_solution.screened;
  report.converged = solution.converged;
  report.iterations = solution.iterations;
  const std::vector<double>& fitted = solution.fitted;
  residuals.summarise(after, report.rms_after_mm, report.max_after_mm, report.max_after_line);
  const bool finite =
      std::isfinite(report.rms_after_mm) && std::isfinite(report.max_after_mm) &&
      std::all_of(fitted.begin(), fitted.end(), [](double value) { return std::isfinite(value); });
  if (!finite) {
    throw FitError("the fit did not reach a finite geometry (residual RMS " +
                   std::to_string(report.rms_after_mm) +
                   " mm): nothing written; check the measurements");
  }
  // Where the model fails beside the solution, no precision is known: deviations 0.
  const Precision precision =
      fit_precision(at_solution.jacobian, screened, at_solution.ok ? at_solution.sigma : 0.0);
  refuse_implausible(screened, precision, at_solution.ok);

  const auto free_column = [&](int index) {
    const auto at = std::find(free.begin(), free.end(), index);
    return at == free.end() ? -1 : static_cast<int>(at - free.begin());
  };
  const double size_mm = machine_size_mm(parameters, residuals.extent_mm());
  for (const int index : requested) {
    const int column = free_column(index);
    if (column < 0) report.held.push_back(parameters[index].name);
    const Plausibility plausibility = parameter_plausibility(parameters[index], size_mm);
    report.parameters.push_back(
        {parameters[index].name, parameters[index].unit, nominal[index], fitted[index],
         column < 0 ? 0.0 : precision.deviation[static_cast<std::size_t>(column)], column >= 0,
         plausibility.kind, plausibility.deviation});
  }
  kinematics.set_parameters(fitted);
  return report;
}

}  // namespace pkm::calibration
