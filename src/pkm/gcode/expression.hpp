// The arithmetic of G-code values, as LinuxCNC's rs274 does it: the binary operators of a
// bracketed expression and their precedence, the functions (angles in degrees), and the
// evaluation of an expression's operands and operators in the order they are read. The reader
// (block.cpp) reads the text; this file computes with what it read.
#pragma once

#include <string_view>
#include <utility>
#include <vector>

namespace pkm::gcode {

enum class Operator {
  none,
  power,
  times,
  divide,
  modulo,
  plus,
  minus,
  eq,
  ne,
  gt,
  ge,
  lt,
  le,
  and_,
  or_,
  xor_
};

// The operators written as words, in the order the reader tries them.
inline constexpr std::pair<std::string_view, Operator> kOperatorWords[] = {
    {"mod", Operator::modulo}, {"eq", Operator::eq},    {"ne", Operator::ne},
    {"gt", Operator::gt},      {"ge", Operator::ge},    {"lt", Operator::lt},
    {"le", Operator::le},      {"and", Operator::and_}, {"or", Operator::or_},
    {"xor", Operator::xor_}};

// The functions a value may call (NAME[argument]); no name is a prefix of another.
inline constexpr std::string_view kFunctionNames[] = {"abs", "acos", "asin", "atan",  "cos",
                                                      "exp", "fix",  "fup",  "ln",    "round",
                                                      "sin", "sqrt", "tan",  "exists"};

// Higher binds first: ** above * / MOD above + - above comparisons above AND OR XOR.
int precedence(Operator op);

// `left op right`, finite; a SyntaxError at `column` for a division by zero, a negative number
// raised to a non-integer power, or a result that is not finite.
double apply_operator(Operator op, double left, double right, int column);

// A function of one argument (any of kFunctionNames but ATAN and EXISTS, which the reader reads
// itself): finite, or a SyntaxError at `column` (an argument out of its domain, or infinity).
double apply_function(std::string_view name, double argument, int column);

// ATAN[y]/[x], in degrees.
double atan_degrees(double y, double x);

// One bracketed expression being evaluated: its operands and operators in the order read, each
// operator applied once none that follows binds tighter (left to right within a level).
class ExpressionStack {
 public:
  explicit ExpressionStack(double first) : values_{first} {}
  // The next operator, read at `column`: those before it that bind at least as tightly are
  // applied first.
  void push_operator(Operator op, int column);
  // The operand after the operator pushed last.
  void push_value(double value) { values_.push_back(value); }
  // The expression's value, once its closing bracket is read.
  double result();

 private:
  void apply_last();

  std::vector<double> values_;
  std::vector<std::pair<Operator, int>> operators_;
};

}  // namespace pkm::gcode
