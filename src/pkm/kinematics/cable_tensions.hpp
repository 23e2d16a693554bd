// What the rest of pkm asks of a machine whose effector is held by more cables than it has
// coordinates (a cable_robot): how many cables, their limits and preferred tension, and the
// tensions that hold the effector at a pose while it accelerates. Kinematics::cable_tensions()
// gives it; pkm ik, fk and check list the tensions, the pages draw them, the planner limits
// acceleration by its force polytope, and the workspace's joints, the joint-rate bound and the
// calibration from readings take the geometry alone, whatever the model (docs/cable-machines.md,
// "N cables"). The poses the tensions hold are bounded over a cell by the model's reach margins
// (derivative_bounds.hpp). The two-cable plotter, whose tensions follow from its geometry alone,
// answers hanging_cables.hpp instead.
#pragma once

#include <Eigen/Core>
#include <memory>
#include <optional>

#include "pkm/geometry/pose.hpp"
#include "pkm/kinematics/cable_force_polytope.hpp"
#include "pkm/kinematics/tension_distribution.hpp"

namespace pkm::kinematics {

class Kinematics;

class CableTensions {
 public:
  virtual ~CableTensions() = default;

  // The cables are joints 0 .. tension_count() - 1, in the machine file's order.
  virtual int tension_count() const = 0;
  // kg; 0: the cables hold only their own pretension.
  virtual double effector_mass_kg() const = 0;
  // Whether the machine file sets tension_limits (else each cable's are [0, inf)).
  virtual bool tension_limited() const = 0;
  // Per cable: its limits and the tension a controller aims for (N).
  virtual TensionTargets tension_targets() const = 0;
  // The tensions at `pose` while the effector accelerates (mm/s^2, machine x y z): the
  // distribution of tension_distribution.hpp; none where a cable has no direction.
  virtual std::optional<TensionDistribution> tensions(
      const geometry::Pose& pose,
      const Eigen::Vector3d& acceleration_mm_per_s2 = Eigen::Vector3d::Zero()) const = 0;
  // The force (N, machine x y z) the cables must exert on the effector accelerating at
  // `acceleration` (mm/s^2): m (a - g). A planar robot's cables give its x y, the sheet the rest.
  virtual Eigen::Vector3d cable_force_N(const Eigen::Vector3d& acceleration_mm_per_s2) const = 0;
  // The forces the cables can exert at `pose` with every tension within tension_targets()'
  // limits (cable_force_polytope.hpp): the effector is held while accelerating at a exactly where
  // cable_force_N(a) is within every facet. False where a cable has no direction or the cables
  // do not span the effector's directions. Allocation-free (the planner asks it per grid point).
  virtual bool force_polytope(const geometry::Pose& pose, CableForcePolytope& polytope) const = 0;
  // The same machine with inverse() refusing no pose for its tensions: its geometry alone, what a
  // calibration from readings fits (the readings were taken where the machine as built held its
  // effector, which the machine file's geometry, still being fitted, may judge otherwise).
  virtual std::unique_ptr<Kinematics> geometry_only() const = 0;
};

// The model whose inverse gives a machine's joints wherever its geometry reaches: a cable robot's
// geometry alone (its tensions may refuse the pose: they are bounded apart, as the workspace's
// and the joint-rate bound's own margins), any other model a copy of itself. What bounds the
// joints over a cell asks, so that a cell is said to be limited by what limits it.
std::unique_ptr<Kinematics> joint_geometry(const Kinematics& model);

}  // namespace pkm::kinematics
