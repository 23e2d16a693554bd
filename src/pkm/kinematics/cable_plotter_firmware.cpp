// The two-cable plotter as firmwares' wall-plotter kinematics hold it (firmware_form.hpp).
#include <cstdio>

#include "pkm/kinematics/cable_plotter.hpp"

namespace pkm::kinematics {
std::optional<FirmwareForm> CablePlotterKinematics::firmware_form() const {
  const CablePlotterGeometry& g = geometry_;
  WallPlotterForm form;
  form.anchors_mm = g.anchors_mm;
  form.cable_offsets_mm = g.cable_offsets_mm;
  FirmwareForm result{form, {}, {}, passthrough_};
  if (g.pulley_radius_mm != 0.0) {
    result.losses.push_back(
        loss_text("pulley_radius %.3f mm: the cords leave their pulleys "
                  "tangentially, not from a point",
                  g.pulley_radius_mm));
  }
  if (!g.attach_mm[0].isZero() || !g.attach_mm[1].isZero()) {
    result.losses.push_back(
        loss_text("effector_attach (%.3f mm apart): the cords are tied apart from the pen, and "
                  "the effector tilts",
                  (g.attach_mm[1] - g.attach_mm[0]).norm()));
  }
  if (g.cable_density_kg_per_m != 0.0) {
    result.losses.push_back(
        loss_text("cable_density %.4f kg/m: the cords sag", g.cable_density_kg_per_m));
  }
  if (g.cable_stretch_mm_per_m_per_N != 0.0) {
    result.losses.push_back(loss_text("cable_stiffness %.0f N: the cords stretch",
                                      1000.0 / g.cable_stretch_mm_per_m_per_N));
  }
  if (g.spool_buildup_mm_per_m != 0.0) {
    result.losses.push_back(
        loss_text("spool_buildup %.4f mm/m: the drums' radius changes", g.spool_buildup_mm_per_m));
  }
  if (g.tension_limited) {
    result.unchecked.push_back(loss_text("tension_limits [%.3f", g.tension_min_N) +
                               loss_text(", %.3f] N", g.tension_max_N));
  }
  return result;
}

}  // namespace pkm::kinematics
