// The modal groups of G and M codes as LinuxCNC groups them (a block may hold at most one code of
// each), and the codes of one block sorted into them. Codes are times ten, as Code::tenths holds
// them (G33.1 is 331).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>

#include "pkm/gcode/block.hpp"

namespace pkm::gcode {

// The modal group of a G code, or -1 for one pkm does not know (LinuxCNC's numbering: 0 the
// non-modal codes, 1 motion, 2 plane, 3 distance, 4 arc distance, 5 feed mode, 6 units, 7 cutter
// compensation, 8 tool length, 10 retract, 12 coordinate system, 13 path control, 14 spindle
// speed mode, 15 lathe diameter mode).
int g_group(int tenths);
// The modal group of an M code, or -1 for one with no meaning here; M100-M199 (user codes) are
// group 10.
int m_group(int tenths);

// "G33.1" from 'G' and 331.
std::string code_name(char letter, int tenths);

// The codes of one block by modal group. One instance serves every block: starting a block
// clears a mask, not the slots (most blocks hold no code at all).
template <std::size_t Groups>
class CodesByGroup {
 public:
  const Code* operator[](int group) const {
    return (present_ >> group) & 1u ? &codes_[static_cast<std::size_t>(group)] : nullptr;
  }
  void set(int group, const Code& code) {
    codes_[static_cast<std::size_t>(group)] = code;
    present_ |= 1u << group;
  }
  void clear() { present_ = 0; }
  bool any() const { return present_ != 0; }

 private:
  static_assert(Groups <= 32);
  std::array<Code, Groups> codes_{};
  std::uint32_t present_ = 0;
};

}  // namespace pkm::gcode
