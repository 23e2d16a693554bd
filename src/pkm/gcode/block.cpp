#include "pkm/gcode/block.hpp"

#include <array>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <stdexcept>

#include "pkm/gcode/expression.hpp"

namespace pkm::gcode {

namespace {

constexpr char lower(char c) {
  return (c >= 'A' && c <= 'Z') ? static_cast<char>(c - 'A' + 'a') : c;
}
constexpr bool is_digit(char c) {
  return c >= '0' && c <= '9';
}
constexpr bool is_alpha(char c) {
  return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z');
}

// Space, tab and carriage return separate words (a table: the reader asks for every character).
constexpr std::array<bool, 256> kBlank = [] {
  std::array<bool, 256> table{};
  table[' '] = table['\t'] = table['\r'] = true;
  return table;
}();
constexpr bool is_blank(char c) {
  return kBlank[static_cast<unsigned char>(c)];
}

// A plain number at `p`: digits with at most one point, no space inside, exact by Clinger's fast
// path (a mantissa below 2^53 and at most 22 decimals are exact doubles, so one division
// rounds correctly, as strtod would). Returns the end of the number and sets `value`, or
// returns nullptr for anything else (the general reader takes it). `p` is NUL-terminated.
inline const char* scan_plain_number(const char* p, double& value) {
  static constexpr double kPowersOfTen[] = {1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,
                                            1e8,  1e9,  1e10, 1e11, 1e12, 1e13, 1e14, 1e15,
                                            1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};
  constexpr std::uint64_t kExactMantissa = std::uint64_t{1} << 53;
  const char* const begin = p;
  std::uint64_t mantissa = 0;
  // One unsigned compare per character: anything below '0' wraps round to a large value.
  unsigned digit = 0;
  while ((digit = static_cast<unsigned char>(*p) - unsigned{'0'}) <= 9) {
    mantissa = mantissa * 10 + digit;
    ++p;
  }
  std::size_t digits = static_cast<std::size_t>(p - begin);
  std::size_t decimals = 0;
  if (*p == '.') {
    const char* const first_decimal = ++p;
    while ((digit = static_cast<unsigned char>(*p) - unsigned{'0'}) <= 9) {
      mantissa = mantissa * 10 + digit;
      ++p;
    }
    decimals = static_cast<std::size_t>(p - first_decimal);
    digits += decimals;
  }
  if (digits == 0 || digits > 19 || mantissa > kExactMantissa || decimals > 22) return nullptr;
  if (*p == ' ' || *p == '\t') {
    // A space ends the number unless more of it follows ("1 0 . 5" is 10.5).
    const char* next = p + 1;
    while (*next == ' ' || *next == '\t') ++next;
    if (is_digit(*next) || *next == '.') return nullptr;
  }
  value = static_cast<double>(mantissa) / kPowersOfTen[decimals];
  return p;
}

// O-word numbers computed by an expression (o[...]) stay below this.
constexpr double kMaxONumber = 1e9;

// O-word keywords, a keyword before any other it is a prefix of ("endsub" before "end...").
constexpr std::string_view kOKeywords[] = {"endsub", "endwhile", "endif",  "endrepeat", "elseif",
                                           "else",   "sub",      "call",   "return",    "do",
                                           "while",  "if",       "repeat", "break",     "continue"};

// Reads one line. The line is a std::string, so a NUL follows its last character: scanning
// loops stop on it without a separate bounds check.
class Reader {
 public:
  Reader(std::string_view line, const Parameters& parameters)
      : line_(line), data_(line.data()), parameters_(parameters) {}

  void read(Block& block) {
    block.clear();
    skip_space();
    if (at_end()) return;
    if (line_[pos_] == '%') {
      block.percent = true;
      return;
    }
    if (line_[pos_] == '/') {
      block.block_delete = true;
      ++pos_;
    }
    while (true) {
      const char c = peek();
      if (c == 0) {
        // A NUL before the end would end the line early, silently: refused.
        if (pos_ < line_.size()) fail(static_cast<int>(pos_) + 1, "NUL byte in the line");
        break;
      }
      const int column = static_cast<int>(pos_) + 1;
      if (c >= 'a' && c <= 'z' && kIsWord[static_cast<std::size_t>(c - 'a')]) {
        // Most words are a letter and a number: first in line.
        ++pos_;
        read_word(block, c - 'a', column);
        continue;
      }
      if (c == '(') {
        block.comments.push_back({read_comment(), column});
        block.plain = false;
      } else if (c == ';') {
        block.comments.push_back({std::string(line_.substr(pos_ + 1)), column});
        refuse_nul_in(block.comments.back().text, column + 1);
        block.plain = false;
        pos_ = line_.size();
      } else if (c == 'n' && block.empty && block.n_label.empty()) {
        ++pos_;
        read_line_number(block, column);
      } else if (c == 'o') {
        read_o_word_line(block, column);
      } else if (c == '#') {
        block.assignments.push_back(read_assignment(column));
        block.empty = false;
        block.plain = false;
      } else if (c == 'g' || c == 'm') {
        ++pos_;
        read_code(block, c, column);
      } else if (c == '@' || c == '^') {
        // Polar radius and angle use the slots of G and M, which are codes, not words.
        ++pos_;
        read_word(block, c == '@' ? 'g' - 'a' : 'm' - 'a', column);
      } else if (is_alpha(c)) {
        fail(column, std::string("bad character '") + display(c) + "' used");
      } else {
        fail(column, std::string("bad character '") + line_[pos_] + "' used");
      }
    }
  }

 private:
  // The digits after N (the N already read).
  void read_line_number(Block& block, int column) {
    block.n_label = read_digits(column);
    // A fractional line number (N1.5) is LinuxCNC's too: the fraction is read and dropped,
    // as rs274 labels the line N1.
    if (peek() == '.') {
      ++pos_;
      while (is_digit(peek())) ++pos_;
    }
    // A line number counts as content only together with other words.
  }

  // An O-word at `column` (at the O), which must be the first word on its line.
  void read_o_word_line(Block& block, int column) {
    if (!block.empty) fail(column, "an O-word must come first on its line");
    block.o_word = read_o_word(column);
    block.empty = false;
    block.plain = false;
    // Only a comment may follow an O-word's arguments.
    const char rest = peek();
    if (rest != 0 && rest != '(' && rest != ';') {
      fail(static_cast<int>(pos_) + 1, "unexpected text after the O-word");
    }
  }

  // The number of a G or M code (the letter `c` already read), kept in tenths (G38.2 is 382).
  void read_code(Block& block, char c, int column) {
    const double value = read_real();
    const double tenths = value * 10.0;
    if (!(value < kMaxCodeNumber)) fail_code_range(c, value, column);
    if (std::abs(tenths - std::round(tenths)) > 1e-3 || value < 0.0) {
      fail(column, std::string("bad ") + static_cast<char>(std::toupper(c)) + " code");
    }
    block.plain = false;
    (c == 'g' ? block.g_codes : block.m_codes)
        .push_back({static_cast<int>(std::lround(tenths)), column});
    block.empty = false;
  }

  static char display(char c) {
    return static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  }

  // Letters that are words: all but G and M (codes), N (line number) and O (control flow).
  static constexpr std::array<bool, 26> kIsWord = [] {
    std::array<bool, 26> table{};
    for (const char w : std::string_view("abcdefhijklpqrstuvwxyz")) table[w - 'a'] = true;
    return table;
  }();

  // The value of the word in `slot` (its letter's), which the line may give once.
  void read_word(Block& block, int slot, int column) {
    std::optional<Word>& word = block.words[static_cast<std::size_t>(slot)];
    if (word) {
      const char letter = slot == 'g' - 'a' ? '@' : slot == 'm' - 'a' ? '^' : 'a' + slot;
      fail(column, std::string("multiple ") + display(letter) + " words on one line");
    }
    word = Word{read_real(), column};
    if (!std::isfinite(word->value)) fail(column, "calculation resulted in infinity or NaN");
    block.letters |= 1u << slot;
    block.empty = false;
  }

  [[noreturn]] void fail(int column, const std::string& message) const {
    throw SyntaxError{column, message};
  }
  [[noreturn, gnu::cold, gnu::noinline]] void fail_code_range(char letter, double value,
                                                              int column) const {
    fail(column, std::string(1, display(letter)) + written_number(value) +
                     " is out of range: G and M codes are below " + written_number(kMaxCodeNumber));
  }
  // A comment's `text`, starting at `column`, holds no NUL byte.
  void refuse_nul_in(const std::string& text, int column) const {
    const std::size_t nul = text.find('\0');
    if (nul != std::string::npos) fail(column + static_cast<int>(nul), "NUL byte in the line");
  }
  // A value must be finite (rs274: "calculation resulted in 'infinity'").
  double finite(double value, int column) const {
    if (!std::isfinite(value)) fail(column, "calculation resulted in infinity or NaN");
    return value;
  }

  // Counts the nesting of values inside values while one is read.
  class NestingGuard {
   public:
    NestingGuard(Reader& reader, int column) : reader_(reader) {
      if (++reader_.nesting_ > kMaxValueNesting) {
        reader_.fail(column, "value nested deeper than " + std::to_string(kMaxValueNesting) +
                                 " levels (brackets, signs, # indirections or functions)");
      }
    }
    ~NestingGuard() { --reader_.nesting_; }
    NestingGuard(const NestingGuard&) = delete;
    NestingGuard& operator=(const NestingGuard&) = delete;

   private:
    Reader& reader_;
  };

  bool at_end() const { return pos_ >= line_.size(); }
  void skip_space() {
    std::size_t at = pos_;
    while (is_blank(data_[at])) ++at;
    pos_ = at;
  }
  // The next character, lower case; 0 at the end of the line.
  char peek() {
    skip_space();
    return lower(data_[pos_]);
  }
  bool accept(char c) {
    if (peek() != c) return false;
    ++pos_;
    return true;
  }
  // A word of letters (operator or function name), spaces between letters ignored.
  bool accept_word(std::string_view word) {
    const std::size_t saved = pos_;
    for (const char expected : word) {
      if (peek() != expected) {
        pos_ = saved;
        return false;
      }
      ++pos_;
    }
    return true;
  }

  std::string read_comment() {
    const int column = static_cast<int>(pos_) + 1;
    const std::size_t close = line_.find(')', pos_ + 1);
    if (close == std::string::npos) fail(column, "unclosed comment");
    const std::size_t open = line_.find('(', pos_ + 1);
    if (open != std::string::npos && open < close)
      fail(static_cast<int>(open) + 1, "nested comment");
    std::string text(line_.substr(pos_ + 1, close - pos_ - 1));
    refuse_nul_in(text, column + 1);
    pos_ = close + 1;
    return text;
  }

  std::string read_digits(int column) {
    std::string digits;
    while (true) {
      const char c = peek();
      if (!is_digit(c)) break;
      digits += c;
      ++pos_;
    }
    if (digits.empty()) fail(column, "bad format of line number");
    return digits;
  }

  // A number with spaces inside ("1 0 . 5" is 10.5, as LinuxCNC reads it), or too long for the
  // fast path: strtod's rounding through from_chars.
  [[gnu::noinline]] double read_spaced_or_long_number() {
    const int column = static_cast<int>(pos_) + 1;
    char text[64];
    std::size_t length = 0;
    int characters = 0;
    bool dot = false;
    while (pos_ < line_.size()) {
      const char c = line_[pos_];
      if (is_digit(c) || (c == '.' && !dot)) {
        if (length == sizeof text) fail(column, "number too long");
        text[length++] = c;
        dot = dot || c == '.';
        ++characters;
      } else if (c != ' ' && c != '\t') {
        break;
      }
      ++pos_;
    }
    if (characters == 0 || (characters == 1 && dot)) fail(column, "bad number format");
    double value = 0.0;
    std::from_chars(text, text + length, value);
    return value;
  }

  // A value: a plain number, maybe negative, read with the position in a register; anything
  // else (expressions, parameters, functions, signs, numbers with spaces) as below.
  double read_real() {
    const char* p = data_ + pos_;
    while (is_blank(*p)) ++p;
    const bool negative = *p == '-';
    if (negative) {
      ++p;
      while (is_blank(*p)) ++p;
    }
    double value = 0.0;
    if (const char* end = scan_plain_number(p, value)) {
      pos_ = static_cast<std::size_t>(end - data_);
      return negative ? -value : value;
    }
    return read_other_real();
  }

  // Everything but a plain number: signs, numbers with spaces inside, expressions, parameters
  // and functions; kept out of read_real so that stays small.
  [[gnu::noinline]] double read_other_real() {
    const char c = peek();
    const NestingGuard nesting(*this, static_cast<int>(pos_) + 1);
    if (c == '-') {
      ++pos_;
      return -read_real();
    }
    if (is_digit(c) || c == '.') return read_spaced_or_long_number();
    const int column = static_cast<int>(pos_) + 1;
    if (c == '[') {
      ++pos_;
      return read_expression();
    }
    if (c == '#') {
      ++pos_;
      return read_parameter_value(column);
    }
    if (c == '+') {
      ++pos_;
      return read_real();
    }
    if (is_alpha(c)) return read_function(column);
    if (c == 0) fail(column, "a value is missing at the end of the line");
    fail(column, std::string("bad number format: '") + line_[pos_] + "'");
  }

  std::string read_name(int column) {
    // After '<': up to '>', spaces removed, lower case.
    std::string name;
    while (!at_end() && line_[pos_] != '>') {
      const char c = line_[pos_++];
      if (c != ' ' && c != '\t')
        name += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    }
    if (at_end()) fail(column, "named parameter not terminated by '>'");
    ++pos_;
    if (name.empty()) fail(column, "empty parameter name");
    return name;
  }

  int read_parameter_number(int column) {
    const double value = read_real();
    const double rounded = std::round(value);
    // Compared as doubles: a number beyond int must not reach the conversion.
    if (!(std::abs(value - rounded) <= 1e-4 && rounded >= 1.0 &&
          rounded < static_cast<double>(Parameters::kCount))) {
      fail(column, "parameter number " + written_number(value) + " out of range (1 to " +
                       std::to_string(Parameters::kCount - 1) + ")");
    }
    return static_cast<int>(rounded);
  }

  double read_parameter_value(int column) {
    if (peek() == '<') {
      ++pos_;
      const std::string name = read_name(column);
      const std::optional<double> value = parameters_.named(name);
      if (!value && Parameters::read_only(name)) {
        fail(column, "#<" + name +
                         "> is not known here: it would be the [value] of the endsub of the "
                         "subroutine defined last, which LinuxCNC reads in passing and pkm does "
                         "not; read it after a call returns");
      }
      if (!value) fail(column, "named parameter #<" + name + "> not defined");
      return *value;
    }
    return parameters_.numbered(read_parameter_number(column));
  }

  Assignment read_assignment(int column) {
    ++pos_;  // '#'
    Assignment assignment;
    assignment.column = column;
    if (peek() == '<') {
      ++pos_;
      assignment.name = read_name(column);
    } else {
      assignment.number = read_parameter_number(column);
    }
    if (!accept('=')) fail(static_cast<int>(pos_) + 1, "equal sign missing in parameter setting");
    assignment.value = read_real();
    return assignment;
  }

  double read_function(int column) {
    std::string name;
    for (const std::string_view candidate : kFunctionNames) {
      if (accept_word(candidate)) {
        name = candidate;  // no name is a prefix of another, so the first match is the one
        break;
      }
    }
    if (name.empty()) fail(column, "unknown word or function where a value is expected");
    if (peek() != '[') fail(static_cast<int>(pos_) + 1, "left bracket missing after " + name);
    ++pos_;
    if (name == "exists") return read_exists(column);
    return evaluate_function(name, read_expression(), column);
  }

  // EXISTS[#<name>] is 1 when the name is defined; EXISTS[#n] (n any value: 5, #1, [expr]) is 1
  // when n is a parameter number (1 to 5601), as LinuxCNC reads it; either is 0 otherwise.
  double read_exists(int column) {
    const int at = static_cast<int>(pos_) + 1;
    if (!accept('#')) fail(at, "EXISTS needs a parameter: #<name> or #number");
    double found = 0.0;
    if (accept('<')) {
      found = parameters_.exists(read_name(column)) ? 1.0 : 0.0;
    } else {
      const double number = read_real();
      const double rounded = std::round(number);
      if (!(std::abs(number - rounded) <= 1e-4))
        fail(at, "parameter number " + written_number(number) + " in EXISTS is not a whole number");
      found = rounded >= 1.0 && rounded < static_cast<double>(Parameters::kCount) ? 1.0 : 0.0;
    }
    if (!accept(']')) fail(static_cast<int>(pos_) + 1, "right bracket missing after EXISTS");
    return found;
  }

  // NAME[argument] read up to its closing bracket; ATAN reads its second argument here.
  double evaluate_function(const std::string& name, double argument, int column) {
    if (name != "atan") return apply_function(name, argument, column);
    if (!accept('/')) fail(static_cast<int>(pos_) + 1, "slash missing after first ATAN argument");
    if (!accept('['))
      fail(static_cast<int>(pos_) + 1, "left bracket missing after slash with ATAN");
    const double second = read_expression();
    return finite(atan_degrees(argument, second), column);
  }

  Operator read_operator() {
    const char c = peek();
    switch (c) {
      case '*':
        ++pos_;
        if (peek() == '*') {
          ++pos_;
          return Operator::power;
        }
        return Operator::times;
      case '/':
        ++pos_;
        return Operator::divide;
      case '+':
        ++pos_;
        return Operator::plus;
      case '-':
        ++pos_;
        return Operator::minus;
      default:
        break;
    }
    for (const auto& [word, op] : kOperatorWords) {
      if (accept_word(word)) return op;
    }
    return Operator::none;
  }

  // After '[': operands and binary operators up to the matching ']', evaluated with LinuxCNC's
  // precedence, left to right within a level.
  double read_expression() {
    const int column = static_cast<int>(pos_);
    ExpressionStack expression(read_real());
    while (true) {
      if (peek() == ']') {
        ++pos_;
        break;
      }
      if (at_end()) fail(column, "unclosed expression: ']' missing");
      const int op_column = static_cast<int>(pos_) + 1;
      const Operator op = read_operator();
      if (op == Operator::none) fail(op_column, "unknown operation in expression");
      expression.push_operator(op, op_column);
      expression.push_value(read_real());
    }
    return expression.result();
  }

  OWord read_o_word(int column) {
    ++pos_;  // 'o'
    OWord o;
    o.column = column;
    if (peek() == '<') {
      ++pos_;
      o.label = "<" + read_name(column) + ">";
    } else if (peek() == '[' || peek() == '#') {
      // A computed number: o[expr], or a parameter's value (o#1, o#<name>), as LinuxCNC reads it.
      const double number = read_real();
      // Compared as a double: a number beyond long must not reach the conversion.
      if (!(std::abs(number) < kMaxONumber)) {
        fail(column, "O-word number " + written_number(number) + " out of range (below " +
                         written_number(kMaxONumber) + ")");
      }
      o.label = std::to_string(std::lround(number));
    } else {
      o.label = read_digits(column);
      o.label.erase(0, std::min(o.label.find_first_not_of('0'), o.label.size() - 1));
    }
    for (const std::string_view keyword : kOKeywords) {
      if (accept_word(keyword)) {
        o.keyword = keyword;
        break;
      }
    }
    if (o.keyword.empty()) {
      // A bare number is a Fanuc-style program number: the main program's, or the start of a
      // subprogram that M98 calls and M99 ends.
      // O<name> alone names the program, as a number does (LinuxCNC's named programs).
      const char rest = peek();
      if (rest != 0 && rest != '(' && rest != ';') {
        fail(static_cast<int>(pos_) + 1, "unknown O-word keyword");
      }
      o.keyword = kProgramNumberKeyword;
      return o;
    }
    if (o.keyword == "call") {
      // Comments may stand between the arguments (LinuxCNC's flowsnake.ngc has one).
      for (char next = peek(); next == '[' || next == '('; next = peek()) {
        if (next == '(') {
          read_comment();
          continue;
        }
        ++pos_;
        o.arguments.push_back(read_expression());
      }
    } else if (peek() == '[') {
      ++pos_;
      o.value = read_expression();
    }
    return o;
  }

  std::string_view line_;
  const char* data_;  // line_.data(), a NUL after its last character
  const Parameters& parameters_;
  std::size_t pos_ = 0;
  int nesting_ = 0;  // values being read inside one another (NestingGuard)
};

}  // namespace

void read_block(std::string_view line, const Parameters& parameters, Block& block) {
  if (line.data()[line.size()] != '\0') {
    throw std::invalid_argument("read_block: the line must be followed by a NUL");
  }
  Reader(line, parameters).read(block);
}

Block read_block(const std::string& line, const Parameters& parameters) {
  Block block;
  read_block(std::string_view(line), parameters, block);
  return block;
}

std::string o_word_keyword(std::string_view line, std::string* label, bool* with_value) {
  // Letters and digits with spaces, tabs and comments removed, lower case.
  std::string compact;
  for (std::size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (c == '(') {
      const std::size_t close = line.find(')', i);
      if (close == std::string::npos) break;
      i = close;
      continue;
    }
    if (c == ';') break;
    if (c == ' ' || c == '\t' || c == '\r') continue;
    compact += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  }
  std::size_t pos = 0;
  if (pos < compact.size() && compact[pos] == '/') ++pos;
  const auto skip_digits = [&] {
    while (pos < compact.size() && std::isdigit(static_cast<unsigned char>(compact[pos]))) ++pos;
  };
  if (pos < compact.size() && compact[pos] == 'n') {
    ++pos;
    skip_digits();
    if (pos < compact.size() && compact[pos] == '.') {
      ++pos;
      skip_digits();
    }
  }
  if (pos >= compact.size() || compact[pos] != 'o') return {};
  ++pos;
  std::string name;
  if (pos < compact.size() && compact[pos] == '<') {
    const std::size_t close = compact.find('>', pos);
    if (close == std::string::npos) return {};
    name = compact.substr(pos, close - pos + 1);
    pos = close + 1;
  } else {
    const std::size_t start = pos;
    while (pos < compact.size() && std::isdigit(static_cast<unsigned char>(compact[pos]))) ++pos;
    name = compact.substr(start, pos - start);
    name.erase(0, std::min(name.find_first_not_of('0'), name.size() == 0 ? 0 : name.size() - 1));
  }
  for (const std::string_view keyword : kOKeywords) {
    if (compact.compare(pos, keyword.size(), keyword) == 0) {
      // Only a value may follow the keyword ("endwhileXYZ" is no endwhile: the reader refuses
      // it when it runs, and skipping must not take it for one either).
      const std::size_t after = pos + keyword.size();
      if (after < compact.size() && compact[after] != '[') return {};
      if (label != nullptr) *label = name;
      if (with_value != nullptr) *with_value = after < compact.size();
      return std::string(keyword);
    }
  }
  if (pos == compact.size() && !name.empty()) {
    if (label != nullptr) *label = name;
    return std::string(kProgramNumberKeyword);
  }
  return {};
}

}  // namespace pkm::gcode
