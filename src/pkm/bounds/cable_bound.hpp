// Proven bounds on a hanging two-cable effector's balance over a box of pen positions: the
// effector's tilt, each cable's tension, the signs that say both cables pull, and each cable's
// joint reading, for every pen position in the box. Interval arithmetic on the balance of
// cable_statics.hpp (straight cables over pulleys, an effector tied at two points that tilts
// under its weight, cables that stretch); the tilt is enclosed by discarding every tilt where
// the moment on the effector provably keeps one sign. One place for what the certified job
// check (the box around a piece of a move) and the workspace (a cell) both prove with. The
// argument is in docs/cable-bounds.md.
#pragma once

#include <array>
#include <cmath>
#include <string>

#include "pkm/kinematics/cable_statics.hpp"

namespace pkm::bounds {

// A closed interval; infinite ends where nothing is known.
struct Range {
  double lo = -INFINITY, hi = INFINITY;
  static Range point(double v) { return {v, v}; }
  bool known() const { return std::isfinite(lo) && std::isfinite(hi); }
  double mid() const { return 0.5 * (lo + hi); }
};

// Empty when cable_box_bound applies to this geometry; else why not, as a sentence fragment
// ("cables that sag (cable_density > 0)..."). Ideal plotters are bounded too (their pull region
// has a closed form elsewhere, but this one holds for them).
std::string cable_bound_unavailable(const kinematics::CablePlotterGeometry& geometry);

// The pull margins: the tensions' signs and the sine of the angle between the cables.
enum CablePullMargin { kLeftPulls = 0, kRightPulls = 1, kCablesApart = 2 };

struct CableBoxBound {
  // False where nothing below is known: a cable's end may reach its pulley within the box, or
  // the tilt could not be enclosed (the bounds then prove nothing, and refute nothing).
  bool known = false;
  // Proven: the effector has no balance within the solver's tilt range (1.5 rad) anywhere in
  // the box, where its cables' ends keep clear of their pulleys: Machine::inverse refuses it all.
  bool no_balance = false;
  Range tilt_rad;
  // Each cable's tension (N) where it meets the effector; for a massless effector, the
  // tensions under a unit load (only their signs mean anything). Positive: the cable pulls.
  std::array<Range, 2> tension_N;
  // |sin| of the angle between the cables, less the 1e-12 below which the balance is singular.
  Range apart;
  std::array<Range, 2> joint_mm;  // each cable's joint reading (cable past the top + offset)
  // 1 / tension (per N; unit load without a mass): bounded where the cables come into line,
  // where the tension is not. 1 / t >= 1 / max says at once that the cable pulls, is not in line
  // with the other, and stays within max.
  std::array<Range, 2> inverse_tension_per_N;
};

// Over every pen position within `centre_mm` +- `half_mm` (x, y; vertical plane, y up), at
// rest (gravity along -y): Machine::inverse's balance lies within these bounds wherever it
// finds one. With `half_chord_mm`, the positions are only those of the segment centre +- s
// half_chord (s in [-1, 1], inside the box): a line piece, whose tensions the mean-value form
// along it bounds to second order where they turn.
CableBoxBound cable_box_bound(const kinematics::CablePlotterGeometry& geometry,
                              const Eigen::Vector2d& centre_mm, const Eigen::Vector2d& half_mm,
                              const Eigen::Vector2d* half_chord_mm = nullptr);

}  // namespace pkm::bounds
