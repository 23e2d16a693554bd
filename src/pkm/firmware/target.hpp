// One firmware target of `pkm export TARGET` and `pkm import TARGET` (docs/firmware.md): its
// name, the forms its kinematics take, its writer and its reader. Each target lives in its own
// files (fluidnc*.cpp, klipper*.cpp, rrf*.cpp, grblhal*.cpp, marlin*.cpp); targets() lists them.
#pragma once

#include <functional>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "pkm/firmware/firmware_machine.hpp"
#include "pkm/machine/imported_machine.hpp"

namespace pkm::firmware {

struct ExportContext {
  std::string pkmkit_version;  // "0.9.0"
  std::string machine_source;  // the machine file's path as given
  // --approximate: a target whose own settings hold less than its form (one radius for three
  // towers) writes its nearest machine with the cost, as firmware_machine does for a form's losses.
  bool approximate = false;
};

// The lines every exported file opens with, without their comment marks: what machine and
// which pkmkit version it came from, the form, and for an approximation its cost.
std::vector<std::string> header_lines(const FirmwareMachine& machine, const ExportContext& context);
// The same lines, each behind `mark` ("# ", "; ", "// ") and ended by a line break.
std::string header_comment(const FirmwareMachine& machine, const ExportContext& context,
                           std::string_view mark);

struct ExportedFile {
  std::string text;
  std::vector<std::string> warnings;  // what the user must act on (a setting to compile in)
  // Set where the target wrote a nearer machine than the one it was given (ExportContext's
  // approximate): what that costs.
  std::optional<ApproximationCost> cost;
};

// A firmware file that cannot be read: file:line[:key] and why.
class FirmwareFileError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct Target {
  std::string name;       // "fluidnc", as on the command line
  std::string file_kind;  // "config.yaml", "printer.cfg", "config.g", "$ settings", ...
  std::vector<FormKind> forms;
  std::function<ExportedFile(const FirmwareMachine&, const ExportContext&)> write;
  // The machine a firmware file describes; `source` names the file in errors and notes.
  std::function<machine::ImportedMachine(std::string_view text, const std::string& source)> read;
};

const std::vector<Target>& targets();
// The target called `name`; throws std::invalid_argument naming the known ones.
const Target& target(std::string_view name);

}  // namespace pkm::firmware
