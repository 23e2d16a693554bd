// libFuzzer target: bytes as a machine file (TOML), parsed by parse_machine as `pkm check` reads
// one. Oracles: no sanitizer report, no exception but MachineFileError (file:line:key), and a
// machine that loads has finite joint limits and a home its inverse can be asked about.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "fuzz_support.hpp"
#include "pkm/machine/machine.hpp"
#include "pkm/machine/machine_file_error.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  try {
    const pkm::machine::Machine machine = pkm::machine::parse_machine(text, "fuzz.toml");
    for (const pkm::machine::JointSpec& joint : machine.joints()) {
      pkm::fuzz::require_finite(joint.min, "a joint's lower limit");
      pkm::fuzz::require_finite(joint.max, "a joint's upper limit");
    }
    for (int i = 0; i < pkm::geometry::kPoseSize; ++i) {
      pkm::fuzz::require_finite(machine.home().as_vector()[i], "the home pose");
    }
    pkm::kinematics::JointVector joints;
    (void)machine.inverse(machine.home(), joints);
  } catch (const pkm::machine::MachineFileError&) {
    // A located error: an expected end.
  }
  return 0;
}
