// The pieces of the grblhal target's files (grblhal.cpp, grblhal_read.cpp, grblhal_delta.cpp):
// `$N=value (comment)` lines written, a settings file scanned, its numbers read with their lines.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "pkm/firmware/target.hpp"

namespace pkm::firmware::grblhal {

// A value as grblHAL's read_float takes it: six decimals, at least three.
std::string value_text(double value);

// The lines of a settings file: comments (parentheses made brackets), `$N=V (what)` settings.
struct Lines {
  std::string text;
  void comment(std::string_view line);
  void setting(int number, double value, std::string_view what);
};

struct Setting {
  std::string value;  // as written, comments and spaces stripped
  int line = 0;
};

struct SettingsFile {
  std::string source;
  std::map<int, Setting> settings;
  std::map<char, Setting> g54;  // X Y Z words of a G10 L2 P1 line
  int last_line = 0;
  std::vector<std::string> ignored;  // "line 12: $H"
};

SettingsFile scan(std::string_view text, const std::string& source);
// Setting `number`, which the kinematics needs (`what` says why), a number above 0; a missing
// one fails at the file's last line.
double required(const SettingsFile& file, int number, const std::string& what);
// Setting `number` if the file has it (any finite number), else nothing.
std::optional<double> optional_number(const SettingsFile& file, int number);
// "settings not imported (...): $0, $22" for the settings outside `used`; the ignored lines.
void note_unused(const SettingsFile& file, const std::vector<int>& used,
                 std::vector<std::string>& notes);

// A rotary delta (delta.c) as `$` settings, and read back (grblhal_delta.cpp).
ExportedFile write_rotary_delta(const FirmwareMachine& machine, const ExportContext& context,
                                const kinematics::RotaryDeltaForm& form);
bool is_delta_file(const SettingsFile& file);
machine::ImportedMachine read_rotary_delta(const SettingsFile& file);

}  // namespace pkm::firmware::grblhal
