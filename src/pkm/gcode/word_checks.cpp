// The words of a block: its codes sorted by modal group (at most one of each), words no code
// uses refused as rs274 refuses them, numbers checked against the range of what they index.
#include <cctype>
#include <string_view>

#include "pkm/gcode/interpreter_state.hpp"

namespace pkm::gcode {

void Interpreter::State::group_codes(const Block& block) {
  g_by_group.clear();
  m_by_group.clear();
  for (const Code& code : block.g_codes) {
    const int group = g_group(code.tenths);
    if (group < 0) refuse_g_code(code);
    const Code* slot = g_by_group[group];
    if (!slot) {
      g_by_group.set(group, code);
      continue;
    }
    if (group == 1 && (slot->tenths == 800 || code.tenths == 800)) {
      // "G80 G0": the cycle ends and the other motion mode takes over, as LinuxCNC allows.
      if (slot->tenths == 800) g_by_group.set(group, code);
      cycle_series = false;
      continue;
    }
    if (group == 0) fail(code.column, "two non-modal G codes on one line");
    fail(code.column, "two G codes of one modal group: " + code_name('G', slot->tenths) + " and " +
                          code_name('G', code.tenths));
  }
  for (const Code& code : block.m_codes) {
    int group = m_group(code.tenths);
    if (group < 0) refuse_unknown_m_code(code);
    if (group == 8 && m_by_group[8] && (code.tenths == 70 || code.tenths == 80) &&
        (m_by_group[8]->tenths == 70 || m_by_group[8]->tenths == 80)) {
      group = 11;  // M7 and M8 may share a line
    }
    if (const Code* slot = m_by_group[group]) {
      fail(code.column, "two M codes of one modal group: " + code_name('M', slot->tenths) +
                            " and " + code_name('M', code.tenths));
    }
    m_by_group.set(group, code);
  }
}

void Interpreter::State::refuse_unknown_m_code(const Code& code) const {
  // LinuxCNC runs such a code only through a remap in its INI file (tests/remap/remap-reentry's
  // M405 moves the machine), which pkmkit cannot know; its rs274 refuses it too. Passing it on
  // made motion that differed from the machine's with exit status 0.
  const std::string name = code_name('M', code.tenths);
  const std::string what = code.tenths > 1990
                               ? " is above M199: LinuxCNC runs it only as a remap of its INI file"
                               : " is not a LinuxCNC M-code (user M-codes are M100-M199)";
  fail(code.column, name + what +
                        ", whose meaning pkmkit cannot know; write what it does as G-code (a "
                        "pen's down and up as Z moves, which pkm post turns into the machine's "
                        "pen lines) or remove it");
}

void Interpreter::State::refuse_g_code(const Code& code) const {
  const int tenths = code.tenths;
  if (tenths == 700 || tenths == 710 || tenths == 711 || tenths == 712 || tenths == 720 ||
      tenths == 721 || tenths == 722) {
    fail(code.column, code_name('G', tenths) +
                          (tenths == 700 ? " (lathe finishing cycle)" : " (lathe roughing cycle)") +
                          " is not supported: give its passes as G0/G1 moves (G70, G71, G72 "
                          "and their .1/.2 forms are refused)");
  }
  fail(code.column, "unknown G code " + code_name('G', tenths));
}

void Interpreter::State::require_word_in_range(const Block& block, char letter, double low,
                                               double high, const std::string& what) const {
  const auto& word = block.word(letter);
  if (!word || (word->value >= low && word->value <= high)) return;
  fail(word->column, std::string(1, static_cast<char>(std::toupper(letter))) +
                         written_number(word->value) + " is out of range: " + what + " " +
                         written_number(low) + " to " + written_number(high));
}

namespace {
// The word letters and the codes that use them (rs274's check of "other" words), known from the
// block: `n` its non-modal G code, `m` the motion it makes (its own or the modal one), `g64`
// whether it sets G64 and `user_m` whether it holds a user M code (M100-M199).
struct WordUsers {
  int n = -1, m = -1;
  bool g64 = false, user_m = false;
  int m5 = -1, m6 = -1, m7 = -1, m9 = -1;  // codes of M groups 5, 6, 7 and 9, or -1
  bool arc() const { return m == 20 || m == 30; }
  bool cycle() const { return m >= 730 && m != 800; }
  bool threading() const { return m == 760; }  // G76
};

// The message refusing `letter`, or nullptr when a code of the block uses it.
const char* unused_word_message(char letter, const WordUsers& u) {
  switch (letter) {
    case 'e':
      if (u.threading() || (u.m5 >= 660 && u.m5 <= 680)) return nullptr;
      return "E word with no G76, M66, M67 or M68 to use it (a number such as 1e-05 is not "
             "G-code: X1e-05 reads as X1 and an E word)";
    case 'i':
    case 'j':
      if (u.arc() || u.n == 100 || u.threading() || (letter == 'i' && u.m == 331)) return nullptr;
      return letter == 'i' ? "I word with no G2, G3, G10, G33.1 or G76 to use it"
                           : "J word with no G2, G3, G10 or G76 to use it";
    case 'k':
      if (u.arc() || u.m == 330 || u.m == 331 || u.threading()) return nullptr;
      return "K word with no G2, G3, G33, G33.1 or G76 to use it";
    case 'h':
      return nullptr;  // checked by refuse_unused_words: it needs the G43 of group 8
    case 'l':
      if (u.n == 100 || u.cycle() || u.m5 == 660) return nullptr;
      return "L word with no G10, cutter compensation, canned cycle or M66 to use it";
    case 'p':
      if (u.arc() || u.n == 40 || u.n == 100 || u.g64 || u.m == 820 || u.m == 860 || u.m == 880 ||
          u.m == 890 || u.m == 840 || u.m == 740 || u.threading() || u.user_m || u.m7 == 190 ||
          (u.m9 >= 500 && u.m9 <= 530) || (u.m5 >= 620 && u.m5 <= 660)) {
        return nullptr;
      }
      return "P word with no G2, G3, G4, G10, G64, G74, G76, G82, G84, G86, G88, G89, M19, "
             "M50-M53, M62-M66 or user M code to use it";
    case 'q':
      if (u.n == 100 || u.g64 || u.m == 730 || u.m == 830 || u.threading() || u.user_m ||
          u.m6 == 610 || (u.m5 >= 660 && u.m5 <= 680) || u.m7 == 190) {
        return nullptr;
      }
      return "Q word with no G10, G64, G73, G76, G83, M19, M61, M66, M67, M68 or user M code to "
             "use "
             "it";
    case 'r':
      if (u.arc() || u.cycle() || u.n == 100 || u.threading() || u.m7 == 190) return nullptr;
      return "R word with no G code or M19 to use it";
    default:
      return nullptr;
  }
}
}  // namespace

void Interpreter::State::refuse_unused_words(const Block& block) const {
  constexpr std::uint32_t kChecked =
      (1u << ('e' - 'a')) | (1u << ('h' - 'a')) | (1u << ('i' - 'a')) | (1u << ('j' - 'a')) |
      (1u << ('k' - 'a')) | (1u << ('l' - 'a')) | (1u << ('p' - 'a')) | (1u << ('q' - 'a')) |
      (1u << ('r' - 'a'));
  if ((block.letters & kChecked) == 0) return;
  WordUsers users;
  users.n = g_by_group[0] ? g_by_group[0]->tenths : -1;
  // G10, G28, G30, G52 and G92 take the axis words: they make no motion of the modal mode.
  users.m = block_motion(block);
  users.g64 = g_by_group[13] && g_by_group[13]->tenths == 640;
  users.user_m = m_by_group[10] != nullptr;
  users.m5 = m_by_group[5] ? m_by_group[5]->tenths : -1;
  users.m6 = m_by_group[6] ? m_by_group[6]->tenths : -1;
  users.m7 = m_by_group[7] ? m_by_group[7]->tenths : -1;
  users.m9 = m_by_group[9] ? m_by_group[9]->tenths : -1;
  for (const char letter : std::string_view("ehijklpqr")) {
    const auto& word = block.word(letter);
    if (!word) continue;
    const bool tool_length_h =
        g_by_group[8] && (g_by_group[8]->tenths == 430 || g_by_group[8]->tenths == 432);
    if (letter == 'h' && !tool_length_h && !users.threading()) {
      fail(word->column, "H word with no G43, G43.2 or G76 to use it");
    }
    if (letter == 'l' && g_by_group[7]) continue;  // cutter compensation's tool orientation
    if (const char* message = unused_word_message(letter, users)) fail(word->column, message);
  }
}

int Interpreter::State::block_motion(const Block& block) const {
  if (g_by_group[1]) return g_by_group[1]->tenths;
  const int n = g_by_group[0] ? g_by_group[0]->tenths : -1;
  // G10, G28, G30, G52 and G92 take the axis words: they make no motion of the modal mode.
  const bool axes_taken = n == 100 || n == 280 || n == 300 || n == 520 || n == 920;
  const bool has_axis = (block.letters & (kAxisSlots | kPolarSlots)) != 0;
  return has_axis && !axes_taken ? motion : -1;
}

void Interpreter::State::refuse_motion_without_axes(const Block& block) const {
  const Code* const code = g_by_group[1];
  if (code == nullptr || (block.letters & (kAxisSlots | kPolarSlots)) != 0) return;
  // rs274 lets G0 to G3 go without axis words (no motion, or an arc's own error), and G80 needs
  // none; every other motion code of the block needs an end point or a hole.
  const int m = code->tenths;
  if (m == 0 || m == 10 || m == 20 || m == 30 || m == 800) return;
  const bool cycle = m == 730 || m == 740 || (m >= 810 && m <= 890);
  fail(code->column, "all axes missing with " + code_name('G', m) +
                         (cycle ? ": give the hole's position" : ": give the end point"));
}

void Interpreter::State::check_synchronised_words(const Block& block) const {
  const int m = block_motion(block);
  if (m != 330 && m != 331 && m != 760) return;
  const int column = g_by_group[1] ? g_by_group[1]->column : 1;
  const std::string name = code_name('G', m);
  if (m == 760) {
    if (!block.has('p')) fail(column, "P word (the thread's pitch) missing with G76");
    if (!(block.value('p') > 0.0)) {
      fail(block.word('p')->column, "G76 P (the thread's pitch) must be positive");
    }
    if (!block.has('i') || !block.has('j') || !block.has('k')) {
      fail(column, "I, J or K word missing with G76 (thread depth I, first cut J, full depth K)");
    }
    return;
  }
  if (!block.has('k')) fail(column, "K word (the pitch, per revolution) missing with " + name);
  if (block.has('f')) {
    fail(block.word('f')->column,
         "F word used with " + name + ": its feed is the pitch K times the spindle speed");
  }
}

void Interpreter::State::missing_feed(int column) const {
  if (feed_mode == FeedMode::inverse_time) {
    fail(column, "F word missing with inverse time (G93) motion");
  }
  if (feed_mode == FeedMode::units_per_revolution && feed > 0.0) {
    fail(column,
         "cannot feed with zero spindle speed in feed per revolution mode (G95): give "
         "an S word");
  }
  fail(column, "cannot do a feed move with zero feed rate: give an F word");
}

}  // namespace pkm::gcode
