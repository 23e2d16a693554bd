// The forces n cables can exert on an effector at one pose with every tension within its limits:
// F = A t over the box min <= t <= max, a zonotope (a polytope when the limits are finite), given
// exactly by its facets. The planner bounds the effector's acceleration by it: the cables must
// exert m (a - g), so each facet is a linear inequality in the acceleration (docs/motion.md,
// "Tension-limited acceleration"). Model-independent: the caller gives the structure matrix and
// the limits (tension_distribution.hpp). Fixed capacity, allocation-free.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>

#include "pkm/kinematics/tension_distribution.hpp"

namespace pkm::kinematics {

// At most one facet normal per pair of cables (spatial; one per cable in the plane).
inline constexpr int kMaxForceFacets = kMaxCables * (kMaxCables - 1) / 2;

// A pair of opposite facets: low_N <= normal . F <= high_N. The normal (a unit vector, machine x
// y z; z 0 for a planar robot) is perpendicular to the facet's own cables (first and second;
// second -1 in the plane); on the high side the cables with normal . w > 0 sit at their max and
// those with normal . w < 0 at their min (the low side the other way round), the facet's own
// cables anywhere within their limits. -inf or +inf where a cable without a max pulls along it.
struct ForceFacet {
  Eigen::Vector3d normal;
  double low_N, high_N;
  int first_cable, second_cable;
  // Cables pulling along the normal (bit i: cable i) and against it, the facet's own excluded.
  std::uint32_t along, against;
};

struct CableForcePolytope {
  std::array<ForceFacet, kMaxForceFacets> facets;  // the first `count`
  int count = 0;
  int dimensions = 0;  // 2 planar, 3 spatial

  // How far `force_N` (x y z; z ignored in the plane) is inside every facet (N, negative outside),
  // and the facet and side (high: past high_N) nearest to or furthest beyond its bound.
  double margin_N(const Eigen::Vector3d& force_N, int& facet, bool& high) const;
};

// The facets of A t over the box [targets.min_N, targets.max_N] for A of 2 or 3 rows (columns:
// the cables' unit directions): in the plane a normal perpendicular to each cable, in space one
// perpendicular to each pair of cables not parallel (within 1e-9 rad), with the support
// normal . c + sum_k h_k |normal . w_k| written as its sum over the box's corners. False where
// the cables do not span the plane (space) the effector moves in: then no force holds it every
// way, and the facets do not describe the set. The targets' preferred tensions are not used.
bool cable_force_polytope(const StructureMatrix& structure, const TensionTargets& targets,
                          CableForcePolytope& polytope);

}  // namespace pkm::kinematics
