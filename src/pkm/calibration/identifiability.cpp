#include "pkm/calibration/identifiability.hpp"

#include <Eigen/QR>
#include <algorithm>
#include <cmath>
#include <cstdio>

namespace pkm::calibration {

namespace {

constexpr double kTradeCorrelation = 0.5;
constexpr std::size_t kMostTrades = 4;

Eigen::MatrixXd without_column(const Eigen::MatrixXd& matrix, Eigen::Index column) {
  Eigen::MatrixXd result(matrix.rows(), matrix.cols() - 1);
  result << matrix.leftCols(column), matrix.rightCols(matrix.cols() - column - 1);
  return result;
}

}  // namespace

Precision fit_precision(const Eigen::MatrixXd& jacobian,
                        const std::vector<ScreenedParameter>& parameters, double sigma) {
  const Eigen::Index n = jacobian.cols();
  Precision result;
  result.deviation.assign(static_cast<std::size_t>(n), 0.0);
  result.correlation = Eigen::MatrixXd::Identity(n, n);
  result.trades.resize(static_cast<std::size_t>(n));
  if (n == 0) return result;
  // (J^T J)^-1 by the pseudo-inverse of the column-normalised J^T J (columns in mm, kg and
  // mm/m/N differ by orders of magnitude): a column the data do not see gets 0, not infinity,
  // and is the rank identification's to hold.
  Eigen::VectorXd scale = jacobian.colwise().norm().transpose();
  for (Eigen::Index c = 0; c < n; ++c) scale[c] = scale[c] > 0.0 ? 1.0 / scale[c] : 1.0;
  const Eigen::MatrixXd normalised = jacobian * scale.asDiagonal();
  const Eigen::MatrixXd inverse =
      scale.asDiagonal() *
      (normalised.transpose() * normalised).completeOrthogonalDecomposition().pseudoInverse() *
      scale.asDiagonal();
  for (Eigen::Index c = 0; c < n; ++c)
    result.deviation[static_cast<std::size_t>(c)] = sigma * std::sqrt(std::max(0.0, inverse(c, c)));
  for (Eigen::Index a = 0; a < n; ++a) {
    for (Eigen::Index b = 0; b < n; ++b) {
      const double spread = std::sqrt(std::max(0.0, inverse(a, a) * inverse(b, b)));
      if (a != b && spread > 0.0) result.correlation(a, b) = inverse(a, b) / spread;
    }
  }
  for (Eigen::Index a = 0; a < n; ++a) {
    std::vector<TradeOff>& trades = result.trades[static_cast<std::size_t>(a)];
    for (Eigen::Index b = 0; b < n; ++b) {
      if (b != a && std::abs(result.correlation(a, b)) >= kTradeCorrelation)
        trades.push_back({parameters[static_cast<std::size_t>(b)].name, result.correlation(a, b)});
    }
    std::sort(trades.begin(), trades.end(), [](const TradeOff& x, const TradeOff& y) {
      return std::abs(x.correlation) > std::abs(y.correlation);
    });
    if (trades.size() > kMostTrades) trades.resize(kMostTrades);
  }
  return result;
}

std::vector<PoorlyDetermined> poorly_determined(const Eigen::MatrixXd& jacobian,
                                                const std::vector<ScreenedParameter>& parameters,
                                                double sigma) {
  std::vector<PoorlyDetermined> held;
  Eigen::MatrixXd columns = jacobian;
  std::vector<ScreenedParameter> remaining = parameters;
  while (!remaining.empty()) {
    const Precision precision = fit_precision(columns, remaining, sigma);
    std::size_t worst = remaining.size();
    double worst_ratio = 1.0;
    for (std::size_t c = 0; c < remaining.size(); ++c) {
      if (!(remaining[c].plausible_deviation > 0.0)) continue;
      const double ratio = precision.deviation[c] / remaining[c].plausible_deviation;
      if (ratio > worst_ratio) worst = c, worst_ratio = ratio;
    }
    if (worst == remaining.size()) break;
    const ScreenedParameter& p = remaining[worst];
    const auto column = static_cast<Eigen::Index>(worst);
    const double norm = columns.col(column).norm();
    held.push_back({p.name, p.unit, p.kind, p.nominal, p.fitted, precision.deviation[worst],
                    norm > 0.0 ? sigma / norm : 0.0, p.plausible_deviation, precision.trades[worst],
                    p.rule});
    columns = without_column(columns, column);
    remaining.erase(remaining.begin() + static_cast<std::ptrdiff_t>(worst));
  }
  return held;
}

std::string describe_trades(const std::vector<TradeOff>& trades) {
  if (trades.empty()) return "no single parameter";
  std::string text;
  for (const TradeOff& t : trades) {
    char correlation[32];
    std::snprintf(correlation, sizeof correlation, "%.2f", t.correlation);
    text += (text.empty() ? "" : ", ") + t.name + " (correlation " + correlation + ")";
  }
  return text;
}

std::string shown_number(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.4g", value);
  return text;
}

}  // namespace pkm::calibration
