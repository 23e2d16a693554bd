// The rotary delta as firmwares' rotary-delta kinematics hold it (firmware_form.hpp): exactly,
// the form's conventions being this model's.
#include "pkm/kinematics/rotary_delta.hpp"

namespace pkm::kinematics {

std::optional<FirmwareForm> RotaryDeltaKinematics::firmware_form() const {
  const RotaryDeltaForm form{geometry_.base_radius_mm, geometry_.arm_length_mm,
                             geometry_.forearm_length_mm, geometry_.platform_radius_mm};
  return FirmwareForm{form, {}, {}, passthrough_};
}

}  // namespace pkm::kinematics
