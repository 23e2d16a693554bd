// libFuzzer target: bytes as a joint-space program, read by verify's joint-program reader and
// held against a small job on a wall plotter, as `pkm verify` does. Oracles: no sanitizer report,
// no exception but the located errors (GcodeError for the program, VerifyError for what verify
// refuses), and every number of the report finite.
#include <cstddef>
#include <cstdint>

#include "fuzz_support.hpp"
#include "pkm/gcode/gcode_error.hpp"
#include "pkm/machine/machine.hpp"
#include "pkm/verify/joint_path.hpp"

namespace {

const pkm::machine::Machine& machine() {
  static const pkm::machine::Machine loaded = pkm::machine::load_machine(PKM_FUZZ_MACHINE);
  return loaded;
}

void check(const pkm::verify::VerifyReport& report) {
  using pkm::fuzz::require_finite;
  require_finite(report.tolerance_mm, "the tolerance");
  require_finite(report.max_deviation_mm, "the largest deviation");
  require_finite(report.rms_deviation_mm, "the rms deviation");
  require_finite(report.job_length_mm, "the job's length");
  require_finite(report.traced_mm, "the length traced");
  for (const auto* summary : {&report.deviation, &report.position, &report.velocity, &report.pen}) {
    if (summary->count > 0) require_finite(summary->worst.value, "a worst violation");
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto joints = pkm::fuzz::input_file(data, size, ".ngc");
  try {
    (void)pkm::verify::tolerance_in_header(joints);
    pkm::verify::VerifyOptions options;
    options.job_options.max_loop_iterations = 1000;
    options.job_options.max_program_iterations = 10000;
    check(pkm::verify::verify_joint_program(machine(), joints, PKM_FUZZ_JOB, options));
  } catch (const pkm::gcode::GcodeError&) {
  } catch (const pkm::verify::VerifyError&) {
  }
  return 0;
}
