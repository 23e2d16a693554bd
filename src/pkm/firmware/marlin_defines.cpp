#include "pkm/firmware/marlin_defines.hpp"

#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>

#include "pkm/firmware/target.hpp"

namespace pkm::firmware {
namespace {

std::string trim(std::string_view text) {
  std::size_t begin = 0, end = text.size();
  while (begin < end && std::isspace(static_cast<unsigned char>(text[begin]))) ++begin;
  while (end > begin && std::isspace(static_cast<unsigned char>(text[end - 1]))) --end;
  return std::string(text.substr(begin, end - begin));
}

// The value text without its trailing `//` or `/* */` comment (outside quotes).
std::string without_comment(std::string_view text) {
  bool quoted = false;
  for (std::size_t i = 0; i + 1 < text.size(); ++i) {
    if (text[i] == '"') quoted = !quoted;
    if (!quoted && text[i] == '/' && (text[i + 1] == '/' || text[i + 1] == '*')) {
      return trim(text.substr(0, i));
    }
  }
  return trim(text);
}

bool is_name_char(char c) {
  return std::isalnum(static_cast<unsigned char>(c)) || c == '_';
}

}  // namespace

// Recursive descent over + - * / ( ) numbers and names of other defines.
class MarlinExpression {
 public:
  MarlinExpression(const MarlinDefines& defines, const std::string& name, std::string_view text,
                   int depth)
      : defines_(defines), name_(name), text_(text), depth_(depth) {}

  double parse() {
    const double value = sum();
    skip_space();
    if (at_ < text_.size()) fail("unexpected '" + std::string(text_.substr(at_)) + "'");
    return value;
  }

 private:
  [[noreturn]] void fail(const std::string& why) const {
    defines_.fail(name_, "'" + std::string(text_) + "' is not a number: " + why);
  }
  void skip_space() {
    while (at_ < text_.size() && std::isspace(static_cast<unsigned char>(text_[at_]))) ++at_;
  }
  bool take(char c) {
    skip_space();
    if (at_ < text_.size() && text_[at_] == c) {
      ++at_;
      return true;
    }
    return false;
  }
  double sum() {
    double value = product();
    while (true) {
      if (take('+')) {
        value += product();
      } else if (take('-')) {
        value -= product();
      } else {
        return value;
      }
    }
  }
  double product() {
    double value = unary();
    while (true) {
      if (take('*')) {
        value *= unary();
      } else if (take('/')) {
        const double divisor = unary();
        if (divisor == 0.0) fail("division by zero");
        value /= divisor;
      } else {
        return value;
      }
    }
  }
  double unary() {
    if (take('-')) return -unary();
    if (take('+')) return unary();
    if (take('(')) {
      const double value = sum();
      if (!take(')')) fail("a '(' is not closed");
      return value;
    }
    skip_space();
    if (at_ >= text_.size()) fail("it ends early");
    return std::isdigit(static_cast<unsigned char>(text_[at_])) || text_[at_] == '.' ? literal()
                                                                                     : reference();
  }
  double literal() {
    const std::string rest(text_.substr(at_));
    char* end = nullptr;
    const double value = std::strtod(rest.c_str(), &end);
    std::size_t used = static_cast<std::size_t>(end - rest.c_str());
    if (used == 0) fail("no digits");
    if (used < rest.size() && (rest[used] == 'f' || rest[used] == 'F')) ++used;
    if (used < rest.size() && is_name_char(rest[used])) fail("'" + rest + "'");
    at_ += used;
    return value;
  }
  double reference() {
    const std::size_t begin = at_;
    while (at_ < text_.size() && is_name_char(text_[at_])) ++at_;
    const std::string other(text_.substr(begin, at_ - begin));
    if (other.empty()) fail("'" + std::string(text_.substr(begin)) + "'");
    if (other == "double" || other == "float" || other == "int" || other == "long") {
      // A functional cast, double(XYZ_BELT_PITCH): the value in parentheses.
      if (!take('(')) fail(other + " without '('");
      const double value = sum();
      if (!take(')')) fail("a '(' is not closed");
      return other == "int" || other == "long" ? std::trunc(value) : value;
    }
    if (!defines_.enabled(other)) fail(other + " is not defined in this file");
    if (depth_ > 32) fail("the defines refer to each other in a loop");
    const MarlinDefines::Define& define = defines_.find(other);
    return defines_.evaluate(other, define.value, depth_ + 1);
  }

  const MarlinDefines& defines_;
  const std::string& name_;
  std::string_view text_;
  int depth_;
  std::size_t at_ = 0;
};

MarlinDefines::MarlinDefines(std::string_view text, std::string source)
    : source_(std::move(source)) {
  int line_number = 0;
  std::size_t start = 0;
  while (start <= text.size()) {
    const std::size_t end = std::min(text.find('\n', start), text.size());
    const std::string line = trim(text.substr(start, end - start));
    start = end + 1;
    ++line_number;
    if (line.rfind("//", 0) == 0) {
      comments_.push_back(Comment{trim(std::string_view(line).substr(2)), line_number});
      continue;
    }
    if (line.rfind("#define", 0) != 0) continue;
    std::string_view rest = std::string_view(line).substr(7);
    std::size_t name_end = 0;
    while (name_end < rest.size() && std::isspace(static_cast<unsigned char>(rest[name_end])))
      ++name_end;
    const std::size_t name_begin = name_end;
    while (name_end < rest.size() && is_name_char(rest[name_end])) ++name_end;
    const std::string name(rest.substr(name_begin, name_end - name_begin));
    if (name.empty()) {
      throw FirmwareFileError(source_ + ":" + std::to_string(line_number) +
                              ": #define: no name after #define");
    }
    if (name_end < rest.size() && rest[name_end] == '(') continue;  // a function-like macro
    if (defines_.count(name) == 0) order_.push_back(name);
    defines_[name] = Define{without_comment(rest.substr(name_end)), line_number};
  }
}

const MarlinDefines::Define& MarlinDefines::find(const std::string& name) const {
  return defines_.at(name);
}

int MarlinDefines::line(const std::string& name) const {
  const auto found = defines_.find(name);
  return found == defines_.end() ? 0 : found->second.line;
}

void MarlinDefines::fail(const std::string& name, const std::string& why) const {
  throw FirmwareFileError(source_ + ":" + std::to_string(line(name)) + ": " + name + ": " + why);
}

void MarlinDefines::missing(const std::string& name, const std::string& needed_by,
                            const std::string& why) const {
  throw FirmwareFileError(source_ + ":" + std::to_string(line(needed_by)) + ": " + name +
                          ": missing; " + why);
}

double MarlinDefines::evaluate(const std::string& name, std::string_view expression,
                               int depth) const {
  if (trim(expression).empty()) fail(name, "no value");
  const double value = MarlinExpression(*this, name, expression, depth).parse();
  if (!std::isfinite(value)) fail(name, "not a finite number");
  return value;
}

double MarlinDefines::number(const std::string& name) const {
  if (!enabled(name)) fail(name, "missing");
  return evaluate(name, find(name).value, 0);
}

std::optional<double> MarlinDefines::optional_number(const std::string& name) const {
  if (!enabled(name)) return std::nullopt;
  return number(name);
}

std::vector<double> MarlinDefines::list(const std::string& name, std::size_t count) const {
  if (!enabled(name)) fail(name, "missing");
  const std::string& text = find(name).value;
  if (text.size() < 2 || text.front() != '{' || text.back() != '}') {
    fail(name, "'" + text + "' is not a list { a, b, c }");
  }
  std::vector<double> values;
  int depth = 0;
  std::size_t item_start = 1;
  for (std::size_t i = 1; i < text.size(); ++i) {
    const char c = text[i];
    if (c == '(') ++depth;
    if (c == ')') --depth;
    if ((c == ',' && depth == 0) || i + 1 == text.size()) {
      const std::string item = trim(std::string_view(text).substr(item_start, i - item_start));
      if (!item.empty() || c == ',') values.push_back(evaluate(name, item, 0));
      item_start = i + 1;
    }
  }
  if (values.size() < count) {
    fail(name, "has " + std::to_string(values.size()) + " values, needs " + std::to_string(count));
  }
  return values;
}

std::optional<std::vector<double>> MarlinDefines::optional_list(const std::string& name,
                                                                std::size_t count) const {
  if (!enabled(name)) return std::nullopt;
  return list(name, count);
}

std::optional<std::string> MarlinDefines::string_value(const std::string& name) const {
  if (!enabled(name)) return std::nullopt;
  const std::string& text = find(name).value;
  if (text.size() < 2 || text.front() != '"' || text.back() != '"') {
    fail(name, "'" + text + "' is not a quoted string");
  }
  return text.substr(1, text.size() - 2);
}

std::vector<std::string> MarlinDefines::unused(const std::vector<std::string>& used) const {
  std::vector<std::string> names;
  for (const std::string& name : order_) {
    bool is_used = false;
    for (const std::string& other : used) is_used = is_used || other == name;
    if (!is_used) names.push_back(name);
  }
  return names;
}

std::vector<MarlinDefines::Comment> MarlinDefines::comment_lines(std::string_view prefix) const {
  std::vector<Comment> lines;
  for (const Comment& comment : comments_) {
    if (comment.text.rfind(prefix, 0) == 0) {
      lines.push_back(
          Comment{trim(std::string_view(comment.text).substr(prefix.size())), comment.line});
    }
  }
  return lines;
}

std::string marlin_number(double value) {
  char text[64];
  std::snprintf(text, sizeof text, "%.6f", value);
  std::string result = text;
  while (!result.empty() && result.back() == '0') result.pop_back();
  if (!result.empty() && result.back() == '.') result.pop_back();
  if (result == "-0") result = "0";
  return result;
}

}  // namespace pkm::firmware
