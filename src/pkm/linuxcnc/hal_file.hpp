// The lines of a LinuxCNC configuration's HAL files that decide a kinematics module's geometry:
// `loadrt` (with module parameters), `setp`, `sets` and `net`, after the INI substitutions
// ([SECTION]KEY) halcmd makes. HAL files come from [HAL] HALFILE (LIB: = LinuxCNC's hallib, a
// relative name looked up beside the INI, then in the hallib), HALCMD and POSTGUI_HALFILE. Tcl
// HAL files are read for their plain setp/sets/net lines; what is not understood is reported as a
// note, never guessed.
#pragma once

#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "pkm/linuxcnc/ini_file.hpp"

namespace pkm::linuxcnc {

// LinuxCNC's library of HAL files (the LIB: prefix), as Debian installs it.
inline const std::filesystem::path kDefaultHallib = "/usr/share/linuxcnc/hallib";

struct HalModule {
  std::string name;
  std::vector<std::string> parameters;  // "coordinates=xz", as written
  SourceLocation where;
};

// A constant a pin takes: from `setp PIN value`, or `sets SIGNAL value` of the signal it is on.
struct HalValue {
  std::string text;
  SourceLocation where;
  std::string how;  // "setp genhexkins.base.0.x" or "sets L (net L lineardeltakins.L ...)"
};

class HalConfig {
 public:
  // Every HAL file and command of the INI, in LinuxCNC's order. Throws ConfigError for a HAL file
  // that does not exist (at its HALFILE line) and for a [SECTION]KEY the INI does not have.
  static HalConfig read(const IniFile& ini, const std::filesystem::path& hallib = kDefaultHallib);

  const std::vector<HalModule>& modules() const { return modules_; }
  // The constant the pin is set to, if any (sets on its signal wins over setp, as in HAL where a
  // linked pin takes its signal's value).
  std::optional<HalValue> value_of(const std::string& pin) const;
  // The pin's value as a number: nullopt when it is never set; ConfigError at the setp/sets line
  // when the value is not a number.
  std::optional<double> number_of(const std::string& pin) const;
  // When the pin is on a signal that no `sets` gives a value: the other pins of that net (the
  // pin follows them at run time), e.g. "motion.tooloffset.z"; nullopt otherwise.
  std::optional<std::string> driven_by(const std::string& pin) const;
  // Lines of Tcl HAL files that may matter and were not read (Tcl variables, substitutions).
  struct UnreadLine {
    SourceLocation where;
    std::string text;
  };
  const std::vector<UnreadLine>& unread() const { return unread_; }
  // The Tcl HAL files read (for their plain lines only).
  const std::vector<std::string>& tcl_files() const { return tcl_files_; }

 private:
  void read_file(const std::filesystem::path& path, const IniFile& ini, bool tcl);
  void command(const std::vector<std::string>& words, const SourceLocation& where);

  std::vector<HalModule> modules_;
  std::map<std::string, HalValue> setp_;
  std::map<std::string, HalValue> sets_;
  std::map<std::string, std::string> signal_of_pin_;
  std::map<std::string, std::vector<std::string>> pins_of_signal_;
  std::vector<UnreadLine> unread_;
  std::vector<std::string> tcl_files_;
};

// `line` with every [SECTION]KEY (and [SECTION](KEY)) replaced by the INI's value, as halcmd -i
// does. Throws ConfigError at `where` when the INI lacks the key.
std::string substitute_ini_values(const std::string& line, const IniFile& ini,
                                  const SourceLocation& where);

}  // namespace pkm::linuxcnc
