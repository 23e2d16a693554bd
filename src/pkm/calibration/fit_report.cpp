#include "pkm/calibration/fit_report.hpp"

namespace pkm {

nlohmann::json fit_report_json(const FitReport& report, const std::string& output) {
  nlohmann::json parameters = nlohmann::json::array();
  for (const ParameterEstimate& p : report.parameters) {
    parameters.push_back({{"name", p.name},
                          {"unit", p.unit},
                          {"nominal", p.nominal},
                          {"fitted", p.fitted},
                          {"standard_deviation", p.standard_deviation},
                          {"held", !p.free}});
  }
  return nlohmann::json{{"measurements", report.measurements},
                        {"rms_before_mm", report.rms_before_mm},
                        {"max_before_mm", report.max_before_mm},
                        {"rms_after_mm", report.rms_after_mm},
                        {"max_after_mm", report.max_after_mm},
                        {"max_after_line", report.max_after_line},
                        {"parameters", parameters},
                        {"indistinguishable", report.indistinguishable},
                        {"held_rigid_motion", report.held_rigid_motion},
                        {"no_effect", report.no_effect},
                        {"held", report.held},
                        {"converged", report.converged},
                        {"output", output}};
}

}  // namespace pkm
