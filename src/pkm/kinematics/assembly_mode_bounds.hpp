// What a model proves about its assembly mode over a region of poses: a value that keeps its sign
// within a mode, with a bound on how fast it changes (a translating glide: det of its strut
// vectors; a rotary delta: det of its forearms), or bounds over a box of poses (a hexapod's tilt
// and base side). Kinematics::assembly_mode_bounds() gives it; bounds/assembly_mode.hpp asks it
// for the certified check and the workspace.
#pragma once

#include <optional>
#include <span>

#include "pkm/kinematics/kinematics.hpp"

namespace pkm::kinematics {

// The mode value at a ball's centre (positive in home's mode) and an upper bound on how fast it
// changes per unit of the ball's radius: value - rate * radius > 0 proves the mode over the ball.
struct ModeBound {
  double value = 0.0;
  double rate = 0.0;
};

// A measure of the mode over a box not proven positive: its least value there, and the leg it
// belongs to (-1: the platform's tilt).
struct ModeShortfall {
  int leg = -1;
  double low = 0.0;
};

class AssemblyModeBounds {
 public:
  virtual ~AssemblyModeBounds() = default;

  // Over a ball about the pose `centre` (mm, rad) whose joints read `joints`, each joint moving
  // at most `joint_speed[i]` per unit of the ball's (scaled) radius: home's mode times the mode's
  // value, and its rate. None where the mode has no such bound.
  virtual std::optional<ModeBound> mode_over_ball(int /*home_mode*/,
                                                  const geometry::Vector6d& /*centre*/,
                                                  const JointVector& /*joints*/,
                                                  std::span<const double> /*joint_speed*/) const {
    return std::nullopt;
  }
  // Over every position within `radius_mm` of `centre`: the same sign, normalised by the struts'
  // lengths, its rate per mm (the workspace's). None where the centre or the cell leaves the
  // model's reach; has_mode_over_cell() false where the model has no such bound.
  virtual bool has_mode_over_cell() const { return false; }
  virtual std::optional<ModeBound> mode_over_cell(int /*home_mode*/,
                                                  const geometry::Vector6d& /*centre*/,
                                                  double /*radius_mm*/) const {
    return std::nullopt;
  }
  // Over the box centre +- half (mm, rad), for models whose mode is bounded over a box instead
  // (has_mode_over_box()): the first of its measures not proven positive, none when all are.
  virtual bool has_mode_over_box() const { return false; }
  virtual std::optional<ModeShortfall> mode_over_box(int /*home_mode*/,
                                                     const geometry::Vector6d& /*centre*/,
                                                     const geometry::Vector6d& /*half*/) const {
    return std::nullopt;
  }
};

}  // namespace pkm::kinematics
