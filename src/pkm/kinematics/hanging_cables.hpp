// What the tension checks ask of a machine whose effector hangs from cables (a cable_plotter):
// its weight, its balance at a pose while it accelerates, and the limits the tensions must keep.
// Kinematics::hanging_cables() gives it; the planner's tension limit, pkm check's tension map and
// the drawing of the cables ask it, whatever the model.
#pragma once

#include <Eigen/Core>
#include <memory>

#include "pkm/kinematics/cable_statics.hpp"
#include "pkm/kinematics/kinematics.hpp"

namespace pkm::kinematics {

class HangingCables {
 public:
  virtual ~HangingCables() = default;

  // kg; 0 in the paper's massless model, whose tensions are not modelled.
  virtual double effector_mass_kg() const = 0;
  // Whether the effector can turn: tied at points off the pen, or weighted off it.
  virtual bool effector_tilts() const = 0;
  // Whether the machine file sets tension_limits; the tensions' [min, max] in N, without them
  // [0, inf) ("both cables pull").
  virtual bool tension_limited() const = 0;
  virtual double tension_min_N() const = 0;
  virtual double tension_max_N() const = 0;
  // Quasi-static balance at the pen position of `pose` while the effector accelerates
  // (mm/s^2, x right, y up): tensions from m (g - a), the tilt for that effective gravity.
  virtual Status statics(const geometry::Pose& pose, const Eigen::Vector2d& acceleration_mm_per_s2,
                         CableStatics& out) const = 0;
  // The whole geometry (anchors, pulleys, effector, stretch), for the bounds of the balance over
  // a box of poses (bounds/cable_bound), the ideal plotter's pull region and the tension map's
  // extent (machine/tension_region.cpp).
  virtual const CablePlotterGeometry& cable_geometry() const = 0;
  // The same cables without tension_limits ([0, inf): a pose where a cable would push is still
  // refused), whose balance the tension map solves again.
  virtual std::unique_ptr<Kinematics> without_tension_limits() const = 0;
};

}  // namespace pkm::kinematics
