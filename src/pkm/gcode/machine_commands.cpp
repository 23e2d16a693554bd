#include "pkm/gcode/machine_commands.hpp"

#include <charconv>
#include <cstdio>

namespace pkm::gcode {

int machine_command_m_number(const std::string& text) {
  int number = -1;
  if (text.size() < 2 || text[0] != 'M') return -1;
  const auto [end, error] = std::from_chars(text.data() + 1, text.data() + text.size(), number);
  if (error != std::errc() || (end != text.data() + text.size() && *end != ' ')) return -1;
  return number;
}

std::string machine_command_text(const Canon& canon) {
  switch (canon.kind) {
    case CanonKind::program_stop:
      return canon.integer == 60 ? "M60" : "M0";
    case CanonKind::optional_stop:
      return "M1";
    case CanonKind::select_tool:
      return "T" + std::to_string(canon.integer);
    case CanonKind::change_tool:
      return "M6";
    case CanonKind::orient_spindle: {  // `value` holds the INI's offset too: 0 unless asked
      char text[64];
      std::snprintf(text, sizeof text, "M19 R%.10g P%d", canon.value, canon.integer);
      return text;
    }
    case CanonKind::wait_orient_spindle: {  // M19 with Q alone waits, orienting nothing
      char text[48];
      std::snprintf(text, sizeof text, "M19 Q%.10g", canon.value);
      return text;
    }
    case CanonKind::event: {
      // The interpreter's events of these codes are their text with their words; other events
      // (a pen's command lines, InterpreterOptions::event_lines) are not the machine's commands.
      const int number = machine_command_m_number(canon.text);
      const bool known = (number >= 48 && number <= 53) || (number >= 62 && number <= 68) ||
                         (number >= 100 && number <= 199);
      return known ? canon.text : "";
    }
    default:
      return "";
  }
}

}  // namespace pkm::gcode
