// Where a hanging cable machine (a cable_plotter whose effector has a mass) can hold its effector
// with both cables' static tensions within their limits: a grid over the frame between the
// anchors, from the anchors down to the bottom of the reach, each point the joints reach (their
// limits and the work envelope, the tensions aside) classified by its tensions at rest. What
// `pkm check` reports for such a machine.
#pragma once

#include <Eigen/Core>
#include <array>
#include <optional>

#include "pkm/machine/machine.hpp"

namespace pkm::machine {

// Points of the grid where something holds, and the box (mm, x y) they span.
struct GridRegion {
  int points = 0;
  Eigen::Vector2d min_mm = Eigen::Vector2d::Constant(1e300);
  Eigen::Vector2d max_mm = Eigen::Vector2d::Constant(-1e300);
  void add(const Eigen::Vector2d& at_mm);
};

struct TensionRegion {
  int columns = 0, rows = 0;
  Eigen::Vector2d min_mm = Eigen::Vector2d::Zero();  // the grid's box (points at cell centres)
  Eigen::Vector2d max_mm = Eigen::Vector2d::Zero();
  GridRegion reached;  // the joints reach the point (tensions aside): the rest count from these
  GridRegion within;   // and both tensions are within their limits at rest
  std::array<GridRegion, 2> slack;     // cable 0 (left), 1 (right): below tension_min_N, or
                                       // it would have to push
  std::array<GridRegion, 2> over_max;  // above tension_max_N
  // The extreme tensions over the points reached, where (mm) and on which cable.
  double lowest_N = 1e300, highest_N = -1e300;
  Eigen::Vector2d lowest_at_mm = Eigen::Vector2d::Zero(), highest_at_mm = Eigen::Vector2d::Zero();
  int lowest_cable = -1, highest_cable = -1;
};

// The region of a cable_plotter machine whose effector has a mass, over `columns` x `rows`
// points between the anchors (x) and from the anchors down to the bottom of the reach along the
// vertical through home (y); none for any other machine.
std::optional<TensionRegion> tension_region(const Machine& machine, int columns = 60,
                                            int rows = 40);

}  // namespace pkm::machine
