// `pkm export grbl|grblhal`: the `$` settings that make a grbl-class controller drive a machine's
// joints as pkmkit's joint programs expect (docs/grbl.md): steps per unit, max rate, acceleration
// and max travel per axis ($100.., $110.., $120.., $130..), junction deviation ($11), positions
// reported in mm ($13=0), the motors kept enabled at rest ($1=255). Each line is one setting with
// its comment after it, as both firmwares accept it: grbl 1.1h strips comments and spaces before it
// reads a `$` line (protocol.c), grblHAL reads the number after `=` and stops at the comment
// (settings_store_setting).
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "pkm/machine/machine.hpp"

namespace pkm::post {

struct ControllerSetting {
  int number = 0;       // 100 for $100
  std::string value;    // as written: "80.000"
  std::string comment;  // without its parentheses
};

struct ControllerSettingsFile {
  std::vector<ControllerSetting> settings;  // in the order they are written
  // What the controller may not manage, with the numbers (a step rate beyond an AVR grbl's).
  std::vector<std::string> warnings;
  // One line per setting, "$100=80.000 (X = joint left: steps/mm)", each at most 80 characters.
  std::string text() const;
};

// The settings of `machine` for a controller of `kind`. Throws std::invalid_argument, naming the
// machine file, when the file has no [controller] table, when its kind is another, or when a
// joint's range in steps passes grbl's step counter (a 32-bit integer).
ControllerSettingsFile controller_settings(const machine::Machine& machine,
                                           machine::ControllerKind kind);

// `text` made safe inside a comment sent to grbl: grbl 1.1h's serial interrupt acts on ? ! ~ and on
// bytes above 0x7F (feed and spindle overrides) wherever they come, comments included, and a
// parenthesis or line break would end the comment: each becomes a plain character.
std::string grbl_comment_text(std::string_view text);

}  // namespace pkm::post
