#include "pkm/gcode/modal_groups.hpp"

#include <initializer_list>

namespace pkm::gcode {

namespace {

// Tables indexed by the code times ten: a lookup per code of every block.
template <std::size_t Size>
struct GroupTable {
  std::array<std::int8_t, Size> group_of{};
  constexpr GroupTable() { group_of.fill(-1); }
  constexpr void assign(int group, std::initializer_list<int> codes) {
    for (const int tenths : codes) group_of[static_cast<std::size_t>(tenths)] = group;
  }
  int operator()(int tenths) const {
    return tenths >= 0 && static_cast<std::size_t>(tenths) < Size
               ? group_of[static_cast<std::size_t>(tenths)]
               : -1;
  }
};

constexpr GroupTable<1000> kGGroups = [] {
  GroupTable<1000> table;
  table.assign(0, {40, 100, 280, 281, 300, 301, 520, 530, 920, 921, 922, 923});
  table.assign(1, {0,   10,  20,  30,  330, 331, 382, 383, 384, 385, 730, 740,
                   760, 800, 810, 820, 830, 840, 850, 860, 870, 880, 890});
  table.assign(2, {170, 180, 190});
  table.assign(3, {900, 910});
  table.assign(4, {901, 911});
  table.assign(5, {930, 940, 950});
  table.assign(6, {200, 210});
  table.assign(7, {400, 410, 411, 420, 421});
  table.assign(8, {430, 431, 432, 490});
  table.assign(10, {980, 990});
  table.assign(12, {540, 550, 560, 570, 580, 590, 591, 592, 593});
  table.assign(13, {610, 611, 640});
  table.assign(14, {960, 970});
  table.assign(15, {70, 80});
  return table;
}();

constexpr GroupTable<2000> kMGroups = [] {
  GroupTable<2000> table;
  table.assign(4, {0, 10, 20, 300, 600, 980, 990});  // M98/M99: Fanuc-style subprograms
  table.assign(5, {620, 630, 640, 650, 660, 670, 680});
  table.assign(6, {60, 610});
  table.assign(7, {30, 40, 50, 190, 700, 710, 720, 730});  // M70-M73 as LinuxCNC groups them
  table.assign(8, {70, 80, 90});
  table.assign(9, {480, 490, 500, 510, 520, 530});
  for (int user = 1000; user <= 1990; ++user) table.group_of[static_cast<std::size_t>(user)] = 10;
  return table;
}();

}  // namespace

int g_group(int tenths) {
  return kGGroups(tenths);
}

int m_group(int tenths) {
  return kMGroups(tenths);
}

std::string code_name(char letter, int tenths) {
  std::string name(1, letter);
  name += std::to_string(tenths / 10);
  if (tenths % 10 != 0) name += "." + std::to_string(tenths % 10);
  return name;
}

}  // namespace pkm::gcode
