// libFuzzer target: bytes as a calibration CSV, read both ways pkm calibrate reads them: as
// measurements (joint readings and measured poses) of a small machine, and as mark-to-mark
// distances of a wall plotter's pattern. Oracles: no sanitizer report, no exception but
// MeasurementFileError (file:line:column), every number read finite.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "fuzz_support.hpp"
#include "pkm/calibration/calibration_pattern.hpp"
#include "pkm/calibration/distance_fit.hpp"
#include "pkm/calibration/measurements.hpp"
#include "pkm/machine/machine.hpp"

namespace {

const pkm::machine::Machine& machine() {
  static const pkm::machine::Machine loaded = pkm::machine::load_machine(PKM_FUZZ_MACHINE);
  return loaded;
}

std::vector<pkm::calibration::PatternMark> marks() {
  std::vector<pkm::calibration::PatternMark> made;
  for (int id = 1; id <= 6; ++id) {
    pkm::calibration::PatternMark mark;
    mark.id = id;
    mark.position_mm = {100.0 * id, 50.0 * (id % 3)};
    made.push_back(mark);
  }
  return made;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    for (const pkm::calibration::Measurement& m :
         pkm::calibration::parse_measurements_csv(text, "fuzz.csv", machine())) {
      for (int i = 0; i < m.joints.size(); ++i) pkm::fuzz::require_finite(m.joints[i], "a joint");
      for (int i = 0; i < pkm::geometry::kPoseSize; ++i) {
        if (m.measured[static_cast<std::size_t>(i)]) pkm::fuzz::require_finite(m.pose[i], "a pose");
      }
    }
  } catch (const pkm::calibration::MeasurementFileError&) {
  }
  static const std::vector<pkm::calibration::PatternMark> pattern = marks();
  try {
    for (const pkm::calibration::MarkDistance& d :
         pkm::calibration::parse_distances_csv(text, "fuzz.csv", pattern)) {
      pkm::fuzz::require_finite(d.distance_mm, "a distance");
    }
  } catch (const pkm::calibration::MeasurementFileError&) {
  }
  return 0;
}
