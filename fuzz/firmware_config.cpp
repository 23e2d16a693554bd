// libFuzzer target: a firmware's configuration file read as `pkm import TARGET` reads it, the
// machine file loaded, and the machine exported to the same target again as `pkm export TARGET`
// writes it. The input's first byte picks the target (byte % 5, in targets() order: fluidnc,
// klipper, rrf, grblhal, marlin), the rest is the file's text. Oracles: no sanitizer report; no
// exception but FirmwareFileError (read), ImportedMachineError and MachineFileError other than a
// syntax error (machine_file_text: the reader's own TOML must parse) and ExportRefused (export);
// a machine that loads has finite joint limits and home; no non-finite number in the export; an
// export read back with the same target loads and exports again; and that second export is a
// fixed point: read back and exported once more, the same text (docs/firmware.md). The first
// export need not be one (its machine's name and numbers are rounded from the input's).
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "fuzz_support.hpp"
#include "pkm/firmware/target.hpp"
#include "pkm/machine/imported_machine.hpp"
#include "pkm/machine/machine.hpp"
#include "pkm/machine/machine_file_error.hpp"

namespace {

namespace firmware = pkm::firmware;
namespace machine = pkm::machine;

const firmware::ExportContext kContext{"fuzz", "fuzz.toml"};

void require_finite_machine(const machine::Machine& loaded) {
  for (const machine::JointSpec& joint : loaded.joints()) {
    pkm::fuzz::require_finite(joint.min, "a joint's lower limit");
    pkm::fuzz::require_finite(joint.max, "a joint's upper limit");
  }
  for (int i = 0; i < pkm::geometry::kPoseSize; ++i) {
    pkm::fuzz::require_finite(loaded.home().as_vector()[i], "the home pose");
  }
}

// The machine file of an imported machine, loaded; none where pkmkit refuses it with a located
// error. A syntax error is the reader's own TOML (its kinematics section) and fails the oracle.
std::optional<machine::Machine> load(const machine::ImportedMachine& imported) {
  std::string text;
  try {
    text = machine::machine_file_text(imported, "fuzz.toml");
  } catch (const machine::ImportedMachineError&) {
    return std::nullopt;
  } catch (const machine::MachineFileError& error) {
    if (error.key() == "(syntax)") {
      pkm::fuzz::oracle_failed(std::string("the reader wrote TOML that does not parse: ") +
                               error.what() + "\n" + imported.kinematics_section);
    }
    return std::nullopt;
  }
  // machine_file_text has loaded it already: it loads.
  return machine::parse_machine(text, "fuzz.toml");
}

std::string export_text(const firmware::Target& target, const machine::Machine& loaded) {
  return target
      .write(firmware::firmware_machine(loaded, target.forms, target.name, false), kContext)
      .text;
}

// An export read back, loaded and exported again: every step must succeed.
std::string round_trip(const firmware::Target& target, const std::string& exported) {
  const machine::ImportedMachine imported = target.read(exported, "exported");
  const std::optional<machine::Machine> loaded = load(imported);
  if (!loaded) pkm::fuzz::oracle_failed("an export does not load back:\n" + exported);
  require_finite_machine(*loaded);
  return export_text(target, *loaded);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const firmware::Target& target = firmware::targets()[data[0] % firmware::targets().size()];
  const std::string_view text(reinterpret_cast<const char*>(data) + 1, size - 1);
  std::optional<machine::Machine> loaded;
  try {
    loaded = load(target.read(text, "fuzz.cfg"));
  } catch (const firmware::FirmwareFileError&) {
    return 0;  // a located error: an expected end
  }
  if (!loaded) return 0;
  require_finite_machine(*loaded);
  std::string first;
  try {
    first = export_text(target, *loaded);
  } catch (const firmware::ExportRefused&) {
    return 0;
  }
  pkm::fuzz::require_no_non_finite_text(first);
  // Any exception from here on escapes and aborts: an export must read back, and so on. The
  // first export need not be the input's fixed point: the input's name (RRF's M550, which export
  // does not write) or its numbers past the decimals the writer keeps are the input's own.
  const std::string second = round_trip(target, first);
  const std::string third = round_trip(target, second);
  if (third != second) {
    pkm::fuzz::oracle_failed("import then export is not a fixed point:\n" + second + "\n----\n" +
                             third);
  }
  return 0;
}
