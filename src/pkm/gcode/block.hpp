// One line of RS274/NGC read into its words, as LinuxCNC reads it: case-insensitive, spaces and
// tabs ignored outside comments, expressions and parameters evaluated when the line is read
// (parameter assignments take effect after the whole line is read).
#pragma once

#include <array>
#include <bit>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "pkm/gcode/gcode_error.hpp"
#include "pkm/gcode/parameters.hpp"

namespace pkm::gcode {

struct Comment {
  std::string text;  // as written, without the parentheses
  int column = 0;
};

struct Assignment {
  int number = 0;    // numbered parameter, or 0
  std::string name;  // named parameter (lower case), or empty
  double value = 0.0;
  int column = 0;
};

struct Word {
  double value = 0.0;
  int column = 0;
};

// A G or M code times ten, so G64.1 is 641 and G1 is 10.
struct Code {
  int tenths = 0;
  int column = 0;
};

// The keyword of a bare O-number line (Fanuc's "O100"), which no O-word can spell.
inline constexpr std::string_view kProgramNumberKeyword = "O-number";

struct OWord {
  std::string label;    // "100" or "<name>" lower case, as written between o and the keyword
  std::string keyword;  // sub, endsub, call, return, do, while, endwhile, if, elseif, else,
                        // endif, repeat, endrepeat, break, continue, or kProgramNumberKeyword
  std::vector<double> arguments;  // call arguments
  std::optional<double> value;    // condition, repeat count, or return value
  int column = 0;
};

struct Block {
  bool empty = true;          // nothing but whitespace or comments
  bool block_delete = false;  // starts with '/'
  bool percent = false;       // a '%' line
  bool plain = true;          // words only: no codes, comments, assignments or O-word
  std::string n_label;        // digits of the N word as written, or empty
  std::array<std::optional<Word>, 26> words;  // letters other than G, M, N, O
  std::uint32_t letters = 0;                  // bit per slot of `words` in use
  std::vector<Code> g_codes;
  std::vector<Code> m_codes;
  std::vector<Comment> comments;
  std::vector<Assignment> assignments;
  std::optional<OWord> o_word;

  const std::optional<Word>& word(char letter) const { return words[letter - 'a']; }
  // Back to an empty block, keeping the vectors' storage (one Block serves every line).
  void clear() {
    empty = true;
    block_delete = false;
    percent = false;
    plain = true;
    n_label.clear();
    // Only the slots in use: most lines hold a few words of 26.
    for (std::uint32_t used = letters; used != 0; used &= used - 1) {
      words[static_cast<std::size_t>(std::countr_zero(used))].reset();
    }
    letters = 0;
    g_codes.clear();
    m_codes.clear();
    comments.clear();
    assignments.clear();
    o_word.reset();
  }
  bool has(char letter) const { return words[letter - 'a'].has_value(); }
  double value(char letter) const { return words[letter - 'a']->value; }
};

// The deepest a value may nest (brackets, signs, parameter indirections and functions inside one
// another): beyond it the reader refuses the line rather than recurse on.
inline constexpr int kMaxValueNesting = 100;
// The largest G or M code number the reader takes (G and M codes are below 10000).
inline constexpr double kMaxCodeNumber = 10000.0;

// Reads `line` (one physical line, without its line end). Throws SyntaxError with the column of
// the problem.
Block read_block(const std::string& line, const Parameters& parameters);
// The same into an existing block, reusing its storage. The line must be followed by a NUL
// (line.data()[line.size()] == '\0', as for a std::string): the reader scans up to it.
void read_block(std::string_view line, const Parameters& parameters, Block& block);

// The keyword of an O-word line (and its label), without evaluating anything: what control flow
// needs of the lines it skips. Empty when the line is no O-word line. `with_value`: whether a
// [value] follows the keyword.
std::string o_word_keyword(std::string_view line, std::string* label = nullptr,
                           bool* with_value = nullptr);

}  // namespace pkm::gcode
