// A calibration fit's report as JSON: what `pkm calibrate fit --json` prints and the Python
// module's pkmkit.calibrate.fit returns, made in one place.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "pkm/calibration/parameter_fit.hpp"

namespace pkm {

// `output`: the machine file the fitted geometry was written to ("" for none).
nlohmann::json fit_report_json(const FitReport& report, const std::string& output);

}  // namespace pkm
