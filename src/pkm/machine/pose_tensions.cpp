#include "pkm/machine/pose_tensions.hpp"

#include <cmath>
#include <cstdio>

#include "pkm/kinematics/cable_tensions.hpp"
#include "pkm/kinematics/hanging_cables.hpp"

namespace pkm::machine {

namespace {

std::string newton_text(double value) {
  char text[48];
  std::snprintf(text, sizeof text, "%.3f N", value + 0.0);
  return text;
}

std::vector<std::string> cable_names(const Machine& machine, int cables) {
  std::vector<std::string> names;
  for (int c = 0; c < cables; ++c)
    names.push_back(machine.joints()[static_cast<std::size_t>(c)].name);
  return names;
}

std::optional<PoseTensions> distribution_at(const Machine& machine,
                                            const kinematics::CableTensions& cables,
                                            const geometry::Pose& pose,
                                            const Eigen::Vector3d& acceleration_mm_per_s2) {
  const std::optional<kinematics::TensionDistribution> distribution =
      cables.tensions(pose, acceleration_mm_per_s2);
  if (!distribution) return std::nullopt;
  const kinematics::TensionTargets targets = cables.tension_targets();
  PoseTensions out;
  out.names = cable_names(machine, cables.tension_count());
  out.limited = cables.tension_limited();
  out.effector_mass_kg = cables.effector_mass_kg();
  for (int c = 0; c < cables.tension_count(); ++c) {
    out.tension_N.push_back(distribution->tension_N[c]);
    out.min_N.push_back(targets.min_N[c]);
    out.max_N.push_back(targets.max_N[c]);
  }
  out.held = distribution->held();
  if (!out.held) out.refusal = kinematics::describe_refusal(*distribution, out.names);
  return out;
}

// A plotter's balance: the tensions where the cables leave the effector; held where every
// cable's tension along it keeps the limits.
std::optional<PoseTensions> balance_at(const Machine& machine,
                                       const kinematics::HangingCables& cables,
                                       const geometry::Pose& pose,
                                       const Eigen::Vector3d& acceleration_mm_per_s2) {
  kinematics::CableStatics statics;
  if (!cables.statics(pose, acceleration_mm_per_s2.head<2>(), statics).ok()) return std::nullopt;
  PoseTensions out;
  out.names = cable_names(machine, 2);
  out.limited = cables.tension_limited();
  out.effector_mass_kg = cables.effector_mass_kg();
  for (std::size_t c = 0; c < 2; ++c) {
    out.tension_N.push_back(statics.tension_N[c]);
    out.min_N.push_back(cables.tension_min_N());
    out.max_N.push_back(cables.tension_limited() ? cables.tension_max_N() : INFINITY);
    const bool slack = statics.lowest_N[c] < out.min_N[c];
    const bool over = statics.highest_N[c] > out.max_N[c];
    if (!slack && !over) continue;
    out.held = false;
    out.refusal += (out.refusal.empty() ? "" : "; ") + out.names[c] + " would need " +
                   newton_text(slack ? statics.lowest_N[c] : statics.highest_N[c]) + " (its " +
                   (slack ? "min " : "max ") + newton_text(slack ? out.min_N[c] : out.max_N[c]) +
                   ")";
  }
  return out;
}

}  // namespace

bool lists_tensions(const Machine& machine) {
  const kinematics::Kinematics& model = machine.kinematics();
  if (const kinematics::CableTensions* cables = model.cable_tensions()) {
    return cables->effector_mass_kg() > 0.0 || cables->tension_limited();
  }
  const kinematics::HangingCables* hanging = model.hanging_cables();
  return hanging != nullptr && hanging->effector_mass_kg() > 0.0;
}

std::optional<PoseTensions> pose_tensions(const Machine& machine, const geometry::Pose& pose,
                                          const Eigen::Vector3d& acceleration_mm_per_s2) {
  if (!lists_tensions(machine)) return std::nullopt;
  const kinematics::Kinematics& model = machine.kinematics();
  if (const kinematics::CableTensions* cables = model.cable_tensions()) {
    return distribution_at(machine, *cables, pose, acceleration_mm_per_s2);
  }
  return balance_at(machine, *model.hanging_cables(), pose, acceleration_mm_per_s2);
}

std::string tensions_text(const PoseTensions& tensions) {
  std::string text;
  for (std::size_t c = 0; c < tensions.names.size(); ++c) {
    text +=
        (text.empty() ? "" : ", ") + tensions.names[c] + " " + newton_text(tensions.tension_N[c]);
  }
  return text;
}

std::string cable_limits_text(const PoseTensions& tensions, std::size_t cable) {
  char text[64];
  if (std::isfinite(tensions.max_N[cable])) {
    std::snprintf(text, sizeof text, "[%g, %g] N", tensions.min_N[cable], tensions.max_N[cable]);
  } else {
    std::snprintf(text, sizeof text, "[%g, inf) N", tensions.min_N[cable]);
  }
  return text;
}

std::string limits_text(const PoseTensions& tensions) {
  if (tensions.names.empty()) return "";
  for (std::size_t c = 1; c < tensions.names.size(); ++c) {
    if (tensions.min_N[c] != tensions.min_N[0] || tensions.max_N[c] != tensions.max_N[0])
      return "per cable";
  }
  return cable_limits_text(tensions, 0);
}

}  // namespace pkm::machine
