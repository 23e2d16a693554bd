// The cables' tensions at one pose, by the joints' names, whichever interface the model answers:
// an effector held by more cables than coordinates (CableTensions: the distribution) or a
// two-cable plotter (HangingCables: its balance). What pkm ik, fk and check print, the pages'
// tension readout and the Python module's Machine.tensions give (docs/cable-machines.md,
// "N cables: what each command shows").
#pragma once

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "pkm/machine/machine.hpp"

namespace pkm::machine {

struct PoseTensions {
  std::vector<std::string> names;  // the cables' joints' names, in the model's order
  std::vector<double> tension_N;   // held: the tensions; else those nearest to holding it
  std::vector<double> min_N;
  std::vector<double> max_N;  // infinity where the file sets no tension_limits
  bool limited = false;       // tension_limits given
  double effector_mass_kg = 0.0;
  // Whether tensions within the limits hold the effector here. Where not: `refusal` names each
  // cable that would leave its limits and the tension it would need ("C would need -3.182 N (its
  // min 0.000 N)"), or how much of the load no tension balances.
  bool held = true;
  std::string refusal;
};

// Whether the machine's cables carry a load worth listing: an effector with a mass, or tension
// limits to keep (a sled lying on its sheet, without either, has every tension 0).
bool lists_tensions(const Machine& machine);

// The tensions at `pose` (mm, rad) while the effector accelerates (mm/s^2, machine x y z; a
// plotter takes x y): none where the machine has no cables (or none worth listing), or the pose
// gives the cables no direction (a plotter's balance not found).
std::optional<PoseTensions> pose_tensions(
    const Machine& machine, const geometry::Pose& pose,
    const Eigen::Vector3d& acceleration_mm_per_s2 = Eigen::Vector3d::Zero());

// "A 39.650 N, B 37.581 N, C 30.249 N, D 17.851 N": each cable by name, 3 decimals.
std::string tensions_text(const PoseTensions& tensions);
// Cable c's limits: "[0, 70] N", or "[0, inf) N" without tension_limits.
std::string cable_limits_text(const PoseTensions& tensions, std::size_t cable);
// The same where every cable has the same limits, else "per cable".
std::string limits_text(const PoseTensions& tensions);

}  // namespace pkm::machine
