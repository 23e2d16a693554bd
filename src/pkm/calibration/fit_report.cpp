#include "pkm/calibration/fit_report.hpp"

namespace pkm::calibration {

nlohmann::json poorly_determined_json(const std::vector<PoorlyDetermined>& held) {
  nlohmann::json result = nlohmann::json::array();
  for (const PoorlyDetermined& p : held) {
    nlohmann::json trades = nlohmann::json::array();
    for (const TradeOff& t : p.trades_with)
      trades.push_back({{"name", t.name}, {"correlation", t.correlation}});
    result.push_back({{"name", p.name},
                      {"unit", p.unit},
                      {"kind", p.kind},
                      {"nominal", p.nominal},
                      {"fitted", p.fitted},
                      {"standard_deviation", p.standard_deviation},
                      {"alone_standard_deviation", p.alone_deviation},
                      {"plausible_deviation", p.plausible_deviation},
                      {"trades_with", trades}});
  }
  return result;
}

std::string poorly_determined_text(const PoorlyDetermined& held, double design_noise_mm) {
  const std::string unit = held.unit.empty() ? "" : " " + held.unit;
  std::string text = "held " + held.name + " at its nominal " + shown_number(held.nominal) + unit;
  if (design_noise_mm > 0.0) {
    text += ": measured to +-" + shown_number(design_noise_mm) + " mm, the distances would pin it";
  } else {
    text += ": the data pin it";
  }
  text += " only to +-" + shown_number(held.standard_deviation) + unit;
  if (design_noise_mm <= 0.0)
    text += " (the fit put it at " + shown_number(held.fitted) + unit + ")";
  text += ", worse than the +-" + shown_number(held.plausible_deviation) + unit + " (" + held.rule +
          ") " + held.kind + " plausibly is off its machine file; it trades with " +
          describe_trades(held.trades_with) + " (alone it would be pinned to +-" +
          shown_number(held.alone_deviation) + unit + ")";
  return text;
}

nlohmann::json fit_report_json(const FitReport& report, const std::string& output) {
  nlohmann::json parameters = nlohmann::json::array();
  for (const ParameterEstimate& p : report.parameters) {
    parameters.push_back({{"name", p.name},
                          {"unit", p.unit},
                          {"nominal", p.nominal},
                          {"fitted", p.fitted},
                          {"standard_deviation", p.standard_deviation},
                          {"kind", p.kind},
                          {"plausible_deviation", p.plausible_deviation},
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
                        {"poorly_determined", poorly_determined_json(report.poorly_determined)},
                        {"held", report.held},
                        {"converged", report.converged},
                        {"output", output}};
}

}  // namespace pkm::calibration
