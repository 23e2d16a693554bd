// The cable robot as firmwares' cable kinematics hold it (firmware_form.hpp): RepRapFirmware's
// Hangprinter and Klipper's winch take each line from a fixed point to one point that
// translates. The effector here does not turn, so a tie point `attach` away from the tool folds
// into its anchor: |anchor - (tool + attach)| = |(anchor - attach) - tool|.
#include <algorithm>
#include <cstdio>

#include "pkm/kinematics/cable_robot.hpp"

namespace pkm::kinematics {
std::optional<FirmwareForm> CableRobotKinematics::firmware_form() const {
  const CableRobotGeometry& g = geometry_;
  CableRobotForm form;
  form.planar = g.planar;
  form.flex_compensation = g.flex_compensation;
  FirmwareForm result{form, {}, {}, passthrough_};
  CableRobotForm& folded = std::get<CableRobotForm>(result.geometry);
  double arm = 0.0;
  for (const RobotCable& cable : g.cables) {
    folded.anchors_mm.push_back(cable.anchor_mm - cable.attach_mm);
    folded.cable_offsets_mm.push_back(cable.offset_mm);
    arm = std::max(arm, cable.swivel_arm_mm);
  }
  if (arm != 0.0) {
    result.losses.push_back(
        loss_text("swivel_arm %.3f mm: each cable is tied at the end of an arm that turns to point "
                  "at its anchor (Maslow 4), not at a point fixed on the effector",
                  arm));
  }
  double pulley = 0.0;
  for (const RobotCable& cable : g.cables) pulley = std::max(pulley, cable.pulley_radius_mm);
  if (pulley != 0.0) {
    result.losses.push_back(
        loss_text("pulley_radius %.3f mm: each cable wraps a swivelling pulley before its straight "
                  "span, where the firmware takes it straight from a point anchor",
                  pulley));
  }
  if (g.cables_follow_z) {
    result.losses.push_back(
        "cables_follow_z: the tie points ride on the tool's z (Maslow 4's arms on its spindle), "
        "so a cable's length changes with z");
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
