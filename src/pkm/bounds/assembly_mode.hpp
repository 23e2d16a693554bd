// The assembly mode over a ball of poses, whatever the model (kinematics/assembly_mode_bounds.hpp
// gives each model's own bound: a translating glide's det of its strut vectors, a rotary delta's
// det of its forearms; a hexapod's is over a box instead). One caller for what the certified job
// check (a ball around a piece of a move) proves with; the workspace asks the model over a cell.
#pragma once

#include <optional>
#include <span>

#include "pkm/kinematics/assembly_mode_bounds.hpp"
#include "pkm/kinematics/kinematics.hpp"

namespace pkm::bounds {

// Whether the model's assembly mode, home's being `home_mode` (0: a single mode, nothing to
// keep), has a bound here (over a ball or over a box).
bool has_assembly_bound(const kinematics::Kinematics& model, int home_mode);

// Over a ball about the pose `centre` whose joints read `joints`, each joint moving at most
// `joint_speed[i]` per unit of the ball's radius: the mode value at the centre (positive in home's
// mode) and its rate; value - rate * radius > 0 proves the mode over the ball. {1, 0} where home
// has no mode to keep; none where the model has no such bound.
std::optional<kinematics::ModeBound> assembly_mode_over_ball(const kinematics::Kinematics& model,
                                                             int home_mode,
                                                             const geometry::Vector6d& centre,
                                                             const kinematics::JointVector& joints,
                                                             std::span<const double> joint_speed);

}  // namespace pkm::bounds
