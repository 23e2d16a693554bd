// The cable robot as firmwares' cable kinematics hold it (firmware_form.hpp): RepRapFirmware's
// Hangprinter and Klipper's winch take each line from a fixed point to one point that
// translates. The effector here does not turn, so a tie point `attach` away from the tool folds
// into its anchor: |anchor - (tool + attach)| = |(anchor - attach) - tool|. Maslow 4's swivel arms
// and tie points riding on z are in the form (its arm turns about the tie point's vertical, which
// folds the same way).

#include <algorithm>

#include "pkm/kinematics/cable_robot.hpp"

namespace pkm::kinematics {
std::optional<FirmwareForm> CableRobotKinematics::firmware_form() const {
  const CableRobotGeometry& g = geometry_;
  CableRobotForm form;
  form.planar = g.planar;
  form.flex_compensation = g.flex_compensation;
  FirmwareForm result{form, {}, {}, passthrough_};
  CableRobotForm& folded = std::get<CableRobotForm>(result.geometry);
  folded.cables_follow_z = g.cables_follow_z;
  for (const RobotCable& cable : g.cables) {
    folded.anchors_mm.push_back(cable.anchor_mm - cable.attach_mm);
    folded.cable_offsets_mm.push_back(cable.offset_mm);
    folded.swivel_arms_mm.push_back(cable.swivel_arm_mm);
  }
  double pulley = 0.0;
  for (const RobotCable& cable : g.cables) pulley = std::max(pulley, cable.pulley_radius_mm);
  if (pulley != 0.0) {
    result.losses.push_back(
        loss_text("pulley_radius %.3f mm: each cable wraps a swivelling pulley before its straight "
                  "span, where the firmware takes it straight from a point anchor",
                  pulley));
  }
  if (g.effector_mass_kg != 0.0) {
    result.unchecked.push_back(
        loss_text("effector_mass %.3f kg: whether the cables can hold it (the wrench-feasible "
                  "workspace)",
                  g.effector_mass_kg));
  }
  if (g.tension_limited) {
    result.unchecked.push_back(loss_text("tension_limits [%.3f", g.tension_min_N) +
                               loss_text(", %.3f] N", g.tension_max_N));
  }
  return result;
}

}  // namespace pkm::kinematics
