// libFuzzer target: bytes as a calibration pattern's pattern.json, parsed as `pkm calibrate fit
// --pattern` reads it. Oracles: no sanitizer report, no exception but PatternFileError
// (file:line:column); the marks read have positive ids, each once, and finite positions within
// the documented 1e6 mm, each with its location; written back as `calibrate pattern` writes
// pattern.json, they read again as the same marks (to the file's 0.001 mm).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <set>
#include <string>
#include <vector>

#include "fuzz_support.hpp"
#include "pkm/calibration/calibration_pattern.hpp"

namespace {

void require_sound(const std::vector<pkm::calibration::PatternMark>& marks) {
  std::set<int> ids;
  for (const pkm::calibration::PatternMark& mark : marks) {
    if (mark.id <= 0 || !ids.insert(mark.id).second) {
      pkm::fuzz::oracle_failed("mark id " + std::to_string(mark.id) + " not positive or repeated");
    }
    for (const double coordinate : {mark.position_mm.x(), mark.position_mm.y()}) {
      pkm::fuzz::require_finite(coordinate, "a mark's position");
      if (std::abs(coordinate) > 1e6) pkm::fuzz::oracle_failed("a mark beyond 1e6 mm");
    }
  }
}

void require_round_trip(const std::vector<pkm::calibration::PatternMark>& marks) {
  const std::vector<pkm::calibration::PatternMark> again = pkm::calibration::parse_pattern_json(
      pkm::calibration::pattern_json_text(marks), "again.json");
  if (again.size() != marks.size()) pkm::fuzz::oracle_failed("the marks written back differ");
  for (std::size_t i = 0; i < marks.size(); ++i) {
    if (again[i].id != marks[i].id ||
        (again[i].position_mm - marks[i].position_mm).cwiseAbs().maxCoeff() > 0.0005 + 1e-9) {
      pkm::fuzz::oracle_failed("mark " + std::to_string(marks[i].id) + " written back differs");
    }
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const std::vector<pkm::calibration::PatternMark> marks =
        pkm::calibration::parse_pattern_json(text, "fuzz.json");
    require_sound(marks);
    for (const pkm::calibration::PatternMark& mark : marks) {
      if (mark.location.rfind("fuzz.json:", 0) != 0) pkm::fuzz::oracle_failed("a mark unlocated");
    }
    require_round_trip(marks);
  } catch (const pkm::calibration::PatternFileError& error) {
    if (std::string(error.what()).rfind("fuzz.json:", 0) != 0) {
      pkm::fuzz::oracle_failed(std::string("an error without its location: ") + error.what());
    }
  }
  return 0;
}
