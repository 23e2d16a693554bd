// The reachable workspace of a machine: the positions where Machine::inverse accepts every
// orientation of a range, found by adaptive (octree) refinement of cells whose answers are
// proven from bounds on the constraints over the whole cell (pose_constraints.hpp), down to a
// guaranteed resolution; its volume as bounds, extent, largest box and cylinder about z, maps of
// dexterity and joint speed, and what limited it. docs/workspace.md says what each answer means.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "pkm/machine/machine.hpp"

namespace pkm::workspace {

struct WorkspaceOptions {
  double resolution_mm = 1.0;  // the largest side of an undecided cell
  // Orientation range (rad, a b c), for the coordinates the model controls; the others ignored.
  Eigen::Vector3d orientation_min_rad = Eigen::Vector3d::Zero();
  Eigen::Vector3d orientation_max_rad = Eigen::Vector3d::Zero();
  int threads = 2;
  // Refuses a run estimated (estimate_cells) or found to judge more cells than this: a resolution
  // too fine for the machine. The default holds the paper's hexapod at 1 mm over +-10 deg
  // (1.3e8 cells, 2.1 GB; docs/workspace.md).
  std::int64_t max_cells = 200'000'000;
  int map_points = 120;  // along the longer side of each map
};

// The orientation range of `machine` with no --orientation: home's orientation, fixed.
WorkspaceOptions default_options(const machine::Machine& machine);

// A cell of the octree: indices on the finest grid (steps of resolution from the origin) and
// its level, its side 2^level steps; it covers [i, i + 2^level) on each axis.
struct CellIndex {
  std::array<std::int32_t, 3> at{};
  std::int32_t level = 0;
};

struct Cylinder {
  Eigen::Vector2d centre_mm = Eigen::Vector2d::Zero();
  double radius_mm = 0.0;
  double z0_mm = 0.0, z1_mm = 0.0;
};

// A map over a plane z = at_mm (or the plane of a planar machine): values at grid points,
// row-major (x fastest), NaN where the machine cannot stand.
struct PlaneMap {
  std::string name;
  double at_mm = 0.0;
  Eigen::Vector2d origin_mm = Eigen::Vector2d::Zero();
  double step_mm = 0.0;
  std::array<int, 2> dims{};
  std::vector<double> values;
};

struct Workspace {
  std::string machine;
  bool planar = false;     // the model moves x and y only: areas, not volumes
  bool guaranteed = true;  // false where a constraint was sampled, not bounded (see notes)
  std::vector<std::string> notes;
  double resolution_mm = 0.0;
  Eigen::Vector3d orientation_min_rad = Eigen::Vector3d::Zero();
  Eigen::Vector3d orientation_max_rad = Eigen::Vector3d::Zero();
  std::array<bool, 3> position_axes{};                  // which of x y z the cells span
  Eigen::Vector3d origin_mm = Eigen::Vector3d::Zero();  // corner of cell (0, 0, 0)
  std::array<int, 3> dims{};                            // finest cells per axis (1 where fixed)
  std::vector<CellIndex> inside, boundary;
  double inside_measure = 0.0;  // mm^3, or mm^2 when planar
  double boundary_measure = 0.0;
  std::int64_t cells_judged = 0;  // position cells
  std::int64_t boxes_judged = 0;  // cells of poses (a position cell by an orientation box)
  // Cells the bounds proved inside whose middle Machine::inverse refused: a limit of the
  // machine without a bound here (then guaranteed is false).
  std::int64_t unbounded_refusals = 0;
  // inside + the boundary cells whose centre the machine reaches at the range's middle and
  // corners: an estimate, not a bound (the Monte-Carlo test holds it to 1 %).
  double estimate = 0.0;
  std::map<std::string, std::int64_t> limited_by;  // status name: outside and boundary cells
  // Boxes of positions (mm): the extent of every cell not proven outside, the largest box
  // inside proven-inside cells.
  std::optional<Eigen::AlignedBox3d> extent, largest_box;
  std::optional<Cylinder> largest_cylinder;
  std::vector<PlaneMap> maps;
};

// What a run will cost, before it runs: from runs at power-of-two multiples of the resolution,
// from the coarsest with at most kEstimateSteps cells along the search box's longest side to the
// first that judges kEstimateRunCells, the last one's counts times 2^(d - 1) per halving (the
// cells the octree judges and lists lie along the boundary, a surface of d - 1 dimensions).
struct CellEstimate {
  double judged = 0.0;              // position cells judged
  double listed = 0.0;              // inside and boundary cells kept
  double bytes = 0.0;               // the lists' peak memory (each part's and the merged ones)
  double from_resolution_mm = 0.0;  // of the run it scales (the resolution itself: exact)
  int growth = 1;                   // the factor per halving, 2^(d - 1)
  std::int64_t run_judged = 0;      // by that run
};
constexpr int kEstimateSteps = 64;
constexpr std::int64_t kEstimateRunCells = 10'000;
CellEstimate estimate_cells(const machine::Machine& machine, const WorkspaceOptions& options);

// A run whose estimate passes options.max_cells, refused before its cells are allocated.
class CellBoundError : public std::invalid_argument {
 public:
  CellBoundError(const std::string& message, const CellEstimate& estimated, double fitting_mm)
      : std::invalid_argument(message), estimate(estimated), fitting_resolution_mm(fitting_mm) {}
  CellEstimate estimate;
  double fitting_resolution_mm;  // the finest that fits, rounded up; 0 where none does
};

// Throws std::invalid_argument for a resolution that is not positive, an empty orientation
// range, or one whose cell count passes options.max_cells (CellBoundError where the estimate
// does, before any work at the resolution).
Workspace compute_workspace(const machine::Machine& machine, const WorkspaceOptions& options);

// The box of position coordinates (mm) that holds every pose the machine can reach: from its
// geometry (joint limits, struts, cables), cut by the work envelope. `proven` false where it
// comes from the extent through home only (models without such a box here).
struct SearchBox {
  Eigen::AlignedBox3d box;
  bool proven = true;
};
SearchBox search_box(const machine::Machine& machine, const WorkspaceOptions& options);

}  // namespace pkm::workspace
