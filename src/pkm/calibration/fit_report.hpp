// A calibration fit's report as JSON: what `pkm calibrate fit --json` prints and the Python
// module's pkmkit.calibrate.fit returns, made in one place; and the sentence that says why a
// poorly determined parameter was held, with its numbers.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "pkm/calibration/parameter_fit.hpp"

namespace pkm::calibration {

// `output`: the machine file the fitted geometry was written to ("" for none).
nlohmann::json fit_report_json(const FitReport& report, const std::string& output);

nlohmann::json poorly_determined_json(const std::vector<PoorlyDetermined>& held);

// "held pulley_radius at its nominal 6.366 mm: the data pin it only to +-18.1 mm (the fit put it
// at 28.3 mm) ...". `design_noise_mm` > 0: said of a design, before any measurement, with that
// noise assumed.
std::string poorly_determined_text(const PoorlyDetermined& held, double design_noise_mm = 0.0);

}  // namespace pkm::calibration
