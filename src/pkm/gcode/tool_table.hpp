// LinuxCNC tool tables (.tbl): one tool per line, "T1 P1 Z0.511 D0.125 ;comment".
#pragma once

#include <filesystem>
#include <map>
#include <string>

#include "pkm/gcode/canon.hpp"

namespace pkm::gcode {

struct ToolEntry {
  int number = 0;
  int pocket = 0;
  Position offset{};  // X Y Z A B C U V W offsets, mm (deg for A B C)
  double diameter = 0.0;
  // Q: a lathe tool's orientation, 1-8 (which of its sides and corners the tip's radius centre
  // lies off; cutter compensation moves the tool by it, as LinuxCNC does), 0 or 9 for none.
  int orientation = 0;
  std::string comment;
};

using ToolTable = std::map<int, ToolEntry>;

// Throws GcodeError (file:line:column) on a malformed line. `units` are those of the table's
// lengths, LinuxCNC's machine units: mm here; LinuxCNC's stand-alone rs274 reads them as inches.
ToolTable read_tool_table(const std::filesystem::path& path, LengthUnits units = LengthUnits::mm);
ToolTable parse_tool_table(const std::string& text, const std::string& source_name,
                           LengthUnits units = LengthUnits::mm);

}  // namespace pkm::gcode
