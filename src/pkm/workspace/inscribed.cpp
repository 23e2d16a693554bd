// Largest box and cylinder inside the proven workspace (inscribed.hpp).
#include "pkm/workspace/inscribed.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

namespace pkm::workspace {

namespace {

constexpr int kMaxVoxels = 96;  // a side: the searches below cost about n^4

// Voxels of 2^shift finest steps; full[x + nx (y + ny z)] when inside cells cover it whole.
struct Raster {
  int shift = 0;
  std::array<int, 3> n{1, 1, 1};
  std::vector<char> full;
  double side_mm = 0.0;
  int at(int x, int y, int z) const { return x + n[0] * (y + n[1] * z); }
};

Raster rasterise(const Workspace& ws) {
  Raster raster;
  int dimensions = 0;
  for (int axis = 0; axis < 3; ++axis) {
    const auto a = static_cast<std::size_t>(axis);
    if (!ws.position_axes[a]) continue;
    ++dimensions;
    while ((ws.dims[a] >> raster.shift) > kMaxVoxels) ++raster.shift;
  }
  for (int axis = 0; axis < 3; ++axis) {
    const auto a = static_cast<std::size_t>(axis);
    raster.n[a] = ws.position_axes[a] ? (ws.dims[a] + (1 << raster.shift) - 1) >> raster.shift : 1;
  }
  raster.side_mm = ws.resolution_mm * std::ldexp(1.0, raster.shift);
  std::vector<std::int64_t> covered(
      static_cast<std::size_t>(raster.n[0] * raster.n[1] * raster.n[2]), 0);
  const std::int64_t whole = std::int64_t{1} << (raster.shift * dimensions);
  for (const CellIndex& cell : ws.inside) {
    std::array<int, 3> lo{}, hi{};
    std::int64_t each = 0;
    if (cell.level >= raster.shift) {
      for (std::size_t a = 0; a < 3; ++a) {
        lo[a] = ws.position_axes[a] ? cell.at[a] >> raster.shift : 0;
        hi[a] = ws.position_axes[a] ? lo[a] + (1 << (cell.level - raster.shift)) : 1;
      }
      each = whole;
    } else {
      for (std::size_t a = 0; a < 3; ++a) {
        lo[a] = ws.position_axes[a] ? cell.at[a] >> raster.shift : 0;
        hi[a] = lo[a] + 1;
      }
      each = std::int64_t{1} << (cell.level * dimensions);
    }
    for (int z = lo[2]; z < std::min(hi[2], raster.n[2]); ++z) {
      for (int y = lo[1]; y < std::min(hi[1], raster.n[1]); ++y) {
        for (int x = lo[0]; x < std::min(hi[0], raster.n[0]); ++x) {
          covered[static_cast<std::size_t>(raster.at(x, y, z))] += each;
        }
      }
    }
  }
  raster.full.resize(covered.size());
  for (std::size_t k = 0; k < covered.size(); ++k) raster.full[k] = covered[k] >= whole ? 1 : 0;
  return raster;
}

struct Rectangle {
  int area = 0;
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;  // voxels [x0, x1) x [y0, y1)
};

// The largest rectangle of set cells in an nx x ny mask: a histogram of runs per row, and the
// largest rectangle under each histogram with a stack.
Rectangle largest_rectangle(const std::vector<char>& mask, int nx, int ny) {
  Rectangle best;
  std::vector<int> height(static_cast<std::size_t>(nx), 0);
  std::vector<int> stack;
  for (int y = 0; y < ny; ++y) {
    for (int x = 0; x < nx; ++x) {
      auto& h = height[static_cast<std::size_t>(x)];
      h = mask[static_cast<std::size_t>(x + nx * y)] ? h + 1 : 0;
    }
    stack.clear();
    for (int x = 0; x <= nx; ++x) {
      const int h = x < nx ? height[static_cast<std::size_t>(x)] : 0;
      while (!stack.empty() && height[static_cast<std::size_t>(stack.back())] >= h) {
        const int top = stack.back();
        stack.pop_back();
        const int left = stack.empty() ? 0 : stack.back() + 1;
        const int th = height[static_cast<std::size_t>(top)];
        const int area = th * (x - left);
        if (area > best.area) best = {area, left, y - th + 1, x, y + 1};
      }
      stack.push_back(x);
    }
  }
  return best;
}

// Squared distance transform in one dimension (Felzenszwalb and Huttenlocher's lower envelope
// of parabolas): d[q] = min_p (q - p)^2 + f[p].
void distance_1d(const std::vector<double>& f, std::vector<double>& d, std::vector<int>& v,
                 std::vector<double>& z) {
  const int n = static_cast<int>(f.size());
  int k = 0;
  v[0] = 0;
  z[0] = -INFINITY;
  z[1] = INFINITY;
  for (int q = 1; q < n; ++q) {
    const auto fq = f[static_cast<std::size_t>(q)];
    double s = 0.0;
    while (true) {
      const int p = v[static_cast<std::size_t>(k)];
      s = ((fq + q * q) - (f[static_cast<std::size_t>(p)] + p * p)) / (2.0 * (q - p));
      if (s > z[static_cast<std::size_t>(k)] || k == 0) break;
      --k;
    }
    if (s <= z[static_cast<std::size_t>(k)]) s = z[static_cast<std::size_t>(k)];
    ++k;
    v[static_cast<std::size_t>(k)] = q;
    z[static_cast<std::size_t>(k)] = s;
    z[static_cast<std::size_t>(k + 1)] = INFINITY;
  }
  k = 0;
  for (int q = 0; q < n; ++q) {
    while (z[static_cast<std::size_t>(k + 1)] < q) ++k;
    const int p = v[static_cast<std::size_t>(k)];
    d[static_cast<std::size_t>(q)] = (q - p) * (q - p) + f[static_cast<std::size_t>(p)];
  }
}

struct Disk {
  double radius = 0.0;  // voxels
  int x = 0, y = 0;
};

// The largest disk about a voxel centre that meets no voxel outside the mask (nor the raster's
// edge): the distance to the nearest blocked centre, less half a voxel's diagonal.
Disk largest_disk(const std::vector<char>& mask, int nx, int ny) {
  const int wx = nx + 2, wy = ny + 2;
  std::vector<double> grid(static_cast<std::size_t>(wx * wy), 0.0);
  for (int y = 0; y < ny; ++y) {
    for (int x = 0; x < nx; ++x) {
      grid[static_cast<std::size_t>((x + 1) + wx * (y + 1))] =
          mask[static_cast<std::size_t>(x + nx * y)] ? 1e18 : 0.0;
    }
  }
  const int n = std::max(wx, wy);
  std::vector<double> f, d(static_cast<std::size_t>(n)), z(static_cast<std::size_t>(n + 1));
  std::vector<int> v(static_cast<std::size_t>(n));
  for (int x = 0; x < wx; ++x) {
    f.assign(static_cast<std::size_t>(wy), 0.0);
    for (int y = 0; y < wy; ++y)
      f[static_cast<std::size_t>(y)] = grid[static_cast<std::size_t>(x + wx * y)];
    distance_1d(f, d, v, z);
    for (int y = 0; y < wy; ++y)
      grid[static_cast<std::size_t>(x + wx * y)] = d[static_cast<std::size_t>(y)];
  }
  Disk best;
  for (int y = 0; y < wy; ++y) {
    f.assign(grid.begin() + wx * y, grid.begin() + wx * (y + 1));
    distance_1d(f, d, v, z);
    for (int x = 0; x < wx; ++x) {
      const double radius = std::sqrt(d[static_cast<std::size_t>(x)]) - 0.5 * std::sqrt(2.0);
      if (radius > best.radius) best = {radius, x - 1, y - 1};
    }
  }
  return best;
}

}  // namespace

InscribedShapes largest_inscribed(const Workspace& ws) {
  InscribedShapes shapes;
  if (ws.inside.empty()) return shapes;
  const Raster raster = rasterise(ws);
  const int nx = raster.n[0], ny = raster.n[1], nz = raster.n[2];
  const std::size_t layer = static_cast<std::size_t>(nx * ny);
  double best_box = 0.0, best_cylinder = 0.0;
  std::vector<char> mask(layer);
  const double side = raster.side_mm;
  const auto corner = [&](int axis, int voxel) {
    return ws.origin_mm[axis] +
           (ws.position_axes[static_cast<std::size_t>(axis)] ? voxel * side : 0.0);
  };
  for (int z0 = 0; z0 < nz; ++z0) {
    std::copy(raster.full.begin() + static_cast<std::ptrdiff_t>(layer * z0),
              raster.full.begin() + static_cast<std::ptrdiff_t>(layer * (z0 + 1)), mask.begin());
    for (int z1 = z0; z1 < nz; ++z1) {
      if (z1 > z0) {
        bool any = false;
        for (std::size_t k = 0; k < layer; ++k) {
          mask[k] = mask[k] && raster.full[layer * static_cast<std::size_t>(z1) + k];
          any = any || mask[k];
        }
        if (!any) break;
      }
      const int height = z1 - z0 + 1;
      const Rectangle rectangle = largest_rectangle(mask, nx, ny);
      if (rectangle.area > 0 && rectangle.area * static_cast<double>(height) > best_box) {
        best_box = rectangle.area * static_cast<double>(height);
        shapes.box = Eigen::AlignedBox3d(
            Eigen::Vector3d(corner(0, rectangle.x0), corner(1, rectangle.y0), corner(2, z0)),
            Eigen::Vector3d(corner(0, rectangle.x1), corner(1, rectangle.y1), corner(2, z1 + 1)));
      }
      const Disk disk = largest_disk(mask, nx, ny);
      const double volume = disk.radius * disk.radius * height;
      if (disk.radius > 0.0 && volume > best_cylinder) {
        best_cylinder = volume;
        Cylinder cylinder;
        cylinder.centre_mm = {corner(0, disk.x) + 0.5 * side, corner(1, disk.y) + 0.5 * side};
        cylinder.radius_mm = disk.radius * side;
        cylinder.z0_mm = corner(2, z0);
        cylinder.z1_mm = corner(2, z1 + 1);
        shapes.cylinder = cylinder;
      }
    }
  }
  return shapes;
}

}  // namespace pkm::workspace
