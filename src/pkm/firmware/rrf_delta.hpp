// RepRapFirmware's linear delta settings (docs/firmware-rrf.md) as config.g says them: M665,
// M666, M92, M203, M201, M208, and the geometry RRF derives from them (its
// LinearDeltaKinematics::Recalc): where each tower stands and each carriage's height at its
// endstop. The writer (rrf.cpp) fills them from a machine, the reader (rrf_config.cpp) from a
// file; both print them with rrf_delta_lines, so an import exports the same lines. Also what
// both of RRF's deltas share: the towers' match to the joints, the print circle and Z range.
#pragma once

#include <Eigen/Core>
#include <array>
#include <optional>
#include <string>
#include <vector>

#include "pkm/kinematics/kinematics.hpp"
#include "pkm/machine/machine.hpp"

namespace pkm::firmware {

// RRF's towers A, B, C are driven by its X, Y, Z motors.
inline constexpr std::array<char, 3> kRrfDriveLetters = {'X', 'Y', 'Z'};
inline constexpr std::array<char, 3> kRrfTowerNames = {'A', 'B', 'C'};
// Where RRF puts towers A, B, C before the angle corrections: deg counter-clockwise from +x.
inline constexpr std::array<double, 3> kRrfNominalTowerAngles = {210.0, 330.0, 90.0};

struct RrfLinearDelta {
  std::array<double, 3> diagonals_mm{};                // M665 L, towers A:B:C
  double radius_mm = 0.0;                              // M665 R
  double homed_height_mm = 0.0;                        // M665 H
  double print_radius_mm = 0.0;                        // M665 B
  std::array<double, 3> angle_corrections_deg{};       // M665 X Y Z
  std::array<double, 3> endstop_adjustments_mm{};      // M666 X Y Z
  std::array<double, 2> tilt{};                        // M666 A B over 100 (z per mm of x, of y)
  std::array<std::optional<double>, 3> steps_per_mm;   // M92 X Y Z
  std::array<double, 3> max_speed_mm_per_min{};        // M203 X Y Z
  std::array<double, 3> max_acceleration_mm_per_s2{};  // M201 X Y Z
  double z_min_mm = 0.0;                               // M208 S1 Z
};

// Tower `tower`'s x y (mm): at radius R, at its nominal angle plus its correction.
Eigen::Vector2d rrf_tower_position(const RrfLinearDelta& delta, int tower);
// The motor position (mm) RRF sets when the carriage of `tower` reaches its endstop:
// H + sqrt(L^2 - R^2) + the endstop correction.
double rrf_homed_carriage_height(const RrfLinearDelta& delta, int tower);

// Which pkmkit joint each RRF tower A, B, C is, and its angle correction (deg).
struct TowerAssignment {
  std::array<int, 3> joint_of_tower{0, 1, 2};
  std::array<double, 3> corrections_deg{};
};
// The towers matched to joints whose towers (arms) point at `angles_deg` (deg ccw from +x), with
// the smallest corrections from `nominal_deg`: RRF's auto-calibration and its users expect
// corrections of a few degrees, not of 120.
TowerAssignment assign_towers(const std::array<double, 3>& angles_deg,
                              const std::array<double, 3>& nominal_deg);

// M665 B (M669 B) and M208 Z: the largest circle about (0, 0) in the machine's work envelope (its
// reach where it has none), and its z range (mm). Throws ExportRefused when the circle is empty.
struct RrfBounds {
  double print_radius_mm = 0.0;
  double z_min_mm = 0.0, z_max_mm = 0.0;
};
RrfBounds rrf_bounds(const machine::Machine& machine);

// An imported home with every joint at its endstop, a limit: its forward kinematics may read back
// a joint 1e-13 past it. Lowers `pose` (by 1e-9 mm, doubling) until the model's joints are
// 1e-12 inside [low, high] (mm or rad); false if 1 mm does not do it.
bool lower_into_limits(const kinematics::Kinematics& model, const std::array<double, 3>& low,
                       const std::array<double, 3>& high, geometry::Pose& pose);

// A number as the lines write it: at most 6 decimals, no trailing zeros, no "-0".
std::string rrf_number(double value);

// The M669 K3, M665, M666, M92, M203, M201 and M208 lines, each with its `;` comment.
std::vector<std::string> rrf_delta_lines(const RrfLinearDelta& delta);

}  // namespace pkm::firmware
