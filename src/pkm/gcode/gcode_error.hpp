#pragma once

#include <charconv>
#include <cmath>
#include <stdexcept>
#include <string>

namespace pkm::gcode {

// An error in a G-code program, located as file:line:column (line and column from 1); a line or
// column of 0 is left out (a file that cannot be opened has no line: "file: message").
class GcodeError : public std::runtime_error {
 public:
  GcodeError(std::string file, int line, int column, const std::string& message)
      : std::runtime_error(location(file, line, column) + ": " + message),
        file_(std::move(file)),
        line_(line),
        column_(column),
        message_(message) {}
  const std::string& file() const { return file_; }
  int line() const { return line_; }
  int column() const { return column_; }
  const std::string& message() const { return message_; }

 private:
  static std::string location(const std::string& file, int line, int column) {
    if (line <= 0) return file;
    if (column <= 0) return file + ":" + std::to_string(line);
    return file + ":" + std::to_string(line) + ":" + std::to_string(column);
  }

  std::string file_;
  int line_;
  int column_;
  std::string message_;
};

// A number for an error message: a whole number as an integer ("4294967296", "100000"), any
// other as short as it can be written and still read back exactly ("1e+300", "0.5", "inf").
inline std::string written_number(double value) {
  if (std::abs(value) < 1e15 && value == std::floor(value)) {
    return std::to_string(static_cast<long long>(value));
  }
  char text[32];
  const auto result = std::to_chars(text, text + sizeof text, value);
  return std::string(text, result.ptr);
}

// Raised inside the reader with a column only; the interpreter adds file and line.
struct SyntaxError {
  int column;
  std::string message;
};

}  // namespace pkm::gcode
