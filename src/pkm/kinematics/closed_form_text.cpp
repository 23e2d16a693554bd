#include "pkm/kinematics/closed_form_text.hpp"

#include <charconv>
#include <cmath>

namespace pkm::kinematics {

std::string plain_decimal(double value) {
  char text[64];
  const auto result = std::to_chars(text, text + sizeof text, value, std::chars_format::fixed);
  return std::string(text, result.ptr);
}

std::string shifted_coordinate(const char* axis, double offset) {
  if (offset == 0.0) return axis;
  return std::string("(") + axis + (offset > 0.0 ? " + " : " - ") +
         plain_decimal(std::abs(offset)) + ")";
}

}  // namespace pkm::kinematics
