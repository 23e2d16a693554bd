#include "pkm/gcode/tool_table.hpp"

#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>

#include "pkm/gcode/gcode_error.hpp"
#include "pkm/text/text_file.hpp"

namespace pkm::gcode {

namespace {
// Largest number a tool table may hold (mm, inch or deg; tool and pocket numbers; the message
// says 1e6): beyond any tool, and small enough that offsets added to coordinates cannot overflow.
constexpr double kLargestValue = 1e6;
}  // namespace

ToolTable parse_tool_table(const std::string& text, const std::string& source_name,
                           LengthUnits units) {
  const double to_mm = units == LengthUnits::inch ? 25.4 : 1.0;
  ToolTable table;
  std::istringstream in(text);
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    const std::size_t semicolon = line.find(';');
    std::string comment;
    if (semicolon != std::string::npos) {
      comment = line.substr(semicolon + 1);
      line.resize(semicolon);
    }
    ToolEntry entry;
    entry.comment = comment;
    bool has_tool = false;
    std::size_t pos = 0;
    while (pos < line.size()) {
      const char c = static_cast<char>(std::toupper(static_cast<unsigned char>(line[pos])));
      if (c == ' ' || c == '\t' || c == '\r') {
        ++pos;
        continue;
      }
      const int column = static_cast<int>(pos) + 1;
      char* end = nullptr;
      const double value = std::strtod(line.c_str() + pos + 1, &end);
      if (end == line.c_str() + pos + 1) {
        throw GcodeError(source_name, number, column,
                         std::string("tool table: '") + line[pos] + "' needs a number");
      }
      if (!std::isfinite(value) || std::abs(value) > kLargestValue) {
        throw GcodeError(source_name, number, column,
                         std::string("tool table: ") +
                             line.substr(pos, static_cast<std::size_t>(end - line.c_str()) - pos) +
                             " must be a finite number of at most 1e6 in size");
      }
      if ((c == 'T' || c == 'P') && (value < 0.0 || value != std::floor(value))) {
        throw GcodeError(
            source_name, number, column,
            std::string("tool table: '") + line[pos] + "' needs a whole number 0 or above");
      }
      static constexpr std::string_view kAxisLetters = "XYZABCUVW";
      if (c == 'T') {
        entry.number = static_cast<int>(value);
        has_tool = true;
      } else if (c == 'P') {
        entry.pocket = static_cast<int>(value);
      } else if (c == 'D') {
        entry.diameter = value * to_mm;
      } else if (kAxisLetters.find(c) != std::string_view::npos) {
        const std::size_t axis = kAxisLetters.find(c);
        entry.offset[axis] = (axis < 3 || axis >= 6) ? value * to_mm : value;
      } else if (c == 'Q') {
        if (value < 0.0 || value > 9.0 || value != std::floor(value)) {
          throw GcodeError(source_name, number, column,
                           "tool table: Q (a lathe tool's orientation) must be a whole number "
                           "from 0 to 9");
        }
        entry.orientation = static_cast<int>(value);
      } else if (c != 'I' && c != 'J') {  // lathe tools' front and back angles: unused
        throw GcodeError(source_name, number, column,
                         std::string("tool table: unknown word '") + line[pos] + "'");
      }
      pos = static_cast<std::size_t>(end - line.c_str());
    }
    if (has_tool) table[entry.number] = entry;
  }
  return table;
}

ToolTable read_tool_table(const std::filesystem::path& path, LengthUnits units) {
  std::string text;
  try {
    text = text::read_text_file(path, text::kMaxDataFileBytes);
  } catch (const text::FileReadError& error) {
    throw GcodeError(path.string(), 0, 0, std::string("the tool table: ") + error.what());
  }
  return parse_tool_table(text, path.string(), units);
}

}  // namespace pkm::gcode
