// The largest axis-aligned box and the largest cylinder about z inside the proven-inside cells
// of a workspace, searched on a raster of at most ~96 voxels a side whose voxels count only when
// inside cells cover them whole, so both shapes are inside the proven workspace.
#pragma once

#include <optional>

#include "pkm/workspace/workspace.hpp"

namespace pkm::workspace {

struct InscribedShapes {
  std::optional<Eigen::AlignedBox3d> box;  // of the largest volume (area when planar)
  std::optional<Cylinder> cylinder;        // of the largest volume (a disk when planar)
};

InscribedShapes largest_inscribed(const Workspace& ws);

}  // namespace pkm::workspace
