// Reading RepRapFirmware's config.g (docs/firmware-rrf.md): its G/M command lines, and the linear
// delta machine its M669 K3 / M665 / M666 / M92 / M203 / M201 / M208 lines describe (a rotary
// delta, M669 K10: rrf_rotary.cpp; a Hangprinter, M669 K6: rrf_hangprinter.cpp).
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "pkm/firmware/target.hpp"

namespace pkm::firmware {

// One parameter of a command: its letter and the text after it ("300:300:300", "\"name\"").
struct RrfWord {
  char letter = 0;
  std::string value;
};

// One command line of config.g: "M665" and its parameters; `line` counts from 1.
struct RrfCommand {
  int line = 0;
  std::string code;
  std::vector<RrfWord> words;
};

// The G, M and T command lines of `text` (comments after `;` dropped). Lines that are not one of
// these (RRF's meta commands: if, var, set, echo, ...) are returned in `skipped` as
// "line N: text".
std::vector<RrfCommand> rrf_commands(std::string_view text, std::vector<std::string>& skipped);

// A parameter's number or colon-separated list ("1:2:3"); FirmwareFileError "file:line: M669 A:
// '..' is not a number list" otherwise.
std::vector<double> rrf_numbers(const RrfCommand& command, const RrfWord& word,
                                const std::string& source);

// The machine config.g describes. Throws FirmwareFileError ("file:line: key: why") for a value
// that is not a number, a missing setting, or kinematics pkmkit cannot hold.
machine::ImportedMachine read_rrf_config(std::string_view text, const std::string& source);

}  // namespace pkm::firmware
