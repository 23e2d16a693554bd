// RepRapFirmware's rotary delta (M669 K10, its RotaryDeltaKinematics; docs/firmware-rrf.md) as
// config.g says it, and its export from pkmkit's rotary delta form. RRF's conventions: arm A, B,
// C pivot at radius R (the pivots less the effector's joints, as one parallelogram) towards -150,
// -30 and 90 deg plus their corrections, at height H; an arm's angle (deg) is 0 horizontal and
// positive up; homing up to an endstop sets the angle to A's maximum plus the endstop correction.
#pragma once

#include <array>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "pkm/firmware/target.hpp"

namespace pkm::firmware {

inline constexpr std::array<double, 3> kRrfRotaryNominalAngles = {-150.0, -30.0, 90.0};

struct RrfRotaryDelta {
  std::array<double, 3> arm_lengths_mm{};      // M669 U
  std::array<double, 3> rod_lengths_mm{};      // M669 L
  std::array<double, 3> bearing_heights_mm{};  // M669 H
  double min_arm_angle_deg = 0.0;              // M669 A min:max
  double max_arm_angle_deg = 0.0;
  double radius_mm = 0.0;                              // M669 R
  double print_radius_mm = 0.0;                        // M669 B
  std::array<double, 3> angle_corrections_deg{};       // M669 X Y Z
  std::array<double, 3> endstop_adjustments_deg{};     // M666 X Y Z
  std::array<std::optional<double>, 3> steps_per_deg;  // M92 X Y Z
  double max_speed_mm_per_min = 0.0;                   // M203 X Y Z
  double max_acceleration_mm_per_s2 = 0.0;             // M201 X Y Z
  double z_min_mm = 0.0, z_max_mm = 0.0;               // M208 Z min:max
};

// The M669 K10, M666, M92, M203, M201 and M208 lines, each with its `;` comment.
std::vector<std::string> rrf_rotary_lines(const RrfRotaryDelta& delta);

// The config.g lines for a machine in pkmkit's rotary delta form.
ExportedFile write_rrf_rotary_delta(const FirmwareMachine& machine, const ExportContext& context);

// A setting pkmkit's rotary delta cannot hold: its key ("M669 U") and why.
class RrfSettingRefused : public std::invalid_argument {
 public:
  RrfSettingRefused(std::string key, const std::string& why)
      : std::invalid_argument(why), key_(std::move(key)) {}
  const std::string& key() const { return key_; }

 private:
  std::string key_;
};

// The machine of RRF rotary delta settings, where pkmkit's form holds them: equal arms and rods,
// the pivots at z 0, arms 120 deg apart with one towards -90 deg. Throws RrfSettingRefused.
machine::ImportedMachine rrf_rotary_machine(const RrfRotaryDelta& delta);

}  // namespace pkm::firmware
