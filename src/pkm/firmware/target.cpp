#include "pkm/firmware/target.hpp"

#include <cstdio>
#include <stdexcept>

#include "pkm/firmware/fluidnc.hpp"
#include "pkm/firmware/grblhal.hpp"
#include "pkm/firmware/klipper.hpp"
#include "pkm/firmware/marlin.hpp"
#include "pkm/firmware/rrf.hpp"

namespace pkm::firmware {
namespace {

std::string millimetres(double value) {
  char text[48];
  std::snprintf(text, sizeof text, "%.4f mm", value);
  return text;
}

}  // namespace

std::vector<std::string> header_lines(const FirmwareMachine& machine,
                                      const ExportContext& context) {
  std::vector<std::string> lines = {
      "Written by pkmkit " + context.pkmkit_version + " from " + context.machine_source + ": " +
          machine.machine.name(),
      std::string("Kinematics: ") + kinematics::form_name(machine.form.geometry)};
  if (machine.cost) {
    const ApproximationCost& cost = *machine.cost;
    const Eigen::Vector3d& at = cost.worst_at.position_mm;
    lines.push_back(
        "APPROXIMATED: the firmware cannot hold this machine exactly; this is the "
        "nearest machine it can hold, fitted over the workspace");
    for (const std::string& loss : machine.form.losses) lines.push_back("  left out: " + loss);
    char where[96];
    std::snprintf(where, sizeof where, "x %.1f y %.1f z %.1f mm", at.x(), at.y(), at.z());
    lines.push_back(
        "Worst tool error " + millimetres(cost.worst_tool_error_mm) + " at " + where + ", rms " +
        millimetres(cost.rms_tool_error_mm) + " over " + std::to_string(cost.samples) +
        " workspace poses (before the fit: " + millimetres(cost.worst_before_fit_mm) + ")");
  }
  for (const std::string& check : machine.form.unchecked) {
    lines.push_back("Not checked by the firmware: " + check);
  }
  return lines;
}

std::string header_comment(const FirmwareMachine& machine, const ExportContext& context,
                           std::string_view mark) {
  std::string text;
  for (const std::string& line : header_lines(machine, context))
    text.append(mark).append(line).append("\n");
  return text;
}

const std::vector<Target>& targets() {
  static const std::vector<Target> all = {fluidnc_target(), klipper_target(), rrf_target(),
                                          grblhal_target(), marlin_target()};
  return all;
}

const Target& target(std::string_view name) {
  std::string known;
  for (const Target& candidate : targets()) {
    if (candidate.name == name) return candidate;
    known += (known.empty() ? "" : ", ") + candidate.name;
  }
  throw std::invalid_argument("no firmware target '" + std::string(name) + "' (known: " + known +
                              ")");
}

}  // namespace pkm::firmware
