#include "pkm/gcode/expression.hpp"

#include <cmath>
#include <numbers>
#include <string>

#include "pkm/gcode/gcode_error.hpp"

namespace pkm::gcode {

namespace {

constexpr double kEqualTolerance = 1e-4;  // LinuxCNC's EQ/NE compare within this

double degrees(double radians) {
  return radians * 180.0 / std::numbers::pi;
}
double radians(double degrees) {
  return degrees * std::numbers::pi / 180.0;
}

[[noreturn]] void fail(int column, const std::string& message) {
  throw SyntaxError{column, message};
}

// A value must be finite (rs274: "calculation resulted in 'infinity'").
double finite(double value, int column) {
  if (!std::isfinite(value)) fail(column, "calculation resulted in infinity or NaN");
  return value;
}

double compare(Operator op, double left, double right) {
  switch (op) {
    case Operator::eq:
      return std::abs(left - right) < kEqualTolerance ? 1.0 : 0.0;
    case Operator::ne:
      return std::abs(left - right) >= kEqualTolerance ? 1.0 : 0.0;
    case Operator::gt:
      return left > right ? 1.0 : 0.0;
    case Operator::ge:
      return left >= right ? 1.0 : 0.0;
    case Operator::lt:
      return left < right ? 1.0 : 0.0;
    case Operator::le:
      return left <= right ? 1.0 : 0.0;
    case Operator::and_:
      return (left != 0.0 && right != 0.0) ? 1.0 : 0.0;
    case Operator::or_:
      return (left != 0.0 || right != 0.0) ? 1.0 : 0.0;
    case Operator::xor_:
      return ((left != 0.0) != (right != 0.0)) ? 1.0 : 0.0;
    default:
      return 0.0;
  }
}

double arithmetic(Operator op, double left, double right, int column) {
  switch (op) {
    case Operator::power:
      if (left < 0.0 && std::floor(right) != right) {
        fail(column, "attempt to raise a negative number to a non-integer power");
      }
      return std::pow(left, right);
    case Operator::times:
      return left * right;
    case Operator::divide:
      if (right == 0.0) fail(column, "attempt to divide by zero");
      return left / right;
    case Operator::modulo: {
      if (right == 0.0) fail(column, "attempt to divide by zero");
      double result = std::fmod(left, right);
      if (result < 0.0) result += std::abs(right);
      return result;
    }
    case Operator::plus:
      return left + right;
    case Operator::minus:
      return left - right;
    default:
      return compare(op, left, right);
  }
}

double unchecked_function(std::string_view name, double argument, int column) {
  if (name == "abs") return std::abs(argument);
  if (name == "acos") {
    if (argument < -1.0 || argument > 1.0) fail(column, "argument to ACOS out of range");
    return degrees(std::acos(argument));
  }
  if (name == "asin") {
    if (argument < -1.0 || argument > 1.0) fail(column, "argument to ASIN out of range");
    return degrees(std::asin(argument));
  }
  if (name == "cos") return std::cos(radians(argument));
  if (name == "sin") return std::sin(radians(argument));
  if (name == "tan") return std::tan(radians(argument));
  if (name == "exp") return std::exp(argument);
  if (name == "fix") return std::floor(argument);
  if (name == "fup") return std::ceil(argument);
  if (name == "round") return static_cast<double>(std::lround(argument));
  if (name == "ln") {
    if (argument <= 0.0) fail(column, "zero or negative argument to LN");
    return std::log(argument);
  }
  if (argument < 0.0) fail(column, "negative argument to SQRT");
  return std::sqrt(argument);
}

}  // namespace

int precedence(Operator op) {
  switch (op) {
    case Operator::power:
      return 6;
    case Operator::times:
    case Operator::divide:
    case Operator::modulo:
      return 5;
    case Operator::plus:
    case Operator::minus:
      return 4;
    case Operator::eq:
    case Operator::ne:
    case Operator::gt:
    case Operator::ge:
    case Operator::lt:
    case Operator::le:
      return 3;
    case Operator::and_:
    case Operator::or_:
    case Operator::xor_:
      return 2;
    case Operator::none:
      return 0;
  }
  return 0;
}

double apply_operator(Operator op, double left, double right, int column) {
  return finite(arithmetic(op, left, right, column), column);
}

double apply_function(std::string_view name, double argument, int column) {
  return finite(unchecked_function(name, argument, column), column);
}

double atan_degrees(double y, double x) {
  return degrees(std::atan2(y, x));
}

void ExpressionStack::push_operator(Operator op, int column) {
  while (!operators_.empty() && precedence(operators_.back().first) >= precedence(op)) {
    apply_last();
  }
  operators_.emplace_back(op, column);
}

double ExpressionStack::result() {
  while (!operators_.empty()) apply_last();
  return values_.back();
}

void ExpressionStack::apply_last() {
  const double right = values_.back();
  values_.pop_back();
  const auto [op, column] = operators_.back();
  values_.back() = apply_operator(op, values_.back(), right, column);
  operators_.pop_back();
}

}  // namespace pkm::gcode
