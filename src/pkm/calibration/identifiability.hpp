// How well a least-squares fit determines each parameter it fits, from the residuals' Jacobian at
// the solution: standard deviations and correlations from sigma^2 (J^T J)^-1, and the parameters
// to hold because the data pin them less well than the machine file already does (their standard
// deviation beyond their kind's plausible deviation, parameter_plausibility.hpp), each with the
// parameters it trades with.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

namespace pkm::calibration {

struct TradeOff {
  std::string name;
  double correlation = 0.0;  // of the two fitted values, -1..1
};

// A parameter the data determine less well than its plausible deviation: held at nominal.
struct PoorlyDetermined {
  std::string name;
  std::string unit;
  std::string kind;  // "a pulley's radius"
  double nominal = 0.0;
  double fitted = 0.0;  // where the fit that could not pin it put it (nominal at design time)
  double standard_deviation = 0.0;
  double alone_deviation = 0.0;  // its standard deviation were it the only parameter fitted
  double plausible_deviation = 0.0;
  std::vector<TradeOff> trades_with;  // |correlation| >= 0.5, strongest first, at most 4
  std::string rule;                   // how plausible_deviation was made (Plausibility::rule)
};

// One fitted parameter as the screen sees it.
struct ScreenedParameter {
  std::string name;
  std::string unit;
  std::string kind;
  double nominal = 0.0;
  double fitted = 0.0;
  double plausible_deviation = 0.0;  // 0: not judged
  std::string rule;                  // how plausible_deviation was made (Plausibility::rule)
};

struct Precision {
  std::vector<double> deviation;              // per column
  Eigen::MatrixXd correlation;                // between columns
  std::vector<std::vector<TradeOff>> trades;  // per column, as PoorlyDetermined::trades_with
};

// The precision of the parameters whose columns `jacobian` has (`parameters` in that order) when
// the residuals' noise is `sigma` (mm).
Precision fit_precision(const Eigen::MatrixXd& jacobian,
                        const std::vector<ScreenedParameter>& parameters, double sigma);

// The columns to hold, in the order held: while some judged column's standard deviation exceeds
// its plausible deviation, the one that exceeds it by the largest factor, its numbers taken with
// the others still fitted; then the rest's precision is taken again without it.
std::vector<PoorlyDetermined> poorly_determined(const Eigen::MatrixXd& jacobian,
                                                const std::vector<ScreenedParameter>& parameters,
                                                double sigma);

// "cable_offset_left (correlation -0.99), anchor_right_x (0.62)"; "no single parameter" if empty.
std::string describe_trades(const std::vector<TradeOff>& trades);

// A number in a message: 4 significant digits, no trailing zeros.
std::string shown_number(double value);

}  // namespace pkm::calibration
