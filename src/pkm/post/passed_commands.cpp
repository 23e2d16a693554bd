#include "pkm/post/passed_commands.hpp"

#include "pkm/gcode/machine_commands.hpp"

namespace pkm::post {

namespace {

// Which controllers have which commands (their G-code references: LinuxCNC's M-codes, Mach3's
// M-code list, grbl 1.1's gcode.c, grblHAL's M62-M68 "as per LinuxCNC" and its tool change).
struct Support {
  bool pallet_shuttle;  // M60
  bool tool_change;     // M6
  bool io;              // M62-M68
  bool user_m_codes;    // M100-M199, as programs or macros on the controller
  bool overrides;       // M48-M53
  bool orientation;     // M19
};

Support support_of(Dialect dialect) {
  switch (dialect) {
    case Dialect::linuxcnc:
      return {true, true, true, true, true, true};
    case Dialect::mach3:
      return {false, true, false, true, false, false};
    case Dialect::grbl:
      return {false, false, false, false, false, false};
    case Dialect::grblhal:
      return {false, true, true, false, false, false};
  }
  return {};
}

std::string others_with(bool Support::*has) {
  std::string names;
  for (const Dialect dialect :
       {Dialect::linuxcnc, Dialect::mach3, Dialect::grbl, Dialect::grblhal}) {
    if (!(support_of(dialect).*has)) continue;
    names += (names.empty() ? "" : " or ") + std::string(dialect_name(dialect));
  }
  return names;
}

PassedCommand carried_if(bool Support::*has, Dialect dialect, const std::string& line,
                         const std::string& what) {
  if (support_of(dialect).*has) return {line, "", ""};
  return {"",
          std::string(dialect_name(dialect)) + " has no " + what + " (" + line +
              "), and leaving it out would run the job differently: use --dialect " +
              others_with(has) + ", or take it out of the job",
          ""};
}

std::optional<PassedCommand> carried_or_refused(const std::string& text, Dialect dialect) {
  const int number = gcode::machine_command_m_number(text);
  if (number >= 48 && number <= 53) {
    if (support_of(dialect).overrides) return PassedCommand{text, "", ""};
    return PassedCommand{
        "", "",
        text + " (an override switch) left out: " + std::string(dialect_name(dialect)) +
            " has no such switch, and the joint program's motion is the same"};
  }
  if (number >= 62 && number <= 68) {
    return carried_if(&Support::io, dialect, text, "digital or analog I/O code");
  }
  if (number >= 100 && number <= 199) {
    return carried_if(&Support::user_m_codes, dialect, text, "user M-code");
  }
  return PassedCommand{text, "", ""};  // T, M0, M6...
}

}  // namespace

std::optional<PassedCommand> passed_command(const gcode::Canon& canon, Dialect dialect) {
  const std::string text = gcode::machine_command_text(canon);
  if (text.empty()) return std::nullopt;
  if (text == "M60") return carried_if(&Support::pallet_shuttle, dialect, text, "M60");
  if (text == "M6" && dialect == Dialect::grbl) {
    // grbl 1.1 refuses M6; its owners change tools by hand at a pause, which M0 gives.
    return PassedCommand{"M0 (M6: change the tool, then resume)", "",
                         "grbl 1.1 has no tool change: M6 written as M0, a pause to change the "
                         "tool by hand"};
  }
  if (text == "M6") return carried_if(&Support::tool_change, dialect, text, "tool change");
  if (text.rfind("M19 ", 0) == 0) {
    return carried_if(&Support::orientation, dialect, text, "spindle orientation");
  }
  if (text == "M1" && dialect == Dialect::grbl) {
    return PassedCommand{text, "",
                         "grbl 1.1 ignores M1 (optional stops are not supported): the machine "
                         "will not stop here; M0 pauses"};
  }
  return carried_or_refused(text, dialect);
}

}  // namespace pkm::post
