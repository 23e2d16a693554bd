// The glide as firmwares' linear-delta kinematics hold it (firmware_form.hpp).
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "pkm/geometry/pose.hpp"
#include "pkm/kinematics/glide.hpp"

namespace pkm::kinematics {

std::optional<FirmwareForm> GlideKinematics::firmware_form() const {
  if (rails_.size() != 3 || dof_.any_rotation() || !rail_dof().controls(0) ||
      !rail_dof().controls(1) || !rail_dof().controls(2)) {
    return std::nullopt;
  }
  // A rail more than 30 deg from vertical makes another machine (a triaglide's horizontal rails),
  // not a delta with an error to approximate.
  const double kMostLean_deg = 30.0;
  for (const GlideRail& rail : rails_) {
    if (rail.direction.normalized().z() < std::cos(geometry::degrees_to_radians(kMostLean_deg)))
      return std::nullopt;
  }
  LinearDeltaForm form;
  FirmwareForm result{form, {}, {}, passthrough_};
  for (std::size_t i = 0; i < rails_.size(); ++i) {
    const GlideRail& rail = rails_[i];
    LinearDeltaTower& tower = form.towers[i];
    tower.column_mm = rail.origin_mm.head<2>() - rail.attach_mm.head<2>();
    tower.rod_mm = rail.strut_mm;
    tower.carriage_offset_mm = rail.attach_mm.z() - rail.origin_mm.z();
    char text[160];
    const double lean_deg = geometry::radians_to_degrees(
        std::acos(std::clamp(rail.direction.normalized().z(), -1.0, 1.0)));
    if (lean_deg != 0.0) {
      std::snprintf(text, sizeof text, "rail %zu leans %.4f deg from vertical", i + 1, lean_deg);
      result.losses.push_back(text);
    }
    if (rail.branch != 1) {
      std::snprintf(text, sizeof text, "rail %zu has its carriage below the effector (branch -1)",
                    i + 1);
      result.losses.push_back(text);
    }
  }
  result.geometry = form;
  if (leg_limits_.active()) {
    result.unchecked.push_back("the struts' joint angles and interference (leg limits)");
  }
  return result;
}

}  // namespace pkm::kinematics
