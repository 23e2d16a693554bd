// The `#define NAME value` lines of a Marlin Configuration.h (docs/firmware-marlin.md): each
// define's line and text, its value as a number or a `{ a, b, c }` list, evaluated with numbers
// (an `f` suffix allowed), + - * /, parentheses and the other defines of the file. Commented-out
// `//#define` lines are off; `#if` blocks are not evaluated (every define counts); function-like
// macros and defines whose values are not asked for are kept only as names for the notes.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace pkm::firmware {

class MarlinDefines {
 public:
  // Throws FirmwareFileError for a define without a name.
  MarlinDefines(std::string_view text, std::string source);

  bool enabled(const std::string& name) const { return defines_.count(name) > 0; }
  int line(const std::string& name) const;  // 0 when not defined
  // The value as a number; FirmwareFileError "source:line: NAME: why" when it is not one.
  double number(const std::string& name) const;
  std::optional<double> optional_number(const std::string& name) const;
  // A `{ a, b, ... }` list of at least `count` numbers (more: the rest are returned too).
  std::vector<double> list(const std::string& name, std::size_t count) const;
  std::optional<std::vector<double>> optional_list(const std::string& name,
                                                   std::size_t count) const;
  // A quoted string's text ("My Delta" -> My Delta).
  std::optional<std::string> string_value(const std::string& name) const;
  // FirmwareFileError "source:line: NAME: missing; <why>" pointing at `needed_by`'s line.
  [[noreturn]] void missing(const std::string& name, const std::string& needed_by,
                            const std::string& why) const;
  // The names of the file's defines not in `used`, in file order.
  std::vector<std::string> unused(const std::vector<std::string>& used) const;
  const std::string& source() const { return source_; }
  struct Comment {
    std::string text;
    int line = 0;
  };
  // Every comment line starting with `prefix` (after "//"): its text after the prefix, its line.
  std::vector<Comment> comment_lines(std::string_view prefix) const;

 private:
  struct Define {
    std::string value;
    int line = 0;
  };
  [[noreturn]] void fail(const std::string& name, const std::string& why) const;
  double evaluate(const std::string& name, std::string_view expression, int depth) const;
  const Define& find(const std::string& name) const;

  std::string source_;
  std::map<std::string, Define> defines_;
  std::vector<std::string> order_;
  std::vector<Comment> comments_;
  friend class MarlinExpression;
};

// A number as the writer prints it: up to 6 decimals, trailing zeros dropped ("124", "-0.5").
std::string marlin_number(double value);

}  // namespace pkm::firmware
